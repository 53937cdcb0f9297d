"""Speed of the Python module (prints, asserts nothing):

1. per-call overhead: `Scene.solve(load)` from Python against the same report built in Rust
   alone (`Scene._rust_solve_seconds`), so the difference is what the module adds (argument
   parsing, the worker thread, the GIL released and taken back, the report to a result);
2. two fits on two threads against one fit (the GIL is released during the fit).

    python python/benches/overhead.py
"""

import pathlib
import threading
import time

import prbfit

REPO = pathlib.Path(__file__).resolve().parents[2]


def per_call(n=2000):
    # Effects given, so no `effects = "auto"` decision: one beam solve per call.
    sc = prbfit.Scene.builtin()
    sc.set_beam(effects="shear,extension")
    load = (0.0, 1.0, 0.3)
    sc.solve(load)  # warm
    rust = sc._rust_solve_seconds(load, n)
    t0 = time.perf_counter()
    for _ in range(n):
        sc.solve(load)
    py = (time.perf_counter() - t0) / n
    t0 = time.perf_counter()
    for _ in range(n):
        sc.solve(load).to_dict()
    py_dict = (time.perf_counter() - t0) / n
    print(f"solve(load): Rust report {rust * 1e6:.1f} us; from Python {py * 1e6:.1f} us "
          f"(overhead {(py - rust) * 1e6:.1f} us); with to_dict() {py_dict * 1e6:.1f} us")
    m = "0.1,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf"
    t0 = time.perf_counter()
    for _ in range(n):
        prbfit.Matrix.parse(m).to_numpy()
    print(f"Matrix.parse + to_numpy: {(time.perf_counter() - t0) / n * 1e6:.1f} us")


def threads():
    sc = prbfit.Scene.load(REPO / "assets" / "scenes" / "steel-flexure.toml")
    fit = lambda: sc.fit("L-R-R-R", fidelity="draft", seed=7)  # noqa: E731
    fit()
    t0 = time.perf_counter()
    fit()
    one = time.perf_counter() - t0
    ts = [threading.Thread(target=fit) for _ in range(2)]
    t0 = time.perf_counter()
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    two = time.perf_counter() - t0
    print(f"one fit {one:.2f} s; two fits on two threads {two:.2f} s ({two / one:.2f}x one)")


if __name__ == "__main__":
    per_call()
    threads()
