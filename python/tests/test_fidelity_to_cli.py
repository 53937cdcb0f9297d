"""Every command's result equals the CLI's `--json` object for the same command and
arguments, on every shipped scene (timings aside): the same report, built by the same library
code. A command the CLI refuses on a scene raises the matching error with the CLI's message.
Fits and selections run at draft fidelity to keep this affordable; the slowest cases are
marked `slow`."""

import re
import shutil

import pytest

import prbfit
from conftest import REPO, SCENES, timeless

NAMES = [s.stem for s in SCENES]


def scene_path(name):
    return REPO / "assets" / "scenes" / f"{name}.toml"


def same(cli_result, call):
    """`call()` gives the CLI's object, or raises the CLI's error as the CLI's kind."""
    if cli_result.status == 0:
        r = call()
        assert timeless(r.to_dict()) == timeless(cli_result.json)
        return r
    kind = prbfit.InputError if cli_result.status == 2 else prbfit.SolveError
    with pytest.raises(kind) as e:
        call()
    assert str(e.value) == cli_result.error
    return None


def model_for(sc):
    """The scene's own model, else Su's 3R (the CLI's `--model su-3r`)."""
    return [] if sc.matrix is not None else ["su-3r"]


@pytest.mark.parametrize("name", NAMES)
def test_solve(cli, name):
    sc = prbfit.Scene.load(scene_path(name))
    same(cli("solve", "--scene", scene_path(name)), lambda: sc.solve())


def test_solve_one_load_with_shape(cli):
    sc = prbfit.Scene.builtin()
    r = same(cli("solve", "--load", "0,1.5,0.2", "--shape"), lambda: sc.solve((0, 1.5, 0.2), shape=True))
    assert r.tips.shape == (1, 3)
    assert len(r.shapes) == 1 and r.shapes[0].shape[1] == 3


@pytest.mark.parametrize("name", NAMES)
def test_eval(cli, name):
    sc = prbfit.Scene.load(scene_path(name))
    models = model_for(sc)
    flags = [x for m in models for x in ("--model", m)]
    same(cli("eval", "--scene", scene_path(name), *flags), lambda: sc.eval(*models))


def test_eval_several_models_and_one_load(cli):
    sc = prbfit.Scene.builtin()
    m = "0.15,inf,inf; 0.85,2.2525,inf"
    r = same(
        cli("eval", "--model", "su-3r", "--prb", m, "--load", "0,2,0"),
        lambda: sc.eval("su-3r", prbfit.Matrix.parse(m), load=(0, 2, 0)),
    )
    assert len(r.models) == 2


@pytest.mark.parametrize("name", NAMES)
def test_modes(cli, name):
    """Where the scene has no `[beam] density` the CLI refuses (status 2) and so must the
    module, with the same message."""
    sc = prbfit.Scene.load(scene_path(name))
    models = model_for(sc)
    flags = [x for m in models for x in ("--model", m)]
    same(cli("modes", "--scene", scene_path(name), *flags), lambda: sc.modes(*models))


def test_modes_every_case_one_load_and_matrices(cli):
    path = scene_path("ringing-flexure")
    sc = prbfit.Scene.load(path)
    m = "0.15,inf,inf,0.3; 0.85,2.2525,inf,0.7"
    same(
        cli("modes", "--scene", path, "--model", "su-3r", "--prb", m, "--cases", "--count", 2),
        lambda: sc.modes(prbfit.Matrix.parse(m), "su-3r", cases=True, count=2),
    )
    same(
        cli("modes", "--scene", path, "--model", "howell-1r", "--load", "-2,0,0", "--count", 1),
        lambda: sc.modes("howell-1r", load=(-2, 0, 0), count=1),
    )
    # Past buckling (pi^2/4 = 2.47 for the free end): the statics' own failure.
    same(cli("modes", "--scene", path, "--load", "-40,0,0"), lambda: sc.modes(load=(-40, 0, 0)))


@pytest.mark.parametrize("name", ["parallel-stage", "steel-flexure", "tapered-flexure-fea"])
def test_modes_of_a_scene_given_its_density_in_python(cli, name, tmp_path):
    """Scenes shipped without a density, given one (and a body) in Python: the same report as
    the CLI's on the edited scene written out."""
    sc = prbfit.Scene.load(scene_path(name))
    sc.set_beam(density=2700.0)
    sc.set_body(mass=0.001, inertia=1e-9)
    if sc.kind == "data":
        # A data scene's TOML names its CSV, read beside the scene file.
        shutil.copy(scene_path(name).with_suffix(".csv"), tmp_path)
    edited = tmp_path / f"{name}.toml"
    edited.write_text(sc.to_toml())
    models = model_for(sc)
    flags = [x for m in models for x in ("--model", m)]
    same(cli("modes", "--scene", edited, *flags, "--cases"), lambda: sc.modes(*models, cases=True))


