"""The module's own behaviour: matrices, scene edits by the scene's rules, errors naming the
argument, numpy arrays, progress callbacks, cancellation, the GIL released."""

import _thread
import math
import os
import re
import threading

import numpy as np
import pytest

import prbfit
from conftest import REPO

STEEL = REPO / "assets" / "scenes" / "steel-flexure.toml"


def test_errors_are_one_family():
    assert issubclass(prbfit.InputError, prbfit.Error)
    assert issubclass(prbfit.SolveError, prbfit.Error)
    assert not issubclass(prbfit.InputError, prbfit.SolveError)


def test_matrix_text_numpy_topology_and_fixed_cells():
    m = prbfit.Matrix.parse("0.1,inf,inf; 0.9!,2.2,inf")
    a = m.to_numpy()
    # Always (N, 4): a matrix written with three columns has mu = gamma (has_mu False).
    assert a.shape == (2, 4) and a.dtype == np.float64
    assert a[0, 0] == 0.1 and math.isinf(a[0, 1]) and a[1, 1] == 2.2
    assert a[:, 3].tolist() == a[:, 0].tolist() and not m.has_mu
    assert m.topology == "L-R"
    assert m.fixed.tolist() == [[False] * 4, [True, False, False, False]]
    assert prbfit.Matrix(a[:, :3]) == prbfit.Matrix.parse("0.1,inf,inf; 0.9,2.2,inf")
    assert prbfit.Matrix(a[:, :3], fixed=m.fixed[:, :3].tolist()) == m
    assert prbfit.Matrix.parse(m.text) == m
    assert prbfit.Matrix.from_topology("L-R-R-R").topology == "L-R-R-R"
    assert len(prbfit.Matrix.from_topology("3R")) == 4


def test_a_float32_array_is_read_as_its_entries_print():
    # 0.1, 0.35, 0.4, 0.15 in float32 sum to 1 + 7.5e-9 as float64: past the gamma rule's
    # 1e-9, they were refused. They are read as the decimals numpy prints.
    su = "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf"
    rows = np.array([[0.1, np.inf, np.inf], [0.35, 3.51, np.inf], [0.4, 2.99, np.inf],
                     [0.15, 2.58, np.inf]], dtype=np.float32)
    assert abs(rows[:, 0].astype(np.float64).sum() - 1.0) > 1e-9
    assert prbfit.Matrix(rows) == prbfit.Matrix.parse(su)
    sc = prbfit.Scene.builtin()
    sc.matrix = rows
    assert sc.matrix == prbfit.Matrix.parse(su)
    # What is off in float32 is still refused, by the rule's own message.
    rows[0, 0] = 0.2
    with pytest.raises(prbfit.InputError, match="gammas must sum to 1"):
        prbfit.Matrix(rows)


def test_matrix_mu_column_is_kept_where_given():
    m = prbfit.Matrix.parse("0.1,inf,inf,0.3; 0.9,2.2,inf,0.7!")
    assert m.has_mu and m.text == "0.1,inf,inf,0.3; 0.9,2.2,inf,0.7!"
    a = m.to_numpy()
    assert a.shape == (2, 4) and a[:, 3].tolist() == [0.3, 0.7]
    assert m.fixed.tolist() == [[False] * 4, [False, False, False, True]]
    # (N, 4) numpy and four-entry lists give the mus; the fourth column round-trips.
    assert prbfit.Matrix(a, fixed=m.fixed.tolist()) == m
    assert prbfit.Matrix(a.tolist()).has_mu
    # A three-column matrix's numpy form given back has its mus written out: the same
    # masses now (mu = gamma), kept apart from the gammas from then on.
    three = prbfit.Matrix.parse("0.1,inf,inf; 0.9,2.2,inf")
    back = prbfit.Matrix(three.to_numpy())
    assert back.has_mu and back.text == "0.1,inf,inf,0.1; 0.9,2.2,inf,0.9"
    sc = prbfit.Scene.builtin()
    sc.matrix = a
    assert sc.matrix == prbfit.Matrix(a) and "0.3" in sc.to_toml()


