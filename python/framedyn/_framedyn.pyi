"""Type stubs of the extension module ``framedyn._framedyn`` (Rust, pyo3).

Use the wrappers of the ``framedyn`` package; this module is their thin
native layer.
"""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "Scene",
    "Stepper",
    "__version__",
    "_debug_assertions",
    "_raise_for_test",
    "chaos_map",
    "cli_main",
    "initial_fields",
    "lyapunov",
    "manifolds",
    "megno",
    "methods",
    "run",
    "run_batch",
    "run_table",
    "sali",
    "gali",
    "section",
    "write_records",
]
__version__: str
# True in a development build (`maturin develop`: the dev profile).
_debug_assertions: bool

_UserPotential = Callable[[npt.NDArray[np.float64], npt.NDArray[np.float64]], float]
_UserGradient = Callable[[npt.NDArray[np.float64], npt.NDArray[np.float64]], Tuple[Any, Any]]

@final
class Scene:
    """A parsed scene (see ``framedyn.Scene``)."""

    @staticmethod
    def from_toml(text: str) -> Scene: ...
    @staticmethod
    def from_json(text: str) -> Scene: ...
    @staticmethod
    def example(name: str) -> Scene: ...
    @staticmethod
    def example_names() -> List[str]: ...
    def to_toml(self) -> str: ...
    def to_json(self) -> str: ...
    def validate(self) -> None: ...
    def columns(self) -> List[Tuple[str, str]]: ...
    def __eq__(self, other: object, /) -> bool: ...

@final
class Stepper:
    """A built scene advanced step by step (see ``framedyn.Stepper``)."""

    def __new__(
        cls, scene: Scene, user_potential: Optional[_UserPotential] = None, user_gradient: Optional[_UserGradient] = None
    ) -> Stepper: ...
    def step(self, h: float) -> None: ...
    def advance(self, h: float, n: int) -> None: ...
    @property
    def t(self) -> float: ...
    @property
    def energy(self) -> float: ...
    @property
    def defect(self) -> float: ...
    @property
    def energy_drift(self) -> float: ...
    @property
    def max_defect(self) -> float: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def span(self) -> Tuple[float, float]: ...
    @property
    def method(self) -> str: ...
    @property
    def columns(self) -> List[Tuple[str, str]]: ...
    def row(self) -> npt.NDArray[np.float64]: ...
    def reset(self) -> None: ...

def run(
    scene: Scene,
    user_potential: Optional[_UserPotential] = None,
    events: Optional[Sequence[Tuple[str, Callable[[float, Dict[str, float]], float], str, bool]]] = None,
    user_gradient: Optional[_UserGradient] = None,
) -> Dict[str, Any]:
    """One run: ``{"data": (n, columns) array, "columns", "units", "summary", "events"}``."""

def run_batch(
    scenes: Sequence[Scene],
    user_potential: Optional[_UserPotential] = None,
    threads: Optional[int] = None,
    user_gradient: Optional[_UserGradient] = None,
    oversubscribe: bool = False,
) -> List[Union[Dict[str, Any], BaseException]]:
    """Parallel runs: per scene the result dict or its exception."""

def run_table(
    scene: Scene,
    names: List[str],
    columns: List[Any],
    keep: str = "all",
    samples: Optional[int] = None,
    threads: Optional[int] = None,
    user_potential: Optional[_UserPotential] = None,
    user_gradient: Optional[_UserGradient] = None,
    oversubscribe: bool = False,
) -> Dict[str, Any]:
    """A columnar ensemble: the stacked records, offsets, statuses and summaries."""

def _raise_for_test(kind: str, message: str) -> None: ...

def cli_main(argv: List[str]) -> int: ...
def methods() -> List[Dict[str, Any]]: ...
def manifolds() -> Dict[str, Dict[str, List[str]]]: ...
def initial_fields() -> List[str]: ...
def write_records(
    path: str, format: str, columns: List[str], units: List[str], data: npt.NDArray[np.float64]
) -> None: ...

def lyapunov(
    scene: Scene,
    exponents: Optional[int],
    every: int,
    transient: float,
    batches: int,
    seed: int,
    eps: Optional[float],
    fourth_order: bool,
    two_trajectory: bool,
    quotient: bool,
    differenced: bool = False,
) -> Dict[str, Any]:
    """Lyapunov exponents: ``{"exponents", "stderr", "spread", "times", "running", "steps", "steps_per_step", "exact_tangents", "state_dimension", "dimension", "two_trajectory"}``."""

def section(scene: Scene, spec_json: str) -> Dict[str, Any]:
    """Poincaré section: ``{"name", "columns", "units", "data", "rising"}``."""

def sali(
    scene: Scene, threshold: float, seed: int, eps: Optional[float] = None, fourth_order: bool = False, differenced: bool = False
) -> Tuple[float, Optional[float], float, int, bool]:
    """Smaller Alignment Index: ``(sali, chaotic_at, min, steps, exact_tangents)``."""

def gali(
    scene: Scene, k: Optional[int], threshold: float, seed: int, eps: Optional[float], fourth_order: bool, quotient: bool, differenced: bool = False
) -> Dict[str, Any]:
    """GALI_k: ``{"k", "gali", "log10", "below_at", "times", "running_log10", "steps", "steps_per_step", "dimension", "exact_tangents"}``."""
    ...

def megno(scene: Scene, seed: int, eps: Optional[float], fourth_order: bool, differenced: bool = False) -> Dict[str, Any]:
    """MEGNO: ``{"megno", "mean", "slope", "lyapunov", "times", "running_megno", "running_mean", "steps", "steps_per_step", "exact_tangents"}``."""

def chaos_map(
    scene: Scene,
    names: List[str],
    columns: List[Any],
    sali: bool,
    megno: bool,
    gali: Optional[int],
    threshold: float,
    gali_threshold: float,
    gali_quotient: bool,
    seed: int,
    eps: Optional[float],
    fourth_order: bool,
    threads: Optional[int],
    oversubscribe: bool,
    differenced: bool = False,
) -> Dict[str, Any]:
    """SALI, MEGNO and GALI_k of every member of a table: ``{"sali", "sali_min", "chaotic_at", "sali_steps", "megno", "megno_mean", "megno_slope", "lyapunov", "megno_steps", "gali_log10", "gali_below_at", "gali_steps", "status", "status_names", "errors"}``."""
