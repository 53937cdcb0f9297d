"""Job 1: the beam, 1000 cases. scipy's solve_bvp (tol 1e-8) against `prbfit solve --scene`.

The beam is DESIGN §2 with every effect off: the inextensible Euler-Bernoulli elastica, a
cantilever under a tip load fixed in direction. The cases are the built-in scene's four load
paths (transverse force, a force pushing back at 135 degrees, a pure moment, force and moment
together), 250 steps each: 1000 cases, each reached by continuation from the previous one.

The scipy program is the one a competent engineer writes for this BVP:
- the state is (x, y, psi, M) with the bending moment M as a state (dM/ds = alpha_x sin psi -
  alpha_y cos psi), so the boundary conditions are local: x = y = psi = 0 at the root and
  M = beta at the tip (no unknown tip position inside the right-hand side);
- the right-hand side is vectorised over the mesh, and both Jacobians (of the right-hand side
  and of the boundary conditions) are given analytically;
- each case starts from the previous case's converged mesh and solution along its load path
  (the first case of a path from the straight beam), so solve_bvp does little more than one
  Newton solve per case.

Usage: python beam.py PRBFIT_BINARY [--repeats N]
"""

import sys

import numpy as np
from scipy.integrate import solve_bvp

import common

STEPS = 250  # per path: 4 paths x 250 = 1000 cases
TOL = 1e-8   # solve_bvp's tolerance, as issue 24 measures it


def straight(nodes):
    """The unloaded beam on `nodes` evenly spaced nodes: (mesh, state)."""
    s = np.linspace(0.0, 1.0, nodes)
    return s, np.vstack([s, np.zeros_like(s), np.zeros_like(s), np.zeros_like(s)])


def solve_case(load, s, guess, tol=TOL):
    """One elastica case by solve_bvp from the mesh `s` and state `guess`: the solution."""
    ax, ay, beta = load

    def rhs(_s, y):
        c, sn = np.cos(y[2]), np.sin(y[2])
        return np.vstack([c, sn, y[3], ax * sn - ay * c])

    def rhs_jac(_s, y):
        c, sn = np.cos(y[2]), np.sin(y[2])
        jac = np.zeros((4, 4, y.shape[1]))
        jac[0, 2] = -sn
        jac[1, 2] = c
        jac[2, 3] = 1.0
        jac[3, 2] = ax * c + ay * sn
        return jac

    def bc(ya, yb):
        return np.array([ya[0], ya[1], ya[2], yb[3] - beta])

    sol = solve_bvp(rhs, bc, s, guess, fun_jac=rhs_jac, bc_jac=BC_JAC, tol=tol,
                    max_nodes=100000)
    if sol.status != 0:
        raise RuntimeError(f"solve_bvp failed at load {load}: {sol.message}")
    return sol


def tip(sol):
    """The tip (a, b, phi) of a solve_bvp solution."""
    return sol.y[0, -1], sol.y[1, -1], sol.y[2, -1]


def solve_path(loads, tol=TOL):
    """Solves the elastica along one load path by continuation; returns [(a, b, phi)] per case."""
    s, guess = straight(11)
    tips = []
    for load in loads:
        sol = solve_case(load, s, guess, tol)
        s, guess = sol.x, sol.y
        tips.append(tip(sol))
    return tips


def _bc_jac(_ya, _yb):
    dya = np.zeros((4, 4))
    dya[0, 0] = dya[1, 1] = dya[2, 2] = 1.0
    dyb = np.zeros((4, 4))
    dyb[3, 3] = 1.0
    return dya, dyb


BC_JAC = _bc_jac


def solve_all(paths):
    """Every case of every path, in scene order."""
    return [tip for loads in paths for tip in solve_path(loads)]


def max_tip_difference(tips, cases):
    """Largest |difference| in a, b or phi between scipy's tips and prbfit's `solve` cases
    (inf if they differ in number, or on NaN)."""
    return common.max_difference(tips, [(c["a"], c["b"], c["phi"]) for c in cases])


def prbfit_side(binary, repeats):
    """The 1000-case scene written, and prbfit's `solve` of it timed (best of `repeats`) and
    checked to be the scene's loads in order: (loads, paths, scene, wall, own, cases)."""
    paths = common.cases_along(common.DEFAULT_PATHS, STEPS)
    scene = common.write_scene(
        common.elastica_scene(common.DEFAULT_PATHS, STEPS, "built-in beam, elastica, 1000 cases"),
        "beam-1000.toml")
    wall, own, out = common.run_prbfit(binary, ["solve", "--scene", scene, "--json"], repeats)
    loads = [c for p in paths for c in p]
    common.check_loads(loads, out["cases"])
    return loads, paths, scene, wall, own, out["cases"]


def run(binary, repeats=3, prbfit_repeats=None):
    """Times both sides (best of `repeats`; prbfit of `prbfit_repeats`, default the same).

    Returns a dict for run.py's table."""
    loads, paths, scene, wall, own, cases = prbfit_side(binary, prbfit_repeats or repeats)
    n = len(loads)
    scipy_time, tips = common.best_of(repeats, lambda: solve_all(paths))
    diff = max_tip_difference(tips, cases)
    # Each side's own error, against prbfit at tol 1e-12 (tip good to about 1e-11).
    _, _, ref = common.run_prbfit(binary, ["solve", "--scene", scene, "--json", "--tol", "1e-12"],
                                  1)
    err_scipy = max_tip_difference(tips, ref["cases"])
    err_prbfit = max_tip_difference([(c["a"], c["b"], c["phi"]) for c in cases], ref["cases"])
    return {
        "job": f"beam, {n} cases (elastica, 4 paths x {STEPS})",
        "prbfit_wall": wall,
        "prbfit_own": own,
        "scipy": scipy_time,
        "scipy_note": f"solve_bvp tol {TOL:g}, warm-started",
        "agreement": (f"max tip diff {diff:.1e} L/rad (error vs tol 1e-12: scipy "
                      f"{err_scipy:.1e}, prbfit {err_prbfit:.1e})"),
        "agree": diff < 1e-6,
        "goal": 1000,
        "prbfit_cmd": f"solve --scene {scene} --json",
    }


def main(argv=None):
    common.job_main(run, __doc__, argv)


if __name__ == "__main__":
    sys.exit(main())
