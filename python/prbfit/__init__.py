"""prbfit: pseudo-rigid-body (PRB) models of compliant beams and mechanisms (DESIGN §12).

The same core as the ``prbfit`` command line: every result's ``to_dict()`` is the object the
CLI prints with ``--json`` for the same command and arguments, ``str(result)`` its text.

    import prbfit
    sc = prbfit.Scene.load("assets/scenes/steel-flexure.toml")
    sol = sc.solve()                      # Solution: .tips (n, 3), .shapes, .to_dict()
    r = sc.eval("su-3r")                  # Evaluation: .objective, .tips, .beam_tips
    f = sc.fit("L-R-R-R", fidelity="draft", seed=3)   # Fit: .matrix, .objective, ...
    m = prbfit.Matrix.parse("0.1,inf,inf; 0.9,2.2,inf"); m.to_numpy(); m.topology
    w = prbfit.Scene.load("assets/scenes/ringing-flexure.toml").modes("su-3r")
    w.beam_hz, w.hz[0], w.freq_err[0]    # Modes: numpy frequencies, beam's and each model's

Errors raise ``InputError`` (what the CLI exits 2 on) or ``SolveError`` (exit 1), both
subclasses of ``Error``, with the CLI's messages. Long calls release the GIL; Ctrl-C cancels
them.
"""

try:
    # The results' arrays are numpy's: without it the first array would fail deep inside the
    # core, so an install without numpy is refused here, at the import.
    import numpy as _numpy  # noqa: F401
except ImportError as _e:
    raise ImportError(f"prbfit needs numpy (pip install numpy): {_e}") from _e

from ._prbfit import (
    Calibration,
    Error,
    Evaluation,
    Export,
    Fea,
    Fit,
    InputError,
    Matrix,
    Modes,
    Report,
    Scene,
    Selection,
    Solution,
    SolveError,
    __version__,
)

__all__ = [
    "Calibration",
    "Error",
    "Evaluation",
    "Export",
    "Fea",
    "Fit",
    "InputError",
    "Matrix",
    "Modes",
    "Report",
    "Scene",
    "Selection",
    "Solution",
    "SolveError",
    "__version__",
]
