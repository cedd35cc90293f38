"""Parameter studies: :func:`sweep` runs variants of a model on Rust threads."""

from __future__ import annotations

import itertools
import os
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any, Mapping, Sequence, Union

import numpy as np

from . import _native
from ._model import Model, as_model

PathLike = Union[str, "os.PathLike[str]"]

STATISTICS = ("final", "max", "min", "absmax", "mean")
_OUTPUT = re.compile(r"^\s*(final|max|min|absmax|mean)\s*\(\s*(.+?)\s*\)\s*$")


def parse_output(spec: str) -> tuple[str, str]:
    """``"max(tip.position.z)"`` -> ``("tip.position.z", "max")``; a bare series name is its final
    value."""
    m = _OUTPUT.match(spec)
    return (m.group(2), m.group(1)) if m else (spec.strip(), "final")


def grid(parameters: Mapping[str, Sequence[Any]]) -> dict[str, list[Any]]:
    """Every combination of the values (a full factorial design), as the equal-length lists
    :func:`sweep` takes: ``grid({"a": [1, 2], "b": [3, 4]})`` has 4 variants."""
    keys = list(parameters)
    combos = list(itertools.product(*(list(parameters[k]) for k in keys)))
    return {k: [c[i] for c in combos] for i, k in enumerate(keys)}


def variants(model: Model, parameters: Mapping[str, Sequence[Any]]) -> list[Model]:
    """The models of a sweep: variant ``k`` sets every key path to its ``k``-th value."""
    lengths = {k: len(v) for k, v in parameters.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"every parameter needs the same number of values (zip), got {lengths}; use flexmbs.grid(...) for all combinations")
    n = next(iter(lengths.values()), 0)
    out = []
    for k in range(n):
        v = model.copy()
        for key, values in parameters.items():
            v[key] = values[k]
        out.append(v)
    return out


def _column(values: Sequence[Any]) -> np.ndarray:
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return np.asarray(values, dtype=object)


def sweep(
    model: Model | Mapping[str, Any] | PathLike,
    parameters: Mapping[str, Sequence[Any]],
    outputs: Sequence[str],
    *,
    workers: int | None = None,
    out_dir: PathLike | None = None,
    keep_files: bool = False,
    as_pandas: bool = False,
) -> Any:
    """Runs variants of a model in parallel on Rust threads and returns a table of outputs.

    ``parameters`` maps key paths to equal-length value lists (variant ``k`` takes the ``k``-th
    value of each; :func:`grid` makes all combinations), e.g. ``{"body[link2].mass": ["1 kg",
    "2 kg"]}``. ``outputs`` names what to keep of each run: ``"max(tip.position.z)"``,
    ``"min(...)"``, ``"absmax(...)"``, ``"mean(...)"``, ``"final(...)"`` or a bare series name (its
    final value), in SI units. ``workers`` defaults to the number of CPUs.

    Returns a dict of numpy arrays (one row per variant): a column per parameter key path, one
    per output spec, ``status`` (``completed``, ``interrupted``, ``failed`` for a solver failure,
    ``invalid`` for a model the compiler rejects, ``error``) and ``message``; outputs of failed
    variants are NaN. ``as_pandas=True`` returns a ``pandas.DataFrame``. The variants' CSV,
    plots and animation are switched off; their results files go to ``out_dir/variant_<k>``
    (default a temporary folder, removed unless ``keep_files``). Ctrl-C stops the running
    variants and raises ``KeyboardInterrupt``.
    """
    base = as_model(model)
    models = variants(base, parameters)
    for v in models:
        v["output.csv"] = None
        v["output.plots"] = None
        v["output.animation"] = False
    texts = [v._source()[0] for v in models]
    file = base._source()[1]
    specs = list(outputs)
    pairs = [parse_output(s) for s in specs]
    if workers is None:
        workers = os.cpu_count() or 1
    temporary = out_dir is None
    root = Path(tempfile.mkdtemp(prefix="flexmbs-sweep-")) if temporary else Path(out_dir)
    try:
        table, status, message = _native.sweep(texts, file, str(root), pairs, int(workers))
    finally:
        if temporary and not keep_files:
            shutil.rmtree(root, ignore_errors=True)
    out: dict[str, np.ndarray] = {k: _column(v) for k, v in parameters.items()}
    for j, spec in enumerate(specs):
        out[spec] = table[:, j]
    out["status"] = np.asarray(status, dtype=object)
    out["message"] = np.asarray(message, dtype=object)
    if as_pandas:
        import pandas as pd

        return pd.DataFrame(out)
    return out
