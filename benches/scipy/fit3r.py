"""Job 2: the 3R fit of a 20-case scene. scipy.optimize.least_squares against `prbfit fit`.

The scene is the built-in one (assets/scenes/default.toml: four load paths of 5 steps, 20
cases) with effects = [], so the truth is the plain elastica. The fit is of the L-R-R-R
topology's free cells (DESIGN §3-§4: the four gammas, summing to 1, and the three joint
springs: 6 parameters), minimising J = mean(e_pos^2 + w e_ang^2), w = 1.

The scipy program is the one a competent engineer writes:
- the truth: the 20 beam tips by solve_bvp (tol 1e-8, analytic Jacobians, warm-started along
  each path, as in beam.py), computed once; its time is counted in scipy's total, as prbfit's
  fit time counts its own baseline;
- the PRB chain's equilibrium (DESIGN §3 statics, k_i theta_i = beta + alpha_y (a - x_i) -
  alpha_x (b - y_i)) by Newton on the analytic 3x3 Jacobian, vectorised over the four load
  paths (one batched numpy solve per iteration), each step of a path warm-started from the
  previous one; a case Newton cannot finish goes to scipy.optimize.root (MINPACK hybrj) and
  an unfollowable trial model gets a finite penalty;
- the residual vector r (3 per case, sum r^2 = J) with its exact Jacobian by the implicit
  function theorem (d theta / d p = -(dR/d theta)^-1 dR/dp): no finite differences;
- least_squares (MINPACK Levenberg-Marquardt, 'lm') started from Su's published 3R, the
  natural start a designer has (DESIGN §3), to its default tolerances tightened to 1e-12.

Usage: python fit3r.py PRBFIT_BINARY [--repeats N]
"""

import math
import sys
import time

import numpy as np
from scipy.optimize import least_squares, root

import beam
import common

STEPS = 5           # the built-in scene: 4 paths x 5 steps = 20 cases
ANGLE_WEIGHT = 1.0
SU_3R = "0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf"
NEWTON_TOL = 1e-13  # |delta theta| at which a chain equilibrium counts as converged
PENALTY = 1.0       # residual of a case a trial model cannot follow (J of a useless model)
TRIL = np.tril(np.ones((3, 3)))  # v @ TRIL: sums of v[m] over m >= i


def parse_matrix(text):
    """An L-R-R-R matrix text (DESIGN §3) as (gammas[4], springs[3])."""
    rows = [[c.strip().rstrip("!") for c in r.split(",")] for r in text.split(";")]
    if len(rows) != 4 or rows[0][1] != "inf" or any(r[2] != "inf" for r in rows):
        raise ValueError(f"not an L-R-R-R matrix: {text}")
    return [float(r[0]) for r in rows], [float(r[1]) for r in rows[1:]]


def matrix_text(gammas, springs):
    """(gammas, springs) of L-R-R-R as matrix text."""
    rows = [f"{float(gammas[0])!r},inf,inf"] + [
        f"{float(g)!r},{float(k)!r},inf" for g, k in zip(gammas[1:], springs)]
    return "; ".join(rows)


