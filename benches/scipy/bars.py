"""Issue 24's own measure: the three jobs against scipy programs as the earlier bars timed scipy.

Issue 24 states its goals as "ratios measured against scipy in one run, as the earlier bars
measured them", and its "now" column (beam 372-386x, 3R fit 267-318x, stage ~2000x) was
measured that way. The earlier bars are issue 2's and issue 4's:

- issue 2 (the beam): "scipy's solve_bvp takes about 11 ms per solve at tolerance 1e-8 for
  alpha_y = 3": a solve, from the straight beam;
- issue 4 (the fit): "a competent scipy script (warm-started equilibria, Nelder-Mead) needs
  about 6 seconds for the same fit, baseline included";
- the stage's "scipy shooting solver" is named but not described: here it is the shooting
  solver a designer writes first, MINPACK's hybrd (`scipy.optimize.fsolve`, its own
  forward-difference Jacobian) on the same four unknowns as parallelogram.py, each residual one
  `solve_ivp` (DOP853, the same tolerances) of both flexures, each case started from a linear
  extrapolation of the two before.

Each program reuses the formulation of the competent job beside it (beam.py, fit3r.py,
parallelogram.py: the same right-hand sides, analytic Jacobians where the bar allows them, the
same batched PRB equilibria); only what the bar names differs (a solve from rest, Nelder-Mead,
fsolve). Where a reader of the bar has a choice, the fastest that keeps the answers was taken
(a review timed the alternatives: 11, 51 or 101 starting nodes; Nelder-Mead's tolerances;
fsolve's tolerance, difference step and start). The fit is also timed with Nelder-Mead stopped
as early as the 2 % goal allows, since prbfit's side is its fastest fidelity within 2 %. Each
is checked against prbfit's answers as its job is. The calibration line of each job gives the
figure its bar quotes, measured here.

The competent jobs (run.py's table) are the harder yardstick; these are the issue's.

Usage: python run.py PRBFIT_BINARY --bars [--repeats N] [--prbfit-repeats N] [--jobs ...]
(or python bars.py with the same arguments)
"""

import sys
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve, minimize

import beam
import common
import fit3r
import parallelogram


LOOSE_XATOL = 1e-2  # Nelder-Mead stopped as early as the 2 % goal allows (J +0.8 % here)


# --- the beam: every case its own solve, from the straight beam (issue 2's bar) ---

START_NODES = 51  # the fastest cold start of 11, 51 and 101 nodes (101 loses accuracy: 6e-9)


def solve_from_rest(load):
    """One elastica case by beam.py's solve_bvp from the straight beam on 51 nodes, not from
    the previous case: the tip (a, b, phi)."""
    return beam.tip(beam.solve_case(load, *beam.straight(START_NODES)))


def beam_job(binary, repeats, prbfit_repeats):
    loads, _, scene, wall, own, cases = beam.prbfit_side(binary, prbfit_repeats)
    scipy_time, tips = common.best_of(repeats, lambda: [solve_from_rest(c) for c in loads])
    diff = beam.max_tip_difference(tips, cases)
    one, _ = common.best_of(max(repeats, 10), lambda: solve_from_rest((0.0, 3.0, 0.0)))
    return {
        "job": f"beam, {len(loads)} cases (elastica, 4 paths x {beam.STEPS})",
        "prbfit_wall": wall, "prbfit_own": own, "scipy": scipy_time, "goal": 1000,
        "scipy_note": (f"issue 2's bar: solve_bvp tol 1e-8, each case from the straight beam on "
                       f"{START_NODES} nodes; one solve at alpha_y = 3: "
                       f"{common.fmt_seconds(one)} (issue 2: about 11 ms)"),
        "agreement": f"max tip diff {diff:.1e} L/rad",
        "agree": diff < 1e-6,
        "prbfit_cmd": f"solve --scene {scene} --json",
    }


# --- the fit: Nelder-Mead on J over warm-started equilibria (issue 4's bar) ---

