"""The exceptions of flexmbs: one base class, :class:`Error`, and a subclass per kind of failure."""

from __future__ import annotations


class Error(Exception):
    """Base of every flexmbs error. ``str(e)`` is the full message (as the command line prints it)."""

    def __init__(self, message: str, **attributes: object) -> None:
        super().__init__(message)
        self.message = message
        for name, value in attributes.items():
            setattr(self, name, value)

    def __str__(self) -> str:
        return self.message


class ModelError(Error):
    """A model that cannot be compiled: a wrong key, value, unit, name or a model the engine rejects.

    Attributes:
        key_path: the key path of the wrong value, e.g. ``"joint[1].a"`` (``""`` for a TOML
            syntax error, ``None`` for an error of the whole model).
        file: the model file, when the model is the unchanged text of a file (else ``None``).
        line: the 1-based line in ``file`` (``None`` if unknown or not from a file).
        reason: what was wrong, without the location.
    """

    key_path: str | None = None
    file: str | None = None
    line: int | None = None
    reason: str | None = None


class SolverError(Error):
    """The solver failed during a run. The results file holds every step up to the failure and
    has status ``failed``.

    Attributes:
        t: time of the failed step in s.
        h: its step size in s.
        residual: the last residual (NaN if unknown).
        results: path of the results file.
        hint: what to try, chosen by the cause of the failure (the text the command line
            prints after ``hint:``).
    """

    t: float = float("nan")
    h: float = float("nan")
    residual: float = float("nan")
    results: str | None = None
    hint: str | None = None


class IoError(Error):
    """A file that cannot be read or written (missing, not a flexmbs file, damaged, locked by
    another run).

    Attributes:
        path: the file, when known (else ``None``).
    """

    path: str | None = None


class UnknownSeriesError(Error, KeyError):
    """No series of this name in a results file (also a :class:`KeyError`).

    Attributes:
        name: the name asked for.
        close: the most similar existing names, comma-separated.
        path: the results file.
    """

    name: str = ""
    close: str = ""
    path: str | None = None
