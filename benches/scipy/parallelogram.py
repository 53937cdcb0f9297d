"""Job 3: the parallel-guiding stage, 1000 cases. A scipy shooting solver against `prbfit solve`.

The scene is assets/scenes/parallel-stage.toml (DESIGN §8): two identical clamped flexures at
(0, +W) and (0, -W), W = 0.3 L, both along +x, their tips clamped to one rigid stage, loads at
the stage centre; each flexure is the DESIGN §2 beam with shear, extension and Poisson on, as
the scene says. Its two drives (a sideways force; the same with a pull along the flexures)
get 500 steps each: 1000 cases, each by continuation from the previous one on its path.

The scipy program is the one a competent engineer writes:
- shooting from the clamps: each flexure is an initial-value problem once its root reaction
  is known (the tip force, constant along the beam, and the root moment); the state is
  (x, y, psi, M) with dM/ds = -f_y x' + f_x y', so one integration gives the tip pose and the
  tip moment;
- four unknowns, not nine: flexure 1's force and root moment and flexure 2's root moment;
  flexure 2's force is the stage load minus flexure 1's (the stage's force balance), and the
  remaining four equations are the two tips' clamp to the rigid stage (equal tip angles, the
  tip-to-tip vector turned with the stage) and the stage's moment balance;
- one solve_ivp call (DOP853, rtol 1e-9, atol 1e-11) integrates, with a vectorised
  right-hand side, both flexures at the unknowns and at the four perturbed unknowns of a
  forward-difference Jacobian, all on the same adaptive steps (so the Jacobian is that of the
  discrete map, good to the perturbation, not to the integration error);
- Newton on the 4 equations with that Jacobian, each case started from a linear
  extrapolation of the previous two solutions along the drive path: 2 evaluations a case
  (scipy.optimize.root's MINPACK methods on the same function and Jacobian took 5 (lm,
  hybr at xtol 1e-10) to 9 (hybr at 1e-12) on this path, so they are only the fallback for a
  case where Newton stalls).

Usage: python parallelogram.py PRBFIT_BINARY [--repeats N]
"""

import sys
import tomllib

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import root

import common

STEPS = 500            # per drive: 2 drives x 500 = 1000 cases
RTOL, ATOL = 1e-9, 1e-11  # as accurate as prbfit's default tol 1e-9 (README: "Tolerances")
FD_STEP = 1e-7         # forward-difference step of the Jacobian (unknowns are O(1))
NEWTON_TOL = 1e-11     # Newton step (forces, moments in E I0 / L^2, E I0 / L) that ends a case
NEWTON_MAX = 8


