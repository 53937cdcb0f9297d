"""Shared helpers: the repo, the shipped scenes, and the `prbfit` binary whose `--json`
output every result's `to_dict()` must equal."""

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = sorted((REPO / "assets" / "scenes").glob("*.toml"))


def _binary():
    env = os.environ.get("PRBFIT_BIN")
    if env:
        return pathlib.Path(env)
    # The newest build: a release binary left from an older commit must not be the judge.
    built = [REPO / "target" / p / "prbfit" for p in ("release", "debug")]
    built = [p for p in built if p.exists()]
    return max(built, key=lambda p: p.stat().st_mtime, default=None)


@pytest.fixture(scope="session")
def prbfit_bin():
    """The CLI binary (PRBFIT_BIN, or the newer of target/release and target/debug: `cargo
    build` first)."""
    b = _binary()
    if b is None:
        pytest.fail("no prbfit binary: run `cargo build` (or set PRBFIT_BIN) before pytest")
    return b


def timeless(v):
    """`v` without its wall-clock timings (keys naming seconds), the only part of a report
    that differs between two runs of the same command."""
    if isinstance(v, dict):
        return {k: timeless(x) for k, x in v.items() if "seconds" not in k}
    if isinstance(v, list):
        return [timeless(x) for x in v]
    return v


class Cli:
    """What the CLI did: its exit status, its JSON (status 0) or its one-line error."""

    def __init__(self, status, json_obj, error):
        self.status, self.json, self.error = status, json_obj, error


@pytest.fixture(scope="session")
def cli(prbfit_bin):
    def run(*args):
        p = subprocess.run(
            [str(prbfit_bin), *map(str, args), "--json"],
            capture_output=True,
            text=True,
            cwd=REPO,
        )
        if p.returncode == 0:
            return Cli(0, json.loads(p.stdout), None)
        err = p.stderr.strip()
        assert err.startswith("prbfit: "), err
        return Cli(p.returncode, None, err[len("prbfit: "):])

    return run
