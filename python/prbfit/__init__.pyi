"""Type stubs for prbfit (the native module prbfit._prbfit, re-exported)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike]
_Rows = Union[Sequence[Sequence[float]], npt.NDArray[np.float64]]
_Model = Union[str, "Matrix", _Rows]

class Error(Exception):
    """Anything prbfit refuses or fails at."""

class InputError(Error):
    """Bad input (the CLI's exit status 2): the message names the argument, file or key."""

class SolveError(Error):
    """A failed computation (the CLI's exit status 1)."""

class Matrix:
    """A PRB matrix: rows [gamma, k_theta, k_ex] or [gamma, k_theta, k_ex, mu] from the root,
    inf for no joint; without mus each segment's mass is where its length is (mu = gamma)."""

    def __init__(self, rows: Union[_Rows, str, "Matrix"], fixed: Optional[Sequence[Sequence[bool]]] = None) -> None: ...
    @staticmethod
    def parse(text: str) -> "Matrix": ...
    @staticmethod
    def from_topology(name: str) -> "Matrix": ...
    def to_numpy(self) -> npt.NDArray[np.float64]:
        """(N, 4) [gamma, k_theta, k_ex, mu], inf where there is no joint; mu = gamma where
        the matrix gives no mus (has_mu False)."""
    @property
    def has_mu(self) -> bool:
        """Whether the matrix gives its mus (a fourth column)."""
    @property
    def fixed(self) -> npt.NDArray[np.bool_]:
        """(N, 4) the cells a fit keeps (`!` in the text form)."""
    @property
    def topology(self) -> str: ...
    @property
    def text(self) -> str: ...
    def __len__(self) -> int: ...
    def __eq__(self, other: object) -> bool: ...

class Report:
    """A command's result: to_dict() is the CLI's --json object, str() its text; every
    top-level key is also an attribute (the figures)."""

    def to_dict(self) -> Dict[str, Any]: ...
    def keys(self) -> List[str]: ...
    def __getattr__(self, name: str) -> Any: ...

class Solution(Report):
    @property
    def tips(self) -> npt.NDArray[np.float64]:
        """(n, 3) [a, b, phi] per case (a mechanism's: flexure 1's tip)."""
    @property
    def stages(self) -> npt.NDArray[np.float64]:
        """(n, 3) a mechanism's stage [dx, dy, dphi] per case."""
    @property
    def shapes(self) -> List[npt.NDArray[np.float64]]:
        """(m, 3) [x, y, psi] per case, with shape=True."""

class Evaluation(Report):
    @property
    def tips(self) -> Union[npt.NDArray[np.float64], List[npt.NDArray[np.float64]]]: ...
    @property
    def beam_tips(self) -> Union[npt.NDArray[np.float64], List[npt.NDArray[np.float64]]]: ...

class Fit(Report):
    @property
    def matrix(self) -> Matrix: ...
    objective: float
    max_pos_err: float
    max_ang_err: float
    rms_pos_err: float
    rms_ang_err: float
    meets_targets: bool

class Selection(Report):
    @property
    def chosen_matrix(self) -> Optional[Matrix]: ...

class Calibration(Report): ...
class Export(Report): ...

class Fea(Report):
    @property
    def tips(self) -> npt.NDArray[np.float64]:
        """(n, 3) the FEA's tips per case; a mechanism's: its stage [dx, dy, dphi]."""
    @property
    def beam_tips(self) -> npt.NDArray[np.float64]:
        """(n, 3) the beam's tips beside them; (0, 3) for a mechanism (its differences are
        in to_dict())."""

class Modes(Report):
    """Natural frequencies of the truth and of each model about the same equilibria.
    Arrays are (count,) for one equilibrium, (n, count) with cases=True; NaN where a model
    has no such frequency."""

    @property
    def beam_omega(self) -> npt.NDArray[np.float64]: ...
    @property
    def beam_hz(self) -> npt.NDArray[np.float64]: ...
    @property
    def omega(self) -> List[npt.NDArray[np.float64]]:
        """One array per model, in the order of `models`."""
    @property
    def hz(self) -> List[npt.NDArray[np.float64]]: ...
    @property
    def freq_err(self) -> List[npt.NDArray[np.float64]]:
        """Omega_PRB / Omega_beam - 1 per frequency, one array per model."""
    @property
    def loads(self) -> npt.NDArray[np.float64]:
        """(n, 3) the equilibria's tip (stage) loads [alpha_x, alpha_y, beta]."""
    density: float
    hz_per_omega: float
    max_freq_err: float
    equilibrium: str

class Scene:
    """A scene: beam (or mechanism, or measured data), load paths, targets, model."""

    @staticmethod
    def load(path: _Path) -> "Scene": ...
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> "Scene": ...
    @staticmethod
    def builtin() -> "Scene": ...
    name: str
    @property
    def kind(self) -> str: ...
    @property
    def beam(self) -> Dict[str, Any]:
        """length, width, thickness, youngs_modulus, poisson_ratio, shear_coefficient,
        effects, density, allowable_stress (SI), slenderness."""
    def set_beam(self, **values: Any) -> None: ...
    def with_beam(self, **values: Any) -> "Scene": ...
    @property
    def body(self) -> Dict[str, float]:
        """The [tip] body (a mechanism's [stage]): mass (kg), inertia (kg m^2)."""
    def set_body(self, *, mass: float = ..., inertia: float = ...) -> None: ...
    @property
    def fit_settings(self) -> Dict[str, Any]:
        """[fit]: angle_weight, force_weight, modes, frequency_weight."""
    def set_fit_settings(
        self,
        *,
        angle_weight: float = ...,
        force_weight: float = ...,
        modes: int = ...,
        frequency_weight: float = ...,
    ) -> None: ...
    @property
    def accuracy(self) -> Dict[str, float]:
        """[accuracy]: max_pos_err, max_ang_err, max_force_err, max_freq_err."""
    def set_accuracy(
        self,
        *,
        max_pos_err: float = ...,
        max_ang_err: float = ...,
        max_force_err: float = ...,
        max_freq_err: float = ...,
    ) -> None: ...
    loads: List[Tuple[float, float, float, int]]
    matrix: Optional[Matrix]
    def validate(self) -> None: ...
    def to_toml(self) -> str: ...
    def copy(self) -> "Scene": ...
    def solve(
        self,
        load: Optional[Sequence[float]] = None,
        *,
        effects: Optional[str] = None,
        slenderness: Optional[float] = None,
        nu: Optional[float] = None,
        kappa: Optional[float] = None,
        tol: Optional[float] = None,
        shape: bool = False,
    ) -> Solution: ...
    def eval(self, *models: _Model, load: Optional[Sequence[float]] = None, tol: Optional[float] = None) -> Evaluation: ...
    def fit(
        self,
        topology: Optional[str] = None,
        *,
        matrix: Optional[_Model] = None,
        fidelity: str = "normal",
        seed: int = 1,
        output: Optional[_Path] = None,
        force: bool = False,
        progress: Optional[Callable[[Dict[str, Any]], Any]] = None,
    ) -> Fit: ...
    def modes(
        self,
        *models: _Model,
        count: int = 3,
        load: Optional[Sequence[float]] = None,
        cases: bool = False,
        tol: Optional[float] = None,
    ) -> Modes: ...
    def select(self, fidelity: str = "normal", *, within_stroke: bool = False) -> Selection: ...
    def calibrate(self, param: str = "youngs_modulus") -> Calibration: ...
    def export(
        self,
        model: Optional[_Model] = None,
        output: Optional[_Path] = None,
        *,
        format: Optional[str] = None,
        force: bool = False,
        density: Optional[float] = None,
        fidelity: str = "normal",
    ) -> Export: ...
    def fea(
        self,
        output: _Path,
        *,
        mesh: int = 40,
        section: Optional[str] = None,
        taper: float = 1.0,
        deck: Optional[_Path] = None,
        force: bool = False,
        timeout: int = 900,
    ) -> Fea: ...