class Stage:
    """The parallel stage in flexure 1's units (L = 1, E I0 = 1)."""

    def __init__(self, scene):
        beam = scene["beam"]
        length, width, thick = beam["length"], beam["width"], beam["thickness"]
        self.nu = beam["poisson_ratio"]
        effects = set(beam["effects"])
        if effects != {"shear", "extension", "poisson"}:
            raise ValueError(f"this solver models shear+extension+poisson, scene has {effects}")
        slenderness = length / thick
        kappa = 10.0 * (1.0 + self.nu) / (12.0 + 11.0 * self.nu)  # Cowper's rectangle
        self.c_e = 1.0 / (12.0 * slenderness**2)                   # I0 / (A0 L^2)
        self.c_s = self.c_e * 2.0 * (1.0 + self.nu) / kappa        # E I0 / (kappa G A0 L^2)
        roots = [np.array(f["root"]) / length for f in scene["flexures"]]
        own = ("length", "width", "thickness", "youngs_modulus", "poisson_ratio")
        plain = all(f.get("angle_deg", 0.0) == 0.0 and f.get("attach", "clamped") == "clamped"
                    and not any(k in f for k in own) for f in scene["flexures"])
        if (len(roots) != 2 or not plain or roots[0][0] != 0.0 or roots[1][0] != 0.0
                or roots[0][1] + roots[1][1] != 0.0):
            raise ValueError(
                "this solver is for two clamped flexures at (0, +W), (0, -W) along +x")
        self.w = roots[0][1]
        point = np.array(scene["stage"]["point"]) / length
        if abs(point[0] - 1.0) > 1e-12 or abs(point[1]) > 1e-12:
            raise ValueError("this solver puts the stage point midway between the tips")
        ei0 = beam["youngs_modulus"] * width * thick**3 / 12.0
        self.drives = [np.array([d.get("fx", 0.0) * length**2 / ei0,
                                 d.get("fy", 0.0) * length**2 / ei0,
                                 d.get("mz", 0.0) * length / ei0]) for d in scene["drives"]]

    def rhs(self, _s, y, fx, fy):
        """Both flexures of every copy at once: y is (x, y, psi, M) x beams, flattened."""
        x = y.reshape(4, -1)
        psi, m = x[2], x[3]
        c, s = np.cos(psi), np.sin(psi)
        n = fx * c + fy * s
        q = -fx * s + fy * c
        r = self.c_e * n
        # eps (1 - nu eps)^2 = c_e N by fixed point: |c_e N| < 1e-3 here, so each pass
        # multiplies the error by about 2 nu c_e |N| < 1e-3 and three passes reach round-off.
        eps = r
        for _ in range(3):
            eps = r / (1.0 - self.nu * eps) ** 2
        p = 1.0 - self.nu * eps
        gamma = self.c_s * q / (p * p)
        dx = (1.0 + eps) * c - gamma * s
        dy = (1.0 + eps) * s + gamma * c
        return np.concatenate([dx, dy, m / p**4, -fy * dx + fx * dy])

    def shoot(self, unknowns, load):
        """Tips of both flexures at `unknowns` and its 4 forward-perturbed copies.

        Returns the tips (copies, 2 flexures, 4: a, b, phi, tip moment) and the tip forces
        (copies, 2 flexures, 2)."""
        copies = np.tile(unknowns, (5, 1))
        copies[1:] += FD_STEP * np.eye(4)
        f1 = copies[:, 0:2]
        f2 = load[None, 0:2] - f1
        fx = np.stack([f1[:, 0], f2[:, 0]], axis=1).reshape(-1)
        fy = np.stack([f1[:, 1], f2[:, 1]], axis=1).reshape(-1)
        m0 = copies[:, 2:4].reshape(-1)
        beams = m0.size
        y0 = np.concatenate([np.zeros(3 * beams), m0])
        sol = solve_ivp(self.rhs, (0.0, 1.0), y0, method="DOP853", rtol=RTOL, atol=ATOL,
                        args=(fx, fy))
        if sol.status != 0:
            raise RuntimeError(f"solve_ivp: {sol.message}")
        tips = sol.y[:, -1].reshape(4, 5, 2).transpose(1, 2, 0)
        forces = np.stack([f1, f2], axis=1)
        return tips, forces

    def equations(self, tips, forces, load):
        """The 4 equations per copy: clamp angle, clamp position (2), stage moment balance."""
        a1, b1, phi1, m1 = tips[:, 0].T
        a2, b2, phi2, m2 = tips[:, 1].T
        dx = a1 - a2                        # tip 1 minus tip 2, global
        dy = (self.w + b1) - (-self.w + b2)
        span = self.w - (-self.w)
        df = forces[:, 0] - forces[:, 1]
        moment = m1 + m2 + 0.5 * (dx * df[:, 1] - dy * df[:, 0]) - load[2]
        return np.stack([phi2 - phi1, dx + span * np.sin(phi1), dy - span * np.cos(phi1),
                         moment], axis=1)

    def residual(self, unknowns, load):
        """The equations and their forward-difference Jacobian, and the stage pose there."""
        tips, forces = self.shoot(unknowns, load)
        eqs = self.equations(tips, forces, load)
        a1, b1, phi1, _ = tips[0, 0]
        a2, b2, _, _ = tips[0, 1]
        stage = ((a1 + a2) / 2.0 - 1.0, ((self.w + b1) + (-self.w + b2)) / 2.0, phi1)
        return eqs[0], ((eqs[1:] - eqs[0]) / FD_STEP).T, stage

    def solve_case(self, guess, load):
        """Newton from `guess`; scipy.optimize.root (MINPACK hybrj) if Newton stalls.

        Returns (unknowns, stage pose)."""
        x = guess.copy()
        for _ in range(NEWTON_MAX):
            f, jac, stage = self.residual(x, load)
            step = np.linalg.solve(jac, f)
            x = x - step
            if not np.all(np.isfinite(x)):
                break
            if np.max(np.abs(step)) < NEWTON_TOL:
                # The pose is that of the last evaluation, NEWTON_TOL from x: the tip moves
                # by about that much, far below the integration tolerance.
                return x, stage
        sol = root(lambda u: self.residual(u, load)[:2], guess, jac=True, method="hybr",
                   options={"xtol": 1e-12})
        if not sol.success:
            raise RuntimeError(f"no equilibrium found at drive load {load}: {sol.message}")
        return sol.x, self.residual(sol.x, load)[2]

    def solve_drive(self, end, steps):
        """Every case of one drive path: [(dx, dy, dphi)]."""
        prev, prev2 = np.zeros(4), np.zeros(4)
        out = []
        for k in range(1, steps + 1):
            guess = 2.0 * prev - prev2 if k > 1 else prev
            x, stage = self.solve_case(guess, end * k / steps)
            prev2, prev = prev, x
            out.append(stage)
        return out

    def solve_all(self, steps, cases=None):
        """Every drive, in scene order; `cases` limits each drive to its first cases."""
        out = []
        for end in self.drives:
            out += self.solve_drive(end, steps)[:cases] if cases else self.solve_drive(end, steps)
        return out