@pytest.mark.parametrize(
    "rows, words",
    [
        ([[0.1, 1.0]], ["rows", "row 1", "3 entries", "4 (gamma, k_theta, k_ex, mu)"]),
        ([[0.5, float("nan"), math.inf], [0.5, 2, math.inf]], ["rows", "row 1", "k_theta", "NaN"]),
        ([[0.5, 1, math.inf, float("nan")], [0.5, 2, math.inf, 0.5]], ["rows", "row 1", "mu", "NaN"]),
        ([[0.5, 1, math.inf, 0.5], [0.5, 2, math.inf]], ["rows", "row 2", "every row gives a mu"]),
        ([[0.5, 1, math.inf, 0.5], [0.5, 2, math.inf, 0.6]], ["rows", "mus must sum to 1"]),
        ([[0.5, 1, math.inf, -0.5], [0.5, 2, math.inf, 1.5]], ["rows", "row 1", "mu", ">= 0"]),
        ("oops", ["rows", "oops"]),
        (3.5, ["rows", "expected"]),
        (np.zeros((2, 5)), ["rows", "shape (N, 3)", "(N, 4)", "got shape (2, 5)"]),
        (np.zeros(3), ["rows", "got shape (3)"]),
        (np.zeros((2, 3, 1)), ["rows", "got shape (2, 3, 1)"]),
        (np.array([[0.5, np.nan, np.inf], [0.5, 2, np.inf]]), ["rows", "row 1", "k_theta", "NaN"]),
        (np.array([[0.5, 1, np.inf, 0.5], [0.5, 2, np.inf, np.nan]]), ["rows", "row 2", "mu", "NaN"]),
        # Complex numbers were cut to their real part with only numpy's warning.
        (np.array([[0.1 + 3j, np.inf, np.inf], [0.9, 2.2, np.inf]]), ["rows", "real numbers", "complex128"]),
        (np.array([[1, 2, 3], [4, 5, 6]], dtype="timedelta64[s]"), ["rows", "real numbers", "timedelta64"]),
    ],
)
def test_bad_matrices_are_input_errors_naming_the_argument(rows, words):
    with pytest.raises(prbfit.InputError) as e:
        prbfit.Matrix(rows)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


