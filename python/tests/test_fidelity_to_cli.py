"""Every command's result equals the CLI's `--json` object for the same command and
arguments, on every shipped scene (timings aside): the same report, built by the same library
code. A command the CLI refuses on a scene raises the matching error with the CLI's message.
Fits and selections run at draft fidelity to keep this affordable; the slowest cases are
marked `slow`."""

import re

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
def test_fea_equals_cli_and_refuses_a_mechanism(cli, tmp_path):
    import shutil

    if shutil.which("ccx") is None:
        pytest.fail("ccx (CalculiX) is needed: apt-get install calculix-ccx")
    sc = prbfit.Scene.builtin()
    a, b = tmp_path / "cli.csv", tmp_path / "py.csv"
    c = cli("fea", "-o", a, "--mesh", "4")
    r = sc.fea(b, mesh=4)
    d = timeless(r.to_dict())
    # The one difference: where each was asked to write (the decks beside the output).
    d["output"] = str(a)
    d["decks"] = [x.replace(str(b.with_suffix("")), str(a.with_suffix(""))) for x in d["decks"]]
    assert d == timeless(c.json)
    assert a.read_text() == b.read_text()
    assert r.tips.shape == r.beam_tips.shape == (len(d["cases"]), 3)
    mech = prbfit.Scene.load(scene_path("parallel-stage"))
    same(cli("fea", "--scene", scene_path("parallel-stage"), "-o", tmp_path / "m.csv"), lambda: mech.fea(tmp_path / "n.csv"))
