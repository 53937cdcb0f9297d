"""The guide's worked example (docs/python.md): sweep a steel flexure's thickness, fit a 3R
model at each, and plot the fitted spring constants against slenderness L/t.

    python python/examples/thickness_sweep.py [OUTPUT.png]

Writes docs/python-sweep.png by default. The pytest suite runs it (python/tests/test_example.py).
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import prbfit  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]


def sweep(thicknesses_mm, fidelity="draft"):
    """Per thickness: the slenderness and the fitted 3R matrix as numpy."""
    base = prbfit.Scene.load(REPO / "assets" / "scenes" / "steel-flexure.toml")
    rows = []
    for t in thicknesses_mm:
        sc = base.with_beam(thickness=t * 1e-3)
        fit = sc.fit("L-R-R-R", fidelity=fidelity, seed=1)
        rows.append((sc.beam["slenderness"], fit.matrix.to_numpy(), fit.max_pos_err))
        print(
            f"t = {t:.2f} mm  L/t = {sc.beam['slenderness']:6.1f}  {fit.matrix}  "
            f"max pos err {fit.max_pos_err:.2e} L"
        )
    return rows


def plot(rows, out):
    slenderness = np.array([r[0] for r in rows])
    # Column 1 of the matrix holds k_theta; the first row is the rigid root (inf).
    springs = np.array([r[1][1:, 1] for r in rows])
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    for j in range(springs.shape[1]):
        ax.plot(slenderness, springs[:, j], "o-", label=f"joint {j + 1}")
    ax.set_xscale("log")
    ax.set_xlabel("slenderness L/t")
    ax.set_ylabel("fitted k_theta (units of E I / L)")
    ax.set_title("3R model of a steel flexure, fitted per thickness")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def main(argv):
    out = pathlib.Path(argv[1]) if len(argv) > 1 else REPO / "docs" / "python-sweep.png"
    rows = sweep([0.2, 0.3, 0.5, 0.8, 1.2, 2.0])
    plot(rows, out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv)