def test_matrix_parse_of_four_columns_and_its_errors():
    m = prbfit.Matrix.parse("0.15,inf,inf,0.2; 0.85,2.2525,inf,0.8")
    assert m.to_numpy()[:, 3].tolist() == [0.2, 0.8]
    for text, words in [
        ("0.5,inf,inf,0.5; 0.5,2,inf", ["text", "every row gives a mu"]),
        ("0.5,inf,inf,0.5; 0.5,2,inf,x", ["text", "column mu"]),
        ("0.5,inf,inf,0.5,1; 0.5,2,inf,0.5", ["text", "got 5"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            prbfit.Matrix.parse(text)
        for w in words:
            assert w in str(e.value), (w, str(e.value))


def test_integer_and_fixed_arrays():
    m = prbfit.Matrix(np.array([[1, 2, np.inf]]))  # an integer gamma is a number too
    assert m.to_numpy().tolist() == [[1.0, 2.0, math.inf, 1.0]]
    with pytest.raises(prbfit.InputError) as e:
        prbfit.Matrix([[0.5, 1, math.inf], [0.5, 2, math.inf]], fixed=[[True] * 3, [True] * 4])
    assert "fixed" in str(e.value) and "row 2" in str(e.value)


def test_fixed_cells_over_a_text_form_or_a_matrix():
    # `fixed` says which cells stay, whatever the text's own `!` marks said.
    flags = [[False] * 3, [True, False, False]]
    want = prbfit.Matrix.parse("0.1,inf,inf; 0.9!,2.2,inf")
    assert prbfit.Matrix("0.1,inf,inf; 0.9,2.2,inf", fixed=flags) == want
    assert prbfit.Matrix("0.1!,inf,inf; 0.9,2.2,inf", fixed=flags) == want
    assert prbfit.Matrix(prbfit.Matrix.parse("0.1,inf,inf; 0.9,2.2,inf"), fixed=flags) == want
    mu = prbfit.Matrix("0.1,inf,inf,0.3; 0.9,2.2,inf,0.7", fixed=[[False] * 4, [False] * 3 + [True]])
    assert mu == prbfit.Matrix.parse("0.1,inf,inf,0.3; 0.9,2.2,inf,0.7!")
    for bad, words in [([[False] * 3], ["fixed", "1 rows for a matrix of 2"]),
                       ([[False] * 3, [False] * 4], ["fixed", "row 2", "4 flags", "3 entries"])]:
        with pytest.raises(prbfit.InputError) as e:
            prbfit.Matrix("0.1,inf,inf; 0.9,2.2,inf", fixed=bad)
        for w in words:
            assert w in str(e.value), (w, str(e.value))


def test_scene_constructors_and_their_errors(tmp_path):
    assert prbfit.Scene.builtin().kind == "cantilever"
    sc = prbfit.Scene.load(STEEL)
    assert prbfit.Scene.from_toml(sc.to_toml()).beam == sc.beam
    with pytest.raises(prbfit.InputError) as e:
        prbfit.Scene.load(tmp_path / "missing.toml")
    assert "missing.toml" in str(e.value)
    with pytest.raises(prbfit.InputError) as e:
        prbfit.Scene.from_toml("[beam]\nlength = -1\n", "bad.toml")
    assert "bad.toml" in str(e.value)
    assert prbfit.Scene.load(REPO / "assets/scenes/parallel-stage.toml").kind == "mechanism"
    assert prbfit.Scene.load(REPO / "assets/scenes/slider-crank-rig.toml").kind == "mechanism data"


def test_beam_edits_follow_the_rules_and_leave_the_scene_when_refused():
    sc = prbfit.Scene.load(STEEL)
    t = sc.beam["thickness"]
    thin = sc.with_beam(thickness=t / 2)
    assert thin.beam["slenderness"] == pytest.approx(2 * sc.beam["slenderness"])
    assert sc.beam["thickness"] == t  # with_beam copies
    sc.set_beam(youngs_modulus=100e9, effects="none")
    assert sc.beam["youngs_modulus"] == 100e9 and sc.beam["effects"] == "none"
    for bad, words in [
        ({"thickness": -1.0}, ["beam.thickness"]),
        ({"thickness": float("nan")}, ["beam.thickness", "finite"]),
        ({"thickness": "thick"}, ["beam.thickness", "number"]),
        ({"colour": 1.0}, ["beam.colour"]),
        ({"effects": "magic"}, ["beam.effects"]),
    ]:
        before = sc.beam
        with pytest.raises(prbfit.InputError) as e:
            sc.set_beam(**bad)
        for w in words:
            assert w in str(e.value)
        assert sc.beam == before


def test_a_data_scene_edit_that_puts_its_rows_out_of_reach_is_refused():
    d = prbfit.Scene.load(REPO / "assets" / "scenes" / "wide-strip-fea.toml")
    before = d.to_toml()
    with pytest.raises(prbfit.InputError) as e:
        d.set_beam(youngs_modulus=1e-3)
    assert "truth.data" in str(e.value) and "beyond the 1e9" in str(e.value), str(e.value)
    assert d.to_toml() == before


def test_a_complex_load_is_refused():
    sc = prbfit.Scene.load(STEEL)
    for load in [np.array([0, 1 + 5j, 0]), [0, np.complex128(1 + 5j), 0]]:
        with pytest.raises(prbfit.InputError) as e:
            sc.solve(load=load)
        assert "load" in str(e.value) and "real numbers" in str(e.value), str(e.value)


def test_dynamics_edits_follow_the_rules():
    sc = prbfit.Scene.load(STEEL)
    assert sc.beam["density"] is None
    assert sc.body == {"mass": 0.0, "inertia": 0.0}
    assert sc.fit_settings["modes"] == 0 and sc.accuracy["max_freq_err"] == 0.01
    sc.set_beam(density=7850.0, allowable_stress=1.2e9)
    assert sc.beam["allowable_stress"] == 1.2e9
    sc.set_body(mass=0.002, inertia=1e-8)
    sc.set_fit_settings(modes=2, frequency_weight=0.5)
    sc.set_accuracy(max_freq_err=0.02)
    assert sc.beam["density"] == 7850.0 and sc.body == {"mass": 0.002, "inertia": 1e-8}
    assert sc.fit_settings["modes"] == 2 and sc.fit_settings["frequency_weight"] == 0.5
    # The edits are the scene's: written to its TOML and read back the same.
    back = prbfit.Scene.from_toml(sc.to_toml())
    assert (back.beam, back.body, back.fit_settings, back.accuracy) == (
        sc.beam, sc.body, sc.fit_settings, sc.accuracy)
    for call, words in [
        (lambda: sc.set_beam(density=-1.0), ["beam.density"]),
        (lambda: sc.set_beam(density=float("nan")), ["beam.density", "finite"]),
        (lambda: sc.set_beam(allowable_stress=0.0), ["beam.allowable_stress"]),
        (lambda: sc.set_body(mass=-0.1), ["tip.mass"]),
        (lambda: sc.set_body(inertia="x"), ["tip.inertia", "number"]),
        (lambda: sc.set_body(volume=1.0), ["tip.volume", "mass, inertia"]),
        (lambda: sc.set_fit_settings(modes=-1), ["fit.modes", "whole number"]),
        (lambda: sc.set_fit_settings(modes=1.5), ["fit.modes", "whole number"]),
        (lambda: sc.set_fit_settings(frequency_weight=-1.0), ["fit.frequency_weight"]),
        # A weight near the largest double made J infinite, handed out as None.
        (lambda: sc.set_fit_settings(angle_weight=1e308), ["fit.angle_weight", "at most 1e9"]),
        (lambda: sc.set_accuracy(max_freq_err=0.0), ["accuracy.max_freq_err"]),
        (lambda: sc.set_accuracy(max_speed=1.0), ["accuracy.max_speed"]),
    ]:
        before = (sc.beam, sc.body, sc.fit_settings, sc.accuracy)
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))
        assert (sc.beam, sc.body, sc.fit_settings, sc.accuracy) == before
    # The scene's own rule across tables: a dynamic fit needs the density.
    with pytest.raises(prbfit.InputError) as e:
        sc.set_beam(density=None)
    assert "fit.modes" in str(e.value) and sc.beam["density"] == 7850.0
    sc.set_fit_settings(modes=0)
    sc.set_beam(density=None)
    assert sc.beam["density"] is None
    mech = prbfit.Scene.load(REPO / "assets/scenes/parallel-stage.toml")
    with pytest.raises(prbfit.InputError) as e:
        mech.set_body(mass=-1.0)
    assert "stage.mass" in str(e.value)


def test_modes_frequencies_are_numpy_arrays():
    sc = prbfit.Scene.load(REPO / "assets/scenes/ringing-flexure.toml")
    r = sc.modes("su-3r", "howell-1r", count=3)
    d = r.to_dict()
    assert r.beam_omega.shape == r.beam_hz.shape == (3,)
    assert r.beam_omega.tolist() == d["beam"]["omega"] and r.beam_hz.tolist() == d["beam"]["hz"]
    assert len(r.omega) == len(r.hz) == len(r.freq_err) == 2
    assert r.omega[0].tolist() == d["models"][0]["omega"]
    # Howell's 1R has one frequency: the others are NaN.
    assert r.hz[1][0] == d["models"][1]["hz"][0] and np.isnan(r.hz[1][1:]).all()
    assert r.freq_err[0].tolist() == d["models"][0]["freq_err"]
    assert r.loads.tolist() == [[0.0, 0.0, 0.0]] and r.density == 7850.0
    c = sc.modes("su-3r", count=2, cases=True)
    n = len(c.to_dict()["cases"])
    assert c.beam_omega.shape == c.omega[0].shape == (n, 2) and c.loads.shape == (n, 3)
    assert c.beam_hz[-1].tolist() == c.to_dict()["cases"][-1]["beam"]["hz"]
    one = sc.modes(prbfit.Matrix.parse("0.15,inf,inf,0.5; 0.85,2.2525,inf,0.5"), count=1, load=(-2, 0, 0))
    assert one.equilibrium == "load" and one.omega[0].shape == (1,)
    # The beam alone when the scene has no model and none is given.
    assert sc.modes(count=1).omega == []


def test_modes_arguments_are_checked_naming_them():
    sc = prbfit.Scene.load(REPO / "assets/scenes/ringing-flexure.toml")
    mech = prbfit.Scene.load(REPO / "assets/scenes/parallel-stage.toml").with_beam(density=7850.0)
    for call, words in [
        (lambda: sc.modes(count=0), ["count: 0", "from 1"]),
        (lambda: sc.modes(count=-2), ["count: -2", "from 1"]),
        # PyO3's own conversion raised an OverflowError naming nothing.
        (lambda: sc.modes(count=10**30), ["count: ", "31 digits", "from 1"]),
        (lambda: sc.modes(count="3"), ["count", "whole number, got str"]),
        (lambda: sc.modes(load=(0, 1, 0), cases=True), ["--load and --cases"]),
        (lambda: sc.modes(load=(0, float("nan"), 0)), ["load", "finite"]),
        # The CLI's --load limit: refused at once, not followed for seconds to a late failure.
        (lambda: sc.modes(load=(0, 1e308, 0)), ["load", "alpha_y", "beyond the 1e9"]),
        (lambda: sc.solve(load=(-1e10, 0, 0)), ["load", "alpha_x", "beyond the 1e9"]),
        (lambda: sc.modes([[1.0]]), ["models[0]"]),
        (lambda: mech.modes(load=(0, 1, 0)), ["--load"]),
        (lambda: prbfit.Scene.load(STEEL).modes(), ["beam.density", "density = 7850.0"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))


def test_load_paths_and_matrix_edits():
    sc = prbfit.Scene.builtin()
    sc.loads = [(0, 1.0, 0, 4), (0, 0, 1.0, 3)]
    assert sc.loads == [(0.0, 1.0, 0.0, 4), (0.0, 0.0, 1.0, 3)]
    assert sc.solve().tips.shape == (7, 3)
    for bad, words in [
        ([(0, 1.0, 0)], ["loads[1]"]),
        ([(0, float("nan"), 0, 4)], ["loads[1]", "finite"]),
        ([(0, 1.0, 0, 0)], ["loads[1].steps"]),
        ("x", ["loads"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            sc.loads = bad
        for w in words:
            assert w in str(e.value)
    assert len(sc.loads) == 2
    sc.matrix = "0.15,inf,inf; 0.85,2.2525,inf"
    assert sc.matrix.topology == "L-R"
    sc.matrix = [[0.2, math.inf, math.inf], [0.8, 2.0, math.inf]]
    assert sc.matrix.to_numpy()[1, 1] == 2.0
    with pytest.raises(prbfit.InputError) as e:
        sc.matrix = [[0.2, math.inf, math.inf], [0.9, 2.0, math.inf]]
    assert "matrix" in str(e.value)
    sc.matrix = None
    assert sc.matrix is None


def test_load_paths_from_lists_and_array_rows():
    sc = prbfit.Scene.builtin()
    # Lists, and the rows of a float array (steps 5.0, a whole number), as tuples are.
    sc.loads = [[0, 1.0, 0, 4]]
    assert sc.loads == [(0.0, 1.0, 0.0, 4)]
    sc.loads = np.array([[0.0, 1.0, 0.0, 5.0], [0.0, 0.0, 1.0, 3.0]])
    assert sc.loads == [(0.0, 1.0, 0.0, 5), (0.0, 0.0, 1.0, 3)]
    for bad, words in [
        ([(0, 1.0, 0, 5.5)], ["loads[1].steps: 5.5", "whole number"]),
        ([(0, 1.0, 0, -1)], ["loads[1].steps: -1"]),
        ([(0, 1.0, 0, True)], ["loads[1].steps", "got bool"]),
        ([(0, "x", 0, 4)], ["loads[1].alpha_y", "a number"]),
        ([(0, 1.0, 0, 4, 5)], ["loads[1]", "got 5 items"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            sc.loads = bad
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    assert len(sc.loads) == 2


def test_whole_number_arguments_are_checked_naming_them():
    sc = prbfit.Scene.builtin()
    # Each was an OverflowError or a TypeError from PyO3's conversion, some naming nothing.
    for call, words in [
        (lambda: sc.fea("x.csv", mesh=-1), ["mesh: -1", "from 1 to 4294967295"]),
        (lambda: sc.fea("x.csv", mesh=2**40), ["mesh: 1099511627776"]),
        (lambda: sc.fea("x.csv", timeout=-1), ["timeout: -1"]),
        (lambda: sc.fit("L-R", seed=-1), ["seed: -1", "from 0"]),
        (lambda: sc.fit("L-R", seed=2.5), ["seed: 2.5"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    # The defaults the signatures show.
    assert "seed=1" in prbfit.Scene.fit.__text_signature__
    assert "mesh=40" in prbfit.Scene.fea.__text_signature__


def test_number_keywords_refuse_bools_huge_ints_and_other_types_naming_them():
    sc = prbfit.Scene.builtin()
    # PyO3's own conversion read True as 1.0, raised a bare OverflowError for an int too
    # large for a float, and a TypeError for a string.
    for call, words in [
        (lambda: sc.solve(nu=True), ["nu", "expected a number, got bool"]),
        (lambda: sc.solve(slenderness=np.bool_(True)), ["slenderness", "dtype bool"]),
        (lambda: sc.solve(kappa="0.8"), ["kappa", "expected a number, got str"]),
        (lambda: sc.solve(tol=10**400), ["tol", "100000000000...", "401 digits", "too large"]),
        (lambda: sc.eval(tol=False), ["tol", "got bool"]),
        (lambda: sc.modes(tol=1j), ["tol", "expected a number, got complex"]),
        (lambda: sc.export("su-3r", "x.csv", density=True), ["density", "got bool"]),
        (lambda: sc.fea("x.csv", taper=True), ["taper", "got bool"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    for values, words in [({"angle_weight": True}, ["angle_weight", "got bool"]),
                          ({"modes": True}, ["modes", "whole number, got bool"]),
                          ({"force_weight": 10**400}, ["force_weight", "too large"])]:
        with pytest.raises(prbfit.InputError) as e:
            sc.set_fit_settings(**values)
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    # Numbers of every kind still are numbers.
    one = sc.solve(load=(0, 1, 0), nu=np.float32(0.3), tol=1e-8)
    assert one.tol == 1e-8 and 0 < one.b < 1
    assert sc.solve(load=(0, 1, 0), slenderness=100).b == sc.solve(load=(0, 1, 0)).b


def test_string_path_and_flag_keywords_refuse_other_types_naming_them():
    sc = prbfit.Scene.builtin()
    # Each was PyO3's TypeError ("argument 'effects': 'int' object cannot be converted...").
    for call, words in [
        (lambda: sc.solve(effects=3), ["effects", "expected a string, got int"]),
        (lambda: sc.solve(load=(0, 1, 0), shape=1), ["shape", "expected True or False, got int"]),
        (lambda: sc.modes(cases="yes"), ["cases", "True or False, got str"]),
        (lambda: sc.fit(3), ["topology", "expected a string, got int"]),
        (lambda: sc.fit("L-R", fidelity=1), ["fidelity", "expected a string, got int"]),
        (lambda: sc.fit("L-R", output=3.5), ["output", "expected a path", "got float"]),
        (lambda: sc.fit("L-R", force="no"), ["force", "True or False, got str"]),
        (lambda: sc.select(fidelity=None, within_stroke=0), ["within_stroke", "got int"]),
        (lambda: sc.calibrate(param=2), ["param", "expected a string, got int"]),
        (lambda: sc.export("su-3r", 7), ["output", "expected a path", "got int"]),
        (lambda: sc.export("su-3r", "x.csv", format=1), ["format", "got int"]),
        (lambda: sc.fea(["x.csv"]), ["output", "expected a path", "got list"]),
        (lambda: sc.fea("x.csv", section=2), ["section", "got int"]),
        (lambda: sc.fea("x.csv", deck=1), ["deck", "expected a path"]),
        (lambda: prbfit.Scene.load(5), ["path", "expected a path", "got int"]),
        (lambda: prbfit.Scene.from_toml(b"name = 'x'"), ["text", "got bytes"]),
        (lambda: prbfit.Scene.from_toml("name = 'x'", origin=1), ["origin", "got int"]),
        (lambda: prbfit.Matrix.parse(1.5), ["text", "got float"]),
        (lambda: prbfit.Matrix.from_topology(None), ["name", "give a topology"]),
        (lambda: prbfit.Matrix([[0.5, 3, "inf"], [0.5, 3, "inf"]], fixed=5), ["fixed"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))
    with pytest.raises(prbfit.InputError) as e:
        sc.name = 4
    assert "name: expected a string, got int" in str(e.value)
    # What they take still works: a path object, a numpy bool, the defaults the signatures show.
    assert prbfit.Scene.load(STEEL).name == prbfit.Scene.load(str(STEEL)).name
    assert sc.solve(load=(0, 1, 0), shape=np.bool_(True)).b > 0
    assert "fidelity='normal'" in prbfit.Scene.select.__text_signature__
    assert "shape=False" in prbfit.Scene.solve.__text_signature__
    assert "origin='<string>'" in prbfit.Scene.from_toml.__text_signature__


def test_models_by_path_and_matrix_text_with_a_mistake():
    sc = prbfit.Scene.load(STEEL)
    by_name = sc.eval("su-3r").to_dict()
    by_path = sc.eval(REPO / "assets" / "models" / "su-3r.toml").to_dict()
    assert by_path["prb"] == by_name["prb"] and by_path["objective"] == by_name["objective"]
    # Matrix text with a missing entry: the matrix's own message, not a missing file's.
    with pytest.raises(prbfit.InputError) as e:
        sc.eval("0.1,inf,inf; 0.9,2.2")
    assert "row 2: expected 3 entries" in str(e.value), str(e.value)
    # A published name where a matrix is wanted says so, with the matrix to give.
    with pytest.raises(prbfit.InputError) as e:
        sc.matrix = "su-3r"
    assert "published model's name, not a matrix" in str(e.value), str(e.value)
    assert "0.1,inf,inf; 0.35,3.51,inf" in str(e.value)


def test_a_scene_can_be_edited_while_a_call_runs_on_it():
    # A call runs on the scene as it was when called; an edit meanwhile (another thread, a
    # fit's progress callback) applies to later calls, where it raised "Already borrowed".
    sc = prbfit.Scene.load(STEEL)
    before = sc.solve().to_dict()
    edits = []

    def edit(_):
        if not edits:
            sc.set_beam(thickness=6e-4)
            edits.append(sc.beam["thickness"])

    f = sc.fit("L-R-R", fidelity="draft", progress=edit)
    assert edits == [6e-4]
    # The fit ran on the 0.3 mm beam: its truth is the unedited scene's.
    unedited = prbfit.Scene.load(STEEL).fit("L-R-R", fidelity="draft")
    assert f.to_dict()["prb"] == unedited.to_dict()["prb"]
    assert sc.beam["thickness"] == 6e-4
    assert sc.solve().to_dict()["cases"] != before["cases"]


def test_command_arguments_are_checked_naming_them():
    sc = prbfit.Scene.builtin()
    for call, words in [
        (lambda: sc.solve((0, float("nan"), 0)), ["load", "finite"]),
        (lambda: sc.solve("0,1,0"), ["load"]),
        (lambda: sc.solve(tol=-1.0), ["--tol"]),
        (lambda: sc.fit("L-R", fidelity="sloppy"), ["fidelity"]),
        (lambda: sc.fit("X-Y"), ["--topology"]),
        (lambda: sc.fit("L-R", matrix="0.1,inf,inf; 0.9,2,inf"), ["topology"]),
        (lambda: sc.fit("L-R", progress=3), ["progress"]),
        (lambda: sc.eval(), ["[prb] matrix"]),
        (lambda: sc.eval("no-such-model"), ["no-such-model"]),
        (lambda: sc.eval([[1.0, 2.0]]), ["models[0]"]),
        (lambda: sc.calibrate(), ["data"]),
    ]:
        with pytest.raises(prbfit.InputError) as e:
            call()
        for w in words:
            assert w in str(e.value), (w, str(e.value))


def test_a_failed_computation_is_a_solve_error():
    sc = prbfit.Scene.builtin()
    # A compressive load past the buckling load: the beam's path meets a critical point.
    with pytest.raises(prbfit.SolveError):
        sc.solve((-40.0, 0.0, 0.0))


def test_results_have_their_figures_as_attributes_and_numpy_arrays():
    sc = prbfit.Scene.load(STEEL)
    sol = sc.solve()
    d = sol.to_dict()
    assert sol.tips.shape == (len(d["cases"]), 3)
    assert sol.tips[-1, 0] == d["cases"][-1]["a"]
    assert sol.scene == d["scene"] and "scene:" in str(sol)
    r = sc.eval("su-3r")
    assert r.max_pos_err == r.to_dict()["max_pos_err"]
    # What it is at a glance, and the figures where tab completion looks.
    assert repr(r).startswith('<prbfit.Evaluation scene "'), repr(r)
    j = re.search(r"J ([0-9.e+-]+),", repr(r))
    assert j and abs(float(j.group(1)) / r.objective - 1) < 1e-4, repr(r)
    assert "L-R-R-R" in repr(r)
    assert {"max_pos_err", "objective", "to_dict", "tips"} <= set(dir(r))
    assert r.tips.shape == r.beam_tips.shape == (len(d["cases"]), 3)
    with pytest.raises(AttributeError):
        r.no_such_figure


def test_fit_progress_callback_sees_the_search():
    sc = prbfit.Scene.load(STEEL)
    seen = []
    f = sc.fit("L-R-R", fidelity="draft", seed=2, progress=seen.append)
    assert seen, "no progress was reported"
    assert set(seen[-1]) == {"phase", "iteration", "evaluations", "best_objective", "best", "seconds"}
    assert all(s["phase"] in ("start", "swarm", "polish") for s in seen)
    # The best J reported is never below what the fit ends with (it is the best so far).
    assert min(s["best_objective"] for s in seen) >= f.objective * (1 - 1e-12)
    assert f.matrix.topology == "L-R-R"


def test_an_exception_in_the_callback_stops_the_fit_and_is_raised():
    sc = prbfit.Scene.load(STEEL)

    def boom(_):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        sc.fit("L-R-R-R", fidelity="precise", progress=boom)


def test_ctrl_c_cancels_a_long_call():
    # The steel flexure's paths at ten times their steps: a precise 4R fit on them runs for
    # about 2 s in a release build (0.3 s at the scene's own steps, since the polish's
    # exact Jacobian), so the interrupt comes first.
    text = re.sub(r"steps = (\d+)", lambda m: f"steps = {10 * int(m.group(1))}", STEEL.read_text())
    sc = prbfit.Scene.from_toml(text, "steel-flexure, 10x steps")
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sc.fit("L-R-R-R-R", fidelity="precise")
    finally:
        timer.cancel()


def test_ctrl_c_stops_calculix_and_no_csv_is_written(tmp_path):
    # The steel flexure at mesh 30: its seven CalculiX runs take about 26 s, so the interrupt
    # comes during the first. It used to wait for all of them and write the CSV.
    import shutil

    if shutil.which("ccx") is None:
        if os.environ.get("CI"):
            pytest.fail("ccx (CalculiX) is not installed")
        pytest.skip("ccx (CalculiX) is not installed")
    sc = prbfit.Scene.load(STEEL)
    out = tmp_path / "fea.csv"
    timer = threading.Timer(1.0, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sc.fea(out, mesh=30)
    finally:
        timer.cancel()
    assert not out.exists(), "an interrupted FEA wrote its CSV"
    # The decks, written before CalculiX ran, stay: they are whole.
    assert (tmp_path / "fea-path1.inp").exists()


def test_two_threads_fit_at_once():
    """The GIL is released: two fits on two threads both finish, with the answers one
    thread gets (the timing is in python/benches/overhead.py)."""
    sc = prbfit.Scene.load(STEEL)
    alone = sc.fit("L-R-R", fidelity="draft", seed=5).to_dict()["prb"]
    out = [None, None]

    def work(i):
        out[i] = sc.fit("L-R-R", fidelity="draft", seed=5).to_dict()["prb"]

    ts = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert out == [alone, alone]


def test_a_panic_in_the_core_comes_out_as_a_solve_error():
    from prbfit import _prbfit

    with pytest.raises(prbfit.SolveError, match="internal error.*deliberate panic"):
        _prbfit._panic_in_worker()
    # The module still works after it.
    assert prbfit.Scene.builtin().kind == "cantilever"


def test_a_data_scene_from_text_is_refused_naming_the_way():
    text = (REPO / "assets/scenes/tapered-flexure-fea.toml").read_text()
    with pytest.raises(prbfit.InputError, match="Scene.load"):
        prbfit.Scene.from_toml(text)