def nelder_mead_fit(chain, start, xatol=None):
    """scipy.optimize.minimize(method="Nelder-Mead") on J from `start` (matrix text).

    The six free cells as fit3r.py's least_squares sees them (g2, g3, g4, k2, k3, k4; g1 the
    rest of 1); J by fit3r's Chain (batched Newton equilibria, warm-started along each path, a
    finite penalty for a model that cannot follow). scipy's default tolerances (they reach the
    least-squares optimum's J to four digits), or a looser `xatol`. Returns (matrix text, J,
    result)."""
    gammas, springs = fit3r.parse_matrix(start)
    x0 = np.array(gammas[1:] + springs)

    def unpack(x):
        return [1.0 - x[0] - x[1] - x[2]] + list(x[:3]), list(x[3:])

    options = {} if xatol is None else {"xatol": xatol}
    result = minimize(lambda x: chain.objective(*unpack(x)), x0, method="Nelder-Mead",
                      options=options)
    gammas, springs = unpack(result.x)
    return fit3r.matrix_text(gammas, springs), float(result.fun), result


def fit_job(binary, repeats, prbfit_repeats):
    scene, paths = fit3r.scene_and_paths()

    def scipy_side(xatol=None):
        t0 = time.perf_counter()
        tips = beam.solve_all(paths)
        chain = fit3r.Chain(paths, tips)
        _, j, result = nelder_mead_fit(chain, fit3r.SU_3R, xatol)
        return time.perf_counter() - t0, j, result, chain, tips

    runs = [scipy_side() for _ in range(repeats)]
    scipy_time = min(r[0] for r in runs)
    _, j_nm, result, chain, tips = runs[-1]
    # The same script stopped as early as the goal allows (a looser xatol, J within 2 %).
    loose = [scipy_side(LOOSE_XATOL) for _ in range(repeats)]
    loose_time = min(r[0] for r in loose)
    j_loose, loose_nfev = loose[-1][1], loose[-1][2].nfev
    truth_diff = fit3r.truth_difference(binary, scene, paths, tips)
    # The optimum the goal is stated at: the competent job's least_squares.
    _, j_opt, _ = fit3r.fit(chain, fit3r.SU_3R)
    for j in (j_nm, j_loose):
        if not j <= 1.02 * j_opt:
            raise RuntimeError(f"Nelder-Mead stopped at J {j:.4e}, not within 2 % of {j_opt:.4e}")
    tried, chosen = fit3r.prbfit_fits(binary, scene, chain, j_opt, prbfit_repeats)
    by = "; ".join(f"{t['fidelity']} {common.fmt_seconds(t['own'])} "
                   f"({scipy_time / t['own']:.0f}x, J {100 * (t['J'] / j_opt - 1):+.1f} %)"
                   for t in tried)
    return {
        "job": f"3R fit, {chain.n} cases (L-R-R-R, from su-3r)",
        "prbfit_wall": chosen["wall"], "prbfit_own": chosen["own"], "scipy": scipy_time,
        "goal": 1000,
        "scipy_note": (f"issue 4's bar: truth (solve_bvp) + Nelder-Mead on J over warm-started "
                       f"equilibria at scipy's defaults ({result.nfev} evaluations), "
                       f"{common.fmt_seconds(scipy_time)} (issue 4: about 6 s); stopped as "
                       f"early as the goal allows (xatol {LOOSE_XATOL:g}: {loose_nfev} "
                       f"evaluations, J {100 * (j_loose / j_opt - 1):+.1f} %) "
                       f"{common.fmt_seconds(loose_time)}, {loose_time / chosen['own']:.0f}x "
                       f"prbfit {chosen['fidelity']}; prbfit by fidelity: {by}"),
        "agreement": (f"J: least_squares optimum {j_opt:.4e}, Nelder-Mead {j_nm:.4e} "
                      f"({100 * (j_nm / j_opt - 1):+.1f} %), prbfit {chosen['fidelity']} "
                      f"{chosen['J']:.4e} ({100 * (chosen['J'] / j_opt - 1):+.1f} %; scipy's J "
                      f"of it {chosen['J_scipy_of_it']:.4e}); truth tip diff {truth_diff:.1e}"),
        "agree": abs(chosen["J_scipy_of_it"] / chosen["J"] - 1) < 1e-3 and truth_diff < 1e-6,
        "prbfit_cmd": (f"fit --scene {scene} --topology L-R-R-R --fidelity "
                       f"{chosen['fidelity']} --json"),
    }


