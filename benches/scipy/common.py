"""Shared helpers of the scipy comparison harness: scenes, timing, running prbfit.

Everything here is plain Python; the numerical work lives in beam.py, fit3r.py and
parallelogram.py. Nondimensional units throughout (DESIGN §1: L = 1, E I0 = 1).
"""

import argparse
import json
import math
import os
import subprocess
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "assets" / "scenes"

# The built-in scene's four load paths (assets/scenes/default.toml): end loads
# (alpha_x, alpha_y, beta). The beam and fit jobs use these paths, with effects = [].
DEFAULT_PATHS = [
    (0.0, 5.0, 0.0),        # transverse force
    (-2.1213, 2.1213, 0.0), # force at 135 degrees, pushing back
    (0.0, 0.0, 2.0),        # pure tip moment
    (-1.0, 3.0, 1.0),       # force and moment together
]


def cases_along(paths, steps):
    """The load cases of proportional paths, k/steps of each end load, k = 1..steps (DESIGN §5).

    Returns a list of paths, each a list of (alpha_x, alpha_y, beta)."""
    return [[(ax * k / steps, ay * k / steps, b * k / steps) for k in range(1, steps + 1)]
            for (ax, ay, b) in paths]


def elastica_scene(paths, steps, name):
    """The built-in beam (slenderness 100, spring steel) as the plain elastica (effects = [])."""
    lines = [
        f'name = "{name}"',
        "[beam]",
        "length = 0.05",
        "width = 0.01",
        "thickness = 0.0005",
        "youngs_modulus = 200e9",
        "poisson_ratio = 0.3",
        "effects = []",
    ]
    for (ax, ay, b) in paths:
        lines += ["[[loads]]", f"alpha_x = {ax!r}", f"alpha_y = {ay!r}", f"beta = {b!r}",
                  f"steps = {steps}"]
    lines += ["[accuracy]", "max_pos_err = 0.01", "max_ang_err = 0.02", "[fit]",
              "angle_weight = 1.0"]
    return "\n".join(lines) + "\n"


def write_scene(text, filename):
    """Writes a generated scene into a fresh temporary directory; returns its path."""
    d = Path(tempfile.mkdtemp(prefix="prbfit-scipy-"))
    path = d / filename
    path.write_text(text)
    return path


def run_prbfit(binary, args, repeats):
    """Runs `binary args` `repeats` times.

    Returns (best wall seconds, best of the `seconds` the JSON reports, parsed JSON of the last
    run); the wall time is the whole process (start-up, scene parsing, JSON output included),
    and the JSON's `seconds` (None when it has none) is prbfit's own timing of its work."""
    best = math.inf
    own = math.inf
    out = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        proc = subprocess.run([str(binary)] + [str(a) for a in args], capture_output=True,
                              text=True, check=False)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"prbfit {' '.join(map(str, args))} exited {proc.returncode}: "
                               f"{proc.stderr.strip()}")
        out = json.loads(proc.stdout)
        best = min(best, wall)
        if "seconds" in out:
            own = min(own, out["seconds"])
    return best, (own if math.isfinite(own) else None), out


def max_difference(mine, theirs):
    """Largest |difference| of two equally long lists of equally long tuples; inf on any NaN
    or a length mismatch, so that no comparison passes by having nothing to compare."""
    if len(mine) != len(theirs) or not mine:
        return math.inf
    worst = 0.0
    for u, v in zip(mine, theirs):
        if len(u) != len(v):
            return math.inf
        for a, b in zip(u, v):
            d = abs(a - b)
            if not d <= worst:
                worst = d if d == d else math.inf
    return worst


def check_loads(loads, cases):
    """prbfit's `solve` cases are `loads` (alpha_x, alpha_y, beta), in order."""
    if len(loads) != len(cases) or any(
            max(abs(c["load"]["alpha_x"] - l[0]), abs(c["load"]["alpha_y"] - l[1]),
                abs(c["load"]["beta"] - l[2])) > 1e-12 for l, c in zip(loads, cases)):
        raise RuntimeError(f"prbfit's {len(cases)} cases are not the scene's {len(loads)} "
                           "loads in order")


def best_of(repeats, job):
    """Runs `job()` `repeats` times; returns (best seconds, result of the last run)."""
    best = math.inf
    result = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = job()
        best = min(best, time.perf_counter() - t0)
    return best, result


def load_average():
    """The machine's 1, 5 and 15 minute load averages, as text."""
    one, five, fifteen = os.getloadavg()
    return f"{one:.2f} {five:.2f} {fifteen:.2f} (1/5/15 min, {os.cpu_count()} cores)"


def fmt_seconds(s):
    """Seconds as us below 1 ms, ms below 1 s, else s."""
    if s < 1e-3:
        return f"{s * 1e6:.0f} us"
    return f"{s * 1e3:.1f} ms" if s < 1.0 else f"{s:.2f} s"


def job_main(run, doc, argv=None):
    """The command line of one job run alone: `python JOB.py BINARY [--repeats N]`, printing
    the job's result fields."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("binary")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    r = run(args.binary, args.repeats)
    for k, v in r.items():
        print(f"{k}: {v}")