class Chain:
    """The L-R-R-R chain over the scene's load paths, batched over paths (rows)."""

    def __init__(self, paths, tips, angle_weight=ANGLE_WEIGHT):
        self.steps = len(paths[0])
        loads = np.array(paths)                       # (P, steps, 3)
        self.ax, self.ay, self.beta = loads[..., 0], loads[..., 1], loads[..., 2]
        self.tips = np.array(tips).reshape(len(paths), self.steps, 3)
        self.n = len(paths) * self.steps
        self.scale = np.array([1.0, 1.0, math.sqrt(angle_weight)]) / math.sqrt(self.n)
        self.idx = np.maximum.outer(np.arange(3), np.arange(3))
        self.eye = np.eye(3)

    def _terms(self, th, g, ax, ay):
        """Segment angles and the sums Newton and the sensitivities need."""
        big = np.cumsum(th, axis=1)                    # Theta of segments 2..4, (P, 3)
        c, s = np.cos(big), np.sin(big)
        e = ay[:, None] * c - ax[:, None] * s          # torque arm term per segment
        d = -(ay[:, None] * s + ax[:, None] * c) * g   # its derivative times gamma
        return big, c, s, e, d

    @staticmethod
    def _revcumsum(v):
        """Sums over m >= i along the last axis (a matrix product: cheaper than flips)."""
        return v @ TRIL

    def _jac_theta(self, k, d):
        """dR/dtheta = diag(k) - S[max(i, j)], S the reverse cumulative sum of d."""
        sums = self._revcumsum(d)                      # (P, 3)
        return self.eye * k - sums[:, self.idx]        # (P, 3, 3)

    def _newton(self, th, g, k, ax, ay, beta):
        """Batched Newton from `th`; returns (theta, converged rows)."""
        for _ in range(30):
            _, _, _, e, d = self._terms(th, g, ax, ay)
            tau = beta[:, None] + self._revcumsum(g * e)
            res = k * th - tau
            step = np.linalg.solve(self._jac_theta(k, d), res[..., None])[..., 0]
            th = th - step
            if not np.all(np.isfinite(th)):
                break
            if np.max(np.abs(step)) < NEWTON_TOL:
                return th, np.ones(th.shape[0], dtype=bool)
        ok = np.all(np.isfinite(th), axis=1) & np.all(np.abs(step) < 1e-10, axis=1)
        return th, ok

    def _root(self, th0, g, k, ax, ay, beta):
        """One case by MINPACK's hybrj, for the rare case plain Newton cannot finish."""
        def fun(t):
            t = t[None, :]
            _, _, _, e, d = self._terms(t, g, np.array([ax]), np.array([ay]))
            res = k * t - (beta + self._revcumsum(g * e))
            return res[0], self._jac_theta(k, d)[0]
        sol = root(fun, th0, jac=True, method="hybr", options={"xtol": 1e-13})
        return sol.x, bool(sol.success)

    def evaluate(self, gammas, springs, jacobian=True):
        """Residuals (3 per case, sum of squares = J) and, with `jacobian`, d r / d params.

        params = (g2, g3, g4, k2, k3, k4); g1 = 1 - g2 - g3 - g4."""
        g = np.asarray(gammas[1:], dtype=float)
        g1 = gammas[0]
        k = np.asarray(springs, dtype=float)
        rows = self.ax.shape[0]
        th = np.zeros((rows, 3))
        res = np.empty((rows, self.steps, 3))
        jac = np.zeros((rows, self.steps, 3, 6))
        failed = np.zeros(rows, dtype=bool)
        for step in range(self.steps):
            ax, ay, beta = self.ax[:, step], self.ay[:, step], self.beta[:, step]
            th, ok = self._newton(th, g, k, ax, ay, beta)
            for r in np.flatnonzero(~ok & ~failed):
                start = th[r] if np.all(np.isfinite(th[r])) else np.zeros(3)
                th[r], ok[r] = self._root(start, g, k, ax[r], ay[r], beta[r])
            failed |= ~ok
            th[failed] = 0.0
            big, c, s, e, d = self._terms(th, g, ax, ay)
            a = g1 + np.sum(g * c, axis=1)
            b = np.sum(g * s, axis=1)
            phi = big[:, 2]
            res[:, step] = (np.stack([a, b, phi], axis=1) - self.tips[:, step]) * self.scale
            if jacobian:
                jth = self._jac_theta(k, d)
                # dR/dp: gammas (R_j depends on g_m for m >= j), springs (diagonal theta).
                drdp = np.zeros((rows, 3, 6))
                for j in range(3):
                    drdp[:, j, j:3] = -e[:, j:3]
                    drdp[:, j, 3 + j] = th[:, j]
                dth = -np.linalg.solve(jth, drdp)                     # (P, 3, 6)
                dtip_dth = np.stack([self._revcumsum(-g * s), self._revcumsum(g * c),
                                     np.ones_like(c)], axis=1)        # (P, 3 tip, 3 theta)
                direct = np.zeros((rows, 3, 6))
                direct[:, 0, 0:3] = c - 1.0
                direct[:, 1, 0:3] = s
                jac[:, step] = (dtip_dth @ dth + direct) * self.scale[None, :, None]
        res[failed] = PENALTY
        jac[failed] = 0.0
        r = res.reshape(-1)
        return (r, jac.reshape(-1, 6)) if jacobian else r

    def objective(self, gammas, springs):
        """J of one matrix over the scene's cases."""
        r = self.evaluate(gammas, springs, jacobian=False)
        return float(r @ r)


def fit(chain, start):
    """least_squares ('lm', analytic Jacobian) from `start` (matrix text).

    Returns (matrix text, J, the least_squares result)."""
    gammas, springs = parse_matrix(start)
    x0 = np.array(gammas[1:] + springs)

    def unpack(x):
        return [1.0 - x[0] - x[1] - x[2]] + list(x[:3]), list(x[3:])

    # 'lm' calls jac right after fun at the same x: memoise the pair.
    cache = {}

    def both(x):
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = chain.evaluate(*unpack(x))
        return cache[key]

    result = least_squares(lambda x: both(x)[0], x0, jac=lambda x: both(x)[1], method="lm",
                           xtol=1e-12, ftol=1e-12, gtol=1e-12)
    gammas, springs = unpack(result.x)
    return matrix_text(gammas, springs), 2.0 * result.cost, result


def scipy_job(paths):
    """The whole scipy side: truth once, then the fit.

    Returns (matrix, J, truth seconds, fit seconds, least_squares result, tips, chain)."""
    t0 = time.perf_counter()
    tips = beam.solve_all(paths)
    t1 = time.perf_counter()
    chain = Chain(paths, tips)
    matrix, j, result = fit(chain, SU_3R)
    t2 = time.perf_counter()
    return matrix, j, t1 - t0, t2 - t1, result, tips, chain


