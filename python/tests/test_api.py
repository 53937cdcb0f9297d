"""The module's own behaviour: matrices, scene edits by the scene's rules, errors naming the
argument, numpy arrays, progress callbacks, cancellation, the GIL released."""

import _thread
import math
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
    assert a.shape == (2, 3) and a.dtype == np.float64
    assert a[0, 0] == 0.1 and math.isinf(a[0, 1]) and a[1, 1] == 2.2
    assert m.topology == "L-R"
    assert m.fixed.tolist() == [[False, False, False], [True, False, False]]
    assert prbfit.Matrix(a) == prbfit.Matrix.parse("0.1,inf,inf; 0.9,2.2,inf")
    assert prbfit.Matrix(m.to_numpy(), fixed=m.fixed.tolist()) == m
    assert prbfit.Matrix.parse(m.text) == m
    assert prbfit.Matrix.from_topology("L-R-R-R").topology == "L-R-R-R"
    assert len(prbfit.Matrix.from_topology("3R")) == 4


@pytest.mark.parametrize(
    "rows, words",
    [
        ([[0.1, 1.0]], ["rows", "row 1", "3 entries"]),
        ([[0.5, float("nan"), math.inf], [0.5, 2, math.inf]], ["rows", "row 1", "k_theta", "NaN"]),
        ("oops", ["rows", "oops"]),
        (3.5, ["rows", "expected"]),
        (np.zeros((2, 4)), ["rows", "3 entries"]),
    ],
)
def test_bad_matrices_are_input_errors_naming_the_argument(rows, words):
    with pytest.raises(prbfit.InputError) as e:
        prbfit.Matrix(rows)
    for w in words:
        assert w in str(e.value)


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
    sc = prbfit.Scene.load(STEEL)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # A precise 4R fit runs for many seconds: the interrupt comes first.
            sc.fit("L-R-R-R-R", fidelity="precise")
    finally:
        timer.cancel()


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
