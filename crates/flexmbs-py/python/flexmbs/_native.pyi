"""Type stubs of the native module ``flexmbs._native`` (Rust, PyO3). Users call the functions of
``flexmbs``; these are its building blocks."""

from typing import Any, Callable, Optional, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class Progress:
    """Progress of a run, handed to the ``progress`` callback of :func:`flexmbs.run`."""

    t: float
    """Simulated time in s (statics: load factor)."""
    t_end: float
    """End time in s (statics: 1)."""
    steps: int
    """Accepted steps."""
    newton_iterations: int
    """Newton iterations (implicit solvers) or function evaluations (explicit) so far."""
    h: float
    """Last step size in s."""
    rejected: int
    """Rejected steps so far (adaptive solvers)."""
    @property
    def fraction(self) -> float:
        """Fraction of the run done, 0..1."""

class NativeResults:
    def time(self) -> npt.NDArray[np.float64]: ...
    def names(self) -> list[str]: ...
    def column(self, name: str) -> npt.NDArray[np.float64]: ...
    def group(self, name: str) -> Optional[npt.NDArray[np.float64]]: ...
    def group_columns(self, name: str) -> list[str]: ...
    def signals(self) -> list[tuple[str, str, list[str]]]: ...
    def rows(self) -> int: ...
    def model(self) -> str: ...
    def path(self) -> str: ...
    def status(self) -> tuple[str, Optional[float], Optional[str]]: ...
    def attributes(self) -> dict[str, str]: ...

def toml_loads(text: str, file: str) -> dict[str, Any]: ...
def toml_dumps(data: dict[str, Any]) -> str: ...
def check(text: str, file: str, from_file: bool) -> dict[str, Any]: ...
def run(
    text: str,
    file: str,
    from_file: bool,
    out_dir: str,
    progress: Optional[Callable[[Progress], object]] = None,
    interval: float = 0.1,
) -> dict[str, Any]: ...
def read(path: str) -> NativeResults: ...
def sweep(
    texts: list[str], file: str, out_root: str, outputs: list[tuple[str, str]], workers: int
) -> tuple[npt.NDArray[np.float64], list[str], list[str]]: ...

class ModalResult(TypedDict):
    """What :func:`modal` returns (``k`` modes, ``N`` nodes, the body's units)."""

    name: str
    frequencies_hz: npt.NDArray[np.float64]
    """``(k,)``, 0 for rigid-body modes."""
    omega2: npt.NDArray[np.float64]
    """``(k,)`` in (rad/s)^2."""
    labels: npt.NDArray[np.object_]
    """``(k,)`` ``str`` objects: the dominant motion of each mode (``ux`` ... ``rz``)."""
    effective_mass_fraction: npt.NDArray[np.float64]
    """``(k, 3)``."""
    n_rigid: int
    nodes: npt.NDArray[np.float64]
    """``(N, 3)``."""
    modes: npt.NDArray[np.float64]
    """``(k, N, 3)`` mass-normalised translations."""
    rotations: npt.NDArray[np.float64]
    """``(k, N, 3)``, zero for nodes without rotations."""
    elements: int
    independent_dofs: int

class ReduceResult(TypedDict):
    """What :func:`reduce` returns: what was written."""

    path: str
    nodes: int
    modes: int
    geometric_load_patterns: int
    rotary_inertia: bool

class BodyFileData(TypedDict):
    """What :func:`read_body` returns (``k`` basis vectors, ``N`` nodes, the body's units)."""

    name: str
    units: str
    kind: str
    nodes: npt.NDArray[np.float64]
    """``(N, 3)``."""
    node_ids: list[int]
    modes: npt.NDArray[np.float64]
    """``(k, N, 3)``."""
    rotations: Optional[npt.NDArray[np.float64]]
    """``(k, N, 3)``, ``None`` for a body without rotations."""
    k_red: npt.NDArray[np.float64]
    """``(k, k)``."""
    m_red: npt.NDArray[np.float64]
    """``(k, k)``."""
    frequencies_hz: npt.NDArray[np.float64]
    """``(k,)``, the frequencies of the reduced model."""
    labels: npt.NDArray[np.object_]
    """``(k,)`` ``str`` objects: the dominant motion per mode, or ``static node <id> <dir>`` for
    a Craig-Bampton constraint mode."""
    interface_nodes: list[int]
    """Indices into ``nodes``."""
    fixed_nodes: list[int]
    """Indices into ``nodes``."""
    geometric_load_patterns: int

def modal(text: str, file: str, from_file: bool, modes: Optional[int] = None) -> ModalResult: ...
def reduce(text: str, file: str, from_file: bool, output: str, geometric: bool = True) -> ReduceResult: ...
def read_body(path: str) -> BodyFileData: ...