def test_dynamic_fit_of_a_scene_edited_in_python(cli, tmp_path):
    """[fit] modes set in Python frees the mus: the same fit as the CLI's on the edited scene
    written out, its matrix four columns."""
    sc = prbfit.Scene.load(scene_path("ringing-flexure"))
    sc.set_fit_settings(modes=2, frequency_weight=0.5)
    edited = tmp_path / "dynamic.toml"
    edited.write_text(sc.to_toml())
    f = same(
        cli("fit", "--scene", edited, "--topology", "L-R-R", "--fidelity", "draft", "--seed", 3),
        lambda: sc.fit("L-R-R", fidelity="draft", seed=3),
    )
    assert f.matrix.has_mu and f.matrix.to_numpy().shape == (3, 4)


SLOW_FIT = {"slider-crank", "slider-crank-rig", "parallel-stage", "cross-axis-pivot", "fixed-guided"}


@pytest.mark.parametrize(
    "name",
    [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_FIT else n for n in NAMES],
)
def test_fit(cli, name):
    sc = prbfit.Scene.load(scene_path(name))
    same(
        cli("fit", "--scene", scene_path(name), "--topology", "L-R-R", "--fidelity", "draft", "--seed", 3),
        lambda: sc.fit("L-R-R", fidelity="draft", seed=3),
    )


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_select(cli, name):
    sc = prbfit.Scene.load(scene_path(name))
    same(cli("select", "--scene", scene_path(name), "--fidelity", "draft"), lambda: sc.select("draft"))


def test_select_builtin(cli):
    sc = prbfit.Scene.builtin()
    same(cli("select", "--fidelity", "draft"), lambda: sc.select("draft"))


def test_select_within_stroke_without_an_allowable_stress(cli):
    sc = prbfit.Scene.load(scene_path("steel-flexure"))
    # Without an allowable stress there is no stroke limit: the CLI's refusal, the same.
    same(
        cli("select", "--scene", scene_path("steel-flexure"), "--fidelity", "draft", "--within-stroke"),
        lambda: sc.select("draft", within_stroke=True),
    )


def test_select_within_stroke_of_a_scene_given_its_allowable_stress_in_python(cli, tmp_path):
    sc = prbfit.Scene.load(scene_path("steel-flexure"))
    sc.set_beam(allowable_stress=1.0e9)
    edited = tmp_path / "stress.toml"
    edited.write_text(sc.to_toml())
    c = cli("select", "--scene", edited, "--fidelity", "draft", "--within-stroke")
    assert c.status == 0, c.error
    same(c, lambda: sc.select("draft", within_stroke=True))


@pytest.mark.parametrize("name", NAMES)
def test_calibrate(cli, name):
    sc = prbfit.Scene.load(scene_path(name))
    same(cli("calibrate", "--scene", scene_path(name)), lambda: sc.calibrate())


@pytest.mark.parametrize("name", NAMES)
def test_export(cli, name, tmp_path):
    sc = prbfit.Scene.load(scene_path(name))
    models = model_for(sc)
    flags = [x for m in models for x in ("--model", m)]
    a, b = tmp_path / "cli.toml", tmp_path / "py.toml"
    c = cli("export", "--scene", scene_path(name), *flags, "-o", a, "--fidelity", "draft")
    call = lambda: sc.export(models[0] if models else None, b, fidelity="draft")
    if c.status != 0:
        same(c, call)
        return
    d = call().to_dict()
    d["output"] = str(a)  # the one difference: where each was asked to write
    assert timeless(d) == timeless(c.json)
    # The same file, but for the time it was written (a model file records it).
    stamp = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ")
    assert stamp.sub("T", a.read_text()) == stamp.sub("T", b.read_text())


@pytest.mark.slow
def test_fea_equals_cli_of_a_beam_and_of_a_mechanism(cli, tmp_path):
    import shutil

    if shutil.which("ccx") is None:
        pytest.fail("ccx (CalculiX) is needed: apt-get install calculix-ccx")
    for scene, flags, n in [(None, [], 0), (scene_path("parallel-stage"), ["--scene", scene_path("parallel-stage")], 1)]:
        sc = prbfit.Scene.builtin() if scene is None else prbfit.Scene.load(scene)
        a, b = tmp_path / f"cli{n}.csv", tmp_path / f"py{n}.csv"
        c = cli("fea", *flags, "-o", a, "--mesh", "4")
        r = sc.fea(b, mesh=4)
        d = timeless(r.to_dict())
        # The one difference: where each was asked to write (the decks beside the output).
        d["output"] = str(a)
        d["decks"] = [x.replace(str(b.with_suffix("")), str(a.with_suffix(""))) for x in d["decks"]]
        assert d == timeless(c.json)
        assert a.read_text() == b.read_text()
        assert r.tips.shape == (len(d["cases"]), 3)
        if sc.kind == "mechanism":
            # The FEA's stage per case; the beam mechanism's differences are in the dict.
            assert r.tips[0].tolist() == d["cases"][0]["stage"] and r.beam_tips.shape == (0, 3)
        else:
            assert r.beam_tips.shape == r.tips.shape
