"""flexmbs: flexible multibody dynamics from Python.

Models are plain data mirroring the model files (:class:`Model`, :func:`load`), compiled and run
by the same Rust code as the ``flexmbs`` command (:func:`check`, :func:`run`); results come back
as numpy arrays (:class:`Results`, :func:`read_results`); :func:`sweep` runs parameter studies on
Rust threads. See ``docs/python.md``.
"""

from __future__ import annotations

from . import _native
from ._fe import modal, read_body, reduce
from ._errors import Error, IoError, ModelError, SolverError, UnknownSeriesError
from ._model import Model, check, load, split_key_path
from ._results import Results, read_results
from ._run import run
from ._sweep import grid, sweep

Progress = _native.Progress
__version__: str = _native.__version__

__all__ = [
    "Error",
    "IoError",
    "Model",
    "ModelError",
    "Progress",
    "Results",
    "SolverError",
    "UnknownSeriesError",
    "check",
    "grid",
    "load",
    "modal",
    "read_body",
    "reduce",
    "read_results",
    "run",
    "split_key_path",
    "sweep",
]