# --- the stage: fsolve over one solve_ivp per residual (the shooting solver) ---

def shoot_once(stage, unknowns, load):
    """Both flexures integrated once at `unknowns`: the four equations and the stage pose."""
    f1 = unknowns[0:2]
    f2 = load[0:2] - f1
    fx = np.array([f1[0], f2[0]])
    fy = np.array([f1[1], f2[1]])
    y0 = np.concatenate([np.zeros(6), unknowns[2:4]])
    sol = solve_ivp(stage.rhs, (0.0, 1.0), y0, method="DOP853", rtol=parallelogram.RTOL,
                    atol=parallelogram.ATOL, args=(fx, fy))
    if sol.status != 0:
        raise RuntimeError(f"solve_ivp: {sol.message}")
    tips = sol.y[:, -1].reshape(4, 1, 2).transpose(1, 2, 0)
    eqs = stage.equations(tips, np.stack([f1, f2])[None], load)[0]
    a1, b1, phi1, _ = tips[0, 0]
    a2, b2, _, _ = tips[0, 1]
    pose = ((a1 + a2) / 2.0 - 1.0, ((stage.w + b1) + (-stage.w + b2)) / 2.0, phi1)
    return eqs, pose


def fsolve_drive(stage, end, steps):
    """Every case of one drive by fsolve (its default xtol; a difference step of 1e-5 for
    unknowns of order 1), each from a linear extrapolation of the previous two cases, its pose
    that of the evaluation at the solution (one more shot only where fsolve's last evaluation
    was elsewhere)."""
    prev = prev2 = np.zeros(4)
    poses = []
    for k in range(1, steps + 1):
        load = end * k / steps
        last = {}

        def residual(u):
            eqs, pose = shoot_once(stage, u, load)
            last["x"], last["pose"] = u.copy(), pose
            return eqs

        guess = 2.0 * prev - prev2 if k > 1 else prev
        x, _info, ier, msg = fsolve(residual, guess, epsfcn=1e-10, full_output=True)
        if ier != 1:
            raise RuntimeError(f"fsolve found no equilibrium at drive load {load}: {msg}")
        poses.append(last["pose"] if np.array_equal(last["x"], x)
                     else shoot_once(stage, x, load)[1])
        prev2, prev = prev, x
    return poses


def stage_job(binary, repeats, prbfit_repeats):
    stage, args, wall, own, cases = parallelogram.prbfit_side(binary, prbfit_repeats)
    steps = parallelogram.STEPS
    scipy_time, poses = common.best_of(
        repeats, lambda: [p for end in stage.drives for p in fsolve_drive(stage, end, steps)])
    diff = parallelogram.max_stage_difference(poses, cases)
    return {
        "job": f"parallel stage, {len(poses)} cases (2 drives x {steps})",
        "prbfit_wall": wall, "prbfit_own": own, "scipy": scipy_time, "goal": 3000,
        "scipy_note": (f"the shooting solver: fsolve (hybrd) on 4 unknowns, solve_ivp DOP853 "
                       f"rtol 1e-9, each case from the last two; "
                       f"{common.fmt_seconds(scipy_time / len(poses))} a case"),
        "agreement": f"max stage diff {diff:.1e} L/rad",
        "agree": diff < 1e-6,
        "prbfit_cmd": " ".join(str(a) for a in args),
    }


JOBS = {"beam": beam_job, "fit3r": fit_job, "parallelogram": stage_job}


def main(argv=None):
    """`python bars.py BINARY [options]`: run.py's command line with `--bars`."""
    import run
    return run.main(list(sys.argv[1:] if argv is None else argv) + ["--bars"])


if __name__ == "__main__":
    sys.exit(main())
