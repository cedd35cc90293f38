"""Results of a run: :class:`Results` reads ``results.h5`` (the file ``flexmbs run`` writes)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Union

import numpy as np

from . import _native

PathLike = Union[str, "os.PathLike[str]"]

#: Groups of columns returned by :meth:`Results.series` as 2-D arrays.
GROUPS = ("q", "u", "lambda", "energy", "drift", "step", "signals")

_FIXED_UNITS = {
    "energy": "J",
    "step/h": "s",
    "step/iterations": "",
    "step/residual": "",
}


class Results:
    """The content of a results file, all values in SI units.

    Shapes (``n`` output rows):

    * ``time``: ``(n,)`` in s (statics: the load factor);
    * ``series("energy/total")``, ``series("q/link1.R_x")``, ``series("tip.position.z")``: ``(n,)``;
    * ``series("tip.position")`` (a signal): ``(n, k)`` with its ``k`` components;
    * ``series("q")``, ``"u"``, ``"lambda"``: ``(n, nq)``, ``(n, nu)``, ``(n, nc)``;
      ``"energy"``: ``(n, 4)`` kinetic, gravity, elastic, springs in J; ``"drift"``: ``(n, 2)``;
      ``"step"``: ``(n, 3)`` step size in s, iterations, residual; ``"signals"``: all signal
      components. :meth:`columns` names the columns of a group.
    """

    def __init__(self, native: Any, summary: dict[str, Any] | None = None) -> None:
        self._r = native
        self._signals = {name: (unit, comps) for name, unit, comps in native.signals()}
        #: The run's summary (steps, rejected, Newton iterations, energy balance error, drift,
        #: wall time, files) when these results come from :func:`flexmbs.run`, else ``None``.
        self.summary = summary

    @property
    def path(self) -> Path:
        """The results file."""
        return Path(self._r.path())

    @property
    def model(self) -> str:
        """The model name."""
        return self._r.model()

    @property
    def rows(self) -> int:
        """Number of output rows ``n``."""
        return self._r.rows()

    def __len__(self) -> int:
        return self.rows

    @property
    def time(self) -> np.ndarray:
        """Output times in s, shape ``(n,)``."""
        return self._r.time()

    @property
    def status(self) -> str:
        """``"completed"``, ``"interrupted"``, ``"failed"`` or ``"running"`` (killed or still going)."""
        return self._r.status()[0]

    @property
    def status_time(self) -> float | None:
        """Time of an interruption or failure in s (else ``None``)."""
        return self._r.status()[1]

    @property
    def status_message(self) -> str | None:
        """What failed (else ``None``)."""
        return self._r.status()[2]

    @property
    def attributes(self) -> dict[str, str]:
        """The file's attributes: model file, solver, program."""
        return self._r.attributes()

    def names(self) -> list[str]:
        """Every single-column series name (``q/...``, ``u/...``, ``lambda/...``, ``energy/...``,
        ``drift/...``, ``step/...``, ``<signal>.<component>``)."""
        return self._r.names()

    def signals(self) -> dict[str, tuple[str, list[str]]]:
        """The requested output signals: name -> (unit, component names)."""
        return dict(self._signals)

    def series(self, name: str) -> np.ndarray:
        """One series ``(n,)``, a signal ``(n, k)`` or a group ``(n, width)`` (see the class doc).
        Raises :class:`UnknownSeriesError` (a ``KeyError``) naming similar names."""
        group = self._r.group(name)
        if group is not None:
            return group
        if name in self._signals:
            comps = self._signals[name][1]
            return np.column_stack([self._r.column(f"{name}.{c}") for c in comps])
        return self._r.column(name)

    __getitem__ = series

    def columns(self, group: str) -> list[str]:
        """Column names of a group (``"q"``: coordinate names; ``"energy"``: kinetic, gravity,
        elastic, springs; a signal: its components)."""
        if group in self._signals:
            return list(self._signals[group][1])
        return self._r.group_columns(group)

    def unit(self, name: str) -> str:
        """SI unit of a series (``""`` for numbers without unit and for mixed groups such as
        ``q``, whose columns are lengths, angles or modal coordinates)."""
        if name in self._signals:
            return self._signals[name][0]
        for sig, (unit, comps) in self._signals.items():
            if name.startswith(sig + ".") and name[len(sig) + 1 :] in comps:
                return unit
        if name in _FIXED_UNITS:
            return _FIXED_UNITS[name]
        if name.startswith("energy/"):
            return "J"
        return ""

    def stats(self, name: str) -> dict[str, float]:
        """Statistics of a single-column series: ``min``, ``max``, ``mean``, ``rms``, ``final``
        and the times ``t_min``, ``t_max`` of the extremes (NaN for an empty file)."""
        v = np.asarray(self._r.column(name))
        t = self.time
        if v.size == 0:
            nan = float("nan")
            return dict(min=nan, max=nan, mean=nan, rms=nan, final=nan, t_min=nan, t_max=nan)
        return dict(
            min=float(np.min(v)),
            max=float(np.max(v)),
            mean=float(np.mean(v)),
            rms=float(np.sqrt(np.mean(v * v))),
            final=float(v[-1]),
            t_min=float(t[int(np.argmin(v))]),
            t_max=float(t[int(np.argmax(v))]),
        )

    def to_pandas(self, names: list[str] | None = None) -> Any:
        """A ``pandas.DataFrame`` of the series ``names`` (default: all), indexed by ``time``.
        Needs pandas (``pip install pandas``)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Results.to_pandas needs pandas: pip install pandas") from e
        names = self.names() if names is None else list(names)
        data = {n: self._r.column(n) for n in names}
        return pd.DataFrame(data, index=pd.Index(self.time, name="time"))

    def __repr__(self) -> str:
        return f"<flexmbs.Results {self.model!r}: {self.rows} rows, {self.status}, {self.path}>"


def read_results(path: PathLike) -> Results:
    """Reads a results file (also one of an interrupted, failed or still running run)."""
    return Results(_native.read(str(path)))