def scene_text(steps):
    """The shipped parallel-stage scene with `steps` steps per drive."""
    text = (common.SCENES / "parallel-stage.toml").read_text()
    if text.count("steps = 8") != 2:
        raise RuntimeError("parallel-stage.toml changed: expected two drives of 8 steps")
    return text.replace("steps = 8", f"steps = {steps}")


def prbfit_side(binary, repeats):
    """The 1000-case stage scene written, and prbfit's `solve` of it timed (best of `repeats`)
    and checked to be the drives' loads in order: (stage, args, wall, own, cases)."""
    text = scene_text(STEPS)
    stage = Stage(tomllib.loads(text))
    scene = common.write_scene(text, "parallel-stage-1000.toml")
    args = ["solve", "--scene", scene, "--json"]
    wall, own, out = common.run_prbfit(binary, args, repeats)
    cases = out["cases"]
    loads = [end * k / STEPS for end in stage.drives for k in range(1, STEPS + 1)]
    if len(cases) != len(loads):
        raise RuntimeError(f"prbfit solved {len(cases)} cases, expected {len(loads)}")
    load_diff = max(float(np.max(np.abs(load - np.array(case["stage_load"]))))
                    for load, case in zip(loads, cases))
    if not load_diff <= 1e-9:
        raise RuntimeError(f"loads differ from prbfit's by {load_diff}")
    return stage, args, wall, own, cases


def max_stage_difference(poses, cases):
    """Largest |difference| between stage poses and prbfit's cases' (inf on NaN or a count
    mismatch)."""
    return common.max_difference(poses, [c["stage"] for c in cases])


def run(binary, repeats=3, prbfit_repeats=None):
    """Times both sides (best of `repeats`; prbfit of `prbfit_repeats`, default the same).

    Returns a dict for run.py's table."""
    stage, args, wall, own, cases = prbfit_side(binary, prbfit_repeats or repeats)
    n = len(cases)
    scipy_time, stages = common.best_of(repeats, lambda: stage.solve_all(STEPS))
    diff = max_stage_difference(stages, cases)
    # Each side's own error, against prbfit at tol 1e-12.
    _, _, ref = common.run_prbfit(binary, args + ["--tol", "1e-12"], 1)
    err_scipy = max_stage_difference(stages, ref["cases"])
    err_prbfit = max_stage_difference([c["stage"] for c in cases], ref["cases"])
    return {
        "job": f"parallel stage, {n} cases (2 drives x {STEPS})",
        "prbfit_wall": wall,
        "prbfit_own": own,
        "scipy": scipy_time,
        "scipy_note": f"solve_ivp DOP853 rtol {RTOL:g}, Newton on 4 unknowns, warm-started",
        "agreement": (f"max stage diff {diff:.1e} L/rad (error vs tol 1e-12: scipy "
                      f"{err_scipy:.1e}, prbfit {err_prbfit:.1e})"),
        "agree": diff < 1e-6,
        "goal": 3000,
        "prbfit_cmd": " ".join(str(a) for a in args),
    }


def main(argv=None):
    common.job_main(run, __doc__, argv)


if __name__ == "__main__":
    sys.exit(main())
