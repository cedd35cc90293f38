"""Type stubs of the native module ``flexmbs._native`` (Rust, PyO3). Users call the functions of
``flexmbs``; these are its building blocks."""

from typing import Any, Callable, Optional

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
