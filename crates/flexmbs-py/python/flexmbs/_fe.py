"""FE bodies from Python: modal analysis, reduction to a body file, reading body files."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping, Union

from . import _native
from ._model import Model, as_model

PathLike = Union[str, "os.PathLike[str]"]


def modal(body: Model | Mapping[str, Any] | PathLike, modes: int | None = None) -> dict[str, Any]:
    """Modal analysis of an FE body model (a file, or its data: the ``[body]`` table of an FE body
    file), as ``flexmbs modal``. ``modes``: elastic modes (default ``body.reduction.modes``).

    Returns a dict: ``frequencies_hz`` ``(k,)`` (0 for rigid-body modes), ``omega2`` ``(k,)`` in
    (rad/s)^2, ``labels`` ``(k,)`` (numpy array of ``str``, dtype object: dominant motion per mode,
    ``ux`` ... ``rz``), ``effective_mass_fraction``
    ``(k, 3)``, ``n_rigid``, ``nodes`` ``(N, 3)`` and ``modes`` ``(k, N, 3)`` (mass-normalised
    translations; ``rotations`` likewise, zero for solid nodes), in the body's units.
    """
    text, file, from_file = as_model(body)._source()
    return _native.modal(text, file, from_file, modes)


def reduce(body: Model | Mapping[str, Any] | PathLike, output: PathLike, *, geometric: bool = True) -> dict[str, Any]:
    """Reduces an FE body model as ``flexmbs reduce`` and writes the reduced-body file ``output``
    (``.fmb.h5``); a body with fixed nodes also gets its centrifugal geometric stiffness unless
    ``geometric=False``. Returns what was written (path, nodes, modes, ...)."""
    text, file, from_file = as_model(body)._source()
    return _native.reduce(text, file, from_file, str(output), geometric)


def read_body(path: PathLike) -> dict[str, Any]:
    """Reads a reduced-body file: ``nodes`` ``(N, 3)``, ``modes`` ``(k, N, 3)``, ``k_red`` and
    ``m_red`` ``(k, k)``, ``frequencies_hz`` (of the reduced model), ``labels`` ``(k,)`` (numpy
    array of ``str``, dtype object; ``static node <id> <direction>`` for a Craig-Bampton constraint
    mode), ``interface_nodes`` and ``fixed_nodes`` (indices into ``nodes``), ``units``, ``kind``."""
    return _native.read_body(str(Path(path)))
