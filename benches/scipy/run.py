"""Runs the three scipy comparison jobs against one prbfit binary and prints one Markdown table.

Usage: python run.py PRBFIT_BINARY [--repeats N] [--prbfit-repeats N]
                     [--jobs beam,fit3r,parallelogram] [--bars]

`--bars` times the jobs against scipy as issue 24's earlier bars timed it (bars.py) instead of
the competent programs (beam.py, fit3r.py, parallelogram.py).

Every time is the best of N runs (default 3) in this one process, on this machine, in this
run: that is how issue 24 measures its ratios. prbfit is timed twice: the whole process
(`prbfit ... --json`, start-up and JSON output included) and the `seconds` its JSON reports
(the solve or fit alone, like the scipy side, which is timed inside Python and excludes the
interpreter's start-up and imports). A ratio counts only where the answers agree.
"""

import argparse
import datetime
import os
import platform
import sys
from pathlib import Path

import numpy
import scipy

import bars
import beam
import common
import fit3r
import parallelogram

JOBS = {"beam": beam.run, "fit3r": fit3r.run, "parallelogram": parallelogram.run}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binary", help="the prbfit binary (e.g. target/release/prbfit)")
    parser.add_argument("--repeats", type=int, default=3, help="best of N runs (default 3)")
    parser.add_argument("--prbfit-repeats", type=int, default=None,
                        help="best of N runs for prbfit's side (default: --repeats); prbfit's "
                        "runs take milliseconds, so more of them steady its figure on a busy "
                        "machine")
    parser.add_argument("--jobs", default=",".join(JOBS),
                        help="comma-separated subset of " + ", ".join(JOBS))
    parser.add_argument("--bars", action="store_true",
                        help="scipy as issue 24's earlier bars timed it (bars.py) instead of "
                        "the competent programs")
    args = parser.parse_args(argv)
    jobs = bars.JOBS if args.bars else JOBS
    binary = Path(args.binary).resolve()
    if not os.access(binary, os.X_OK):
        parser.error(f"{args.binary}: not an executable file")
    names = [j.strip() for j in args.jobs.split(",") if j.strip()]
    unknown = [j for j in names if j not in JOBS]
    if unknown:
        parser.error(f"--jobs: unknown job(s) {', '.join(unknown)} (expected {', '.join(JOBS)})")

    built = datetime.datetime.fromtimestamp(binary.stat().st_mtime, datetime.timezone.utc)
    print(f"prbfit: {binary} (modified {built:%Y-%m-%d %H:%M} UTC)")
    print(f"python {platform.python_version()}, numpy {numpy.__version__}, "
          f"scipy {scipy.__version__}; best of {args.repeats} "
          f"(prbfit: of {args.prbfit_repeats or args.repeats})")
    print("scipy: " + ("as issue 24's earlier bars timed it (bars.py)" if args.bars
                       else "the competent programs (beam.py, fit3r.py, parallelogram.py)"))
    print(f"load average at start: {common.load_average()}")
    results = []
    for name in names:
        print(f"running {name} ...", file=sys.stderr, flush=True)
        results.append(jobs[name](binary, args.repeats, args.prbfit_repeats or args.repeats))
    print(f"load average at end:   {common.load_average()}")
    print()
    print("| job | prbfit (process) | prbfit (own `seconds`) | scipy | ratio (process) "
          "| ratio (own) | issue 24's goal: prbfit (own) at most | agreement |")
    print("|---|---|---|---|---|---|---|---|")
    for r in results:
        if r["agree"]:
            ratios = (f"{r['scipy'] / r['prbfit_wall']:.0f}x",
                      f"{r['scipy'] / r['prbfit_own']:.0f}x")
        else:
            ratios = ("n/a: answers differ", "n/a")
        print(f"| {r['job']} | {common.fmt_seconds(r['prbfit_wall'])} | "
              f"{common.fmt_seconds(r['prbfit_own'])} | {common.fmt_seconds(r['scipy'])} | "
              f"{ratios[0]} | {ratios[1]} | {r['goal']}x: "
              f"{common.fmt_seconds(r['scipy'] / r['goal'])} | {r['agreement']} |")
    print()
    for r in results:
        print(f"- {r['job']}: scipy {r['scipy_note']}; prbfit `{r['prbfit_cmd']}`")
        for key, value in r.get("details", {}).items():
            print(f"  - {key}: {value}")
    return 0 if all(r["agree"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