def scene_and_paths():
    """The 20-case scene, written, and its load paths."""
    paths = common.cases_along(common.DEFAULT_PATHS, STEPS)
    scene = common.write_scene(
        common.elastica_scene(common.DEFAULT_PATHS, STEPS, "built-in beam, elastica, 20 cases"),
        "fit-20.toml")
    return scene, paths


def truth_difference(binary, scene, paths, tips):
    """prbfit's own baseline of `scene` against scipy's `tips` (checked to be the same loads
    in order)."""
    _, _, solved = common.run_prbfit(binary, ["solve", "--scene", scene, "--json"], 1)
    common.check_loads([c for p in paths for c in p], solved["cases"])
    return beam.max_tip_difference(tips, solved["cases"])


def prbfit_fits(binary, scene, chain, j_opt, repeats):
    """prbfit's fit at draft and normal (and precise, should neither reach it), each timed
    (best of `repeats`) and its model's J on all 20 cases by `prbfit eval` (draft fits on
    half the load samples). Returns (every fidelity tried, the fastest within 2 % of
    `j_opt`)."""
    tried = []
    for fidelity in ["draft", "normal", "precise"]:
        if fidelity == "precise" and any(t["reached"] for t in tried):
            break
        walls, owns, fits = [], [], []
        for _ in range(repeats):
            wall, own, out = common.run_prbfit(
                binary, ["fit", "--scene", scene, "--topology", "L-R-R-R", "--fidelity",
                         fidelity, "--json"], 1)
            walls.append(wall)
            owns.append(own)
            fits.append(out["seconds"] - out["baseline_seconds"])
        _, _, ev = common.run_prbfit(binary, ["eval", "--scene", scene, "--prb", out["prb"],
                                              "--json"], 1)
        j_prbfit = ev["objective"]
        tried.append({
            "fidelity": fidelity, "J": j_prbfit, "J_scipy_of_it": chain.objective(
                *parse_matrix(out["prb"])), "wall": min(walls), "own": min(owns),
            "fit": min(fits), "prb": out["prb"], "reached": j_prbfit <= 1.02 * j_opt})
    reached = [t for t in tried if t["reached"]]
    if not reached:
        raise RuntimeError(f"no prbfit fidelity reached J within 2 % of scipy's {j_opt:.4e}: "
                           f"{tried}")
    return tried, min(reached, key=lambda t: t["own"])


def run(binary, repeats=3, prbfit_repeats=None):
    """Times both sides (best of `repeats`; prbfit of `prbfit_repeats`, default the same).

    Returns a dict for run.py's table."""
    scene, paths = scene_and_paths()
    runs = [scipy_job(paths) for _ in range(repeats)]
    best = min(runs, key=lambda r: r[2] + r[3])
    matrix, j_scipy, _, _, result, tips, chain = best
    scipy_time = best[2] + best[3]
    fit_time = min(r[3] for r in runs)
    truth_diff = truth_difference(binary, scene, paths, tips)
    tried, chosen = prbfit_fits(binary, scene, chain, j_scipy, prbfit_repeats or repeats)
    others = "; ".join(f"{t['fidelity']} J {t['J']:.4e} ({100 * (t['J'] / j_scipy - 1):+.1f} %) "
                       f"in {common.fmt_seconds(t['own'])}" for t in tried)
    return {
        "job": f"3R fit, {chain.n} cases (L-R-R-R, from su-3r)",
        "prbfit_wall": chosen["wall"],
        "prbfit_own": chosen["own"],
        "scipy": scipy_time,
        "scipy_note": (f"truth (solve_bvp, 20 cases) + least_squares lm ({result.nfev} "
                       f"evaluations); the fit alone, truth excluded on both sides: scipy "
                       f"{common.fmt_seconds(fit_time)}, "
                       f"prbfit {common.fmt_seconds(chosen['fit'])} "
                       f"({fit_time / chosen['fit']:.0f}x); prbfit by fidelity: {others}"),
        "agreement": (f"J scipy {j_scipy:.4e}, prbfit {chosen['fidelity']} {chosen['J']:.4e} "
                      f"({100 * (chosen['J'] / j_scipy - 1):+.1f} %; scipy's J of it "
                      f"{chosen['J_scipy_of_it']:.4e}); truth tip diff {truth_diff:.1e}"),
        "goal": 1000,
        "agree": abs(chosen["J_scipy_of_it"] / chosen["J"] - 1) < 1e-3 and truth_diff < 1e-6,
        "prbfit_cmd": (f"fit --scene {scene} --topology L-R-R-R --fidelity {chosen['fidelity']} "
                       "--json"),
        "details": {"scipy_matrix": matrix, "prbfit_matrix": chosen["prb"]},
    }


def main(argv=None):
    common.job_main(run, __doc__, argv)


if __name__ == "__main__":
    sys.exit(main())
