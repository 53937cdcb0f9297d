"""Speed of the Python module (prints, asserts nothing):

1. per-call overhead: `Scene.solve(load)` from Python against the same report built in Rust
   alone (`Scene._rust_solve_seconds`), so the difference is what the module adds (argument
   parsing, the worker thread, the GIL released and taken back, the report to a result);
2. two fits on two threads against one fit (the GIL is released during the fit).

Each figure is the best of several batches (as timeit does): on a shared machine the mean
measures the neighbours.

    python python/benches/overhead.py
"""

import pathlib
import threading
import time

import prbfit

REPO = pathlib.Path(__file__).resolve().parents[2]


def best(f, n, batches=7):
    """The least mean seconds per call of `f` over `batches` batches of `n` calls."""
    out = []
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(n):
            f()
        out.append((time.perf_counter() - t0) / n)
    return min(out)


def per_call(n=300):
    # Effects given, so no `effects = "auto"` decision: one beam solve per call.
    sc = prbfit.Scene.builtin()
    sc.set_beam(effects="shear,extension")
    load = (0.0, 1.0, 0.3)
    sc.solve(load)  # warm
    # Rust and Python batches interleaved, so both meet the same neighbours.
    rust, py, py_dict = [], [], []
    for _ in range(9):
        rust.append(sc._rust_solve_seconds(load, n))
        py.append(best(lambda: sc.solve(load), n, batches=1))
        py_dict.append(best(lambda: sc.solve(load).to_dict(), n, batches=1))
    rust, py, py_dict = min(rust), min(py), min(py_dict)
    print(
        f"solve(load): Rust report {rust * 1e6:.1f} us; from Python {py * 1e6:.1f} us "
        f"(overhead {(py - rust) * 1e6:.1f} us); with to_dict() {py_dict * 1e6:.1f} us"
    )
    m = "0.1,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf"
    parse = best(lambda: prbfit.Matrix.parse(m).to_numpy(), 10 * n)
    print(f"Matrix.parse + to_numpy (no worker thread): {parse * 1e6:.1f} us")


def threads():
    sc = prbfit.Scene.load(REPO / "assets" / "scenes" / "steel-flexure.toml")
    fit = lambda: sc.fit("L-R-R-R", fidelity="draft", seed=7)  # noqa: E731
    fit()
    one = best(fit, 1, batches=3)

    def two_fits():
        ts = [threading.Thread(target=fit) for _ in range(2)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    two = best(two_fits, 1, batches=3)
    print(f"one fit {one:.3f} s; two fits on two threads {two:.3f} s ({two / one:.2f}x one)")
    # The GIL released, seen without a second free core: Python keeps running on this thread
    # while a fit runs on another (with the GIL held the count would stay near zero).
    t = threading.Thread(target=fit)
    count = 0
    t0 = time.perf_counter()
    t.start()
    while t.is_alive():
        count += 1
    print(f"during a {time.perf_counter() - t0:.3f} s fit on another thread this thread ran "
          f"{count} Python loop iterations")


if __name__ == "__main__":
    per_call()
    threads()
