"""The guide's example (docs/python.md) runs and writes its PNG."""

import runpy
import sys

from conftest import REPO


def test_thickness_sweep_example_writes_its_png(tmp_path, monkeypatch):
    out = tmp_path / "sweep.png"
    monkeypatch.setattr(sys, "argv", ["thickness_sweep.py", str(out)])
    runpy.run_path(str(REPO / "python" / "examples" / "thickness_sweep.py"), run_name="__main__")
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
