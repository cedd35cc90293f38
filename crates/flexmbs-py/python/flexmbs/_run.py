"""Running a model from Python."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Mapping, Optional, Union

from . import _native
from ._model import Model, as_model
from ._results import Results

PathLike = Union[str, "os.PathLike[str]"]


def run(
    model: Model | Mapping[str, Any] | PathLike,
    out_dir: PathLike | None = None,
    *,
    progress: Optional[Callable[[Any], object]] = None,
    progress_interval: float = 0.1,
) -> Results:
    """Runs a model (a :class:`Model`, a dict or a model file) and returns its :class:`Results`.

    Writes ``results.h5`` (and the animation, CSV and plots the model asks for) into ``out_dir``
    (default ``out/<model name>``, as ``flexmbs run``). The integration runs with the GIL
    released; ``progress(p)`` is called at most every ``progress_interval`` seconds with a
    :class:`Progress` (``t``, ``t_end``, ``steps``, ``newton_iterations``, ``h``, ``rejected``,
    ``fraction``). Ctrl-C stops the run after its current step: the results file is finished
    with status ``interrupted`` and ``KeyboardInterrupt`` is raised. An exception raised by
    ``progress`` stops the run the same way and is raised.

    Raises :class:`ModelError`, :class:`SolverError` (the results file keeps the steps before the
    failure, status ``failed``) or :class:`IoError`.
    """
    m = as_model(model)
    text, file, from_file = m._source()
    if out_dir is None:
        out_dir = Path("out") / (m.name or "run")
    summary = _native.run(text, file, from_file, str(out_dir), progress, progress_interval)
    return Results(_native.read(str(Path(out_dir) / "results.h5")), summary)
