"""Models as plain data: a :class:`Model` holds a dict with exactly the keys, values and units of a
model file (``docs/model-file.md``), and is validated and compiled by the same Rust code as the
file would be."""

from __future__ import annotations

import copy
import os
import re
from pathlib import Path
from typing import Any, Iterator, Mapping, Union

from . import _native
from ._errors import ModelError

PathLike = Union[str, "os.PathLike[str]"]

_TOKEN = re.compile(r"([^.\[\]]+)|\[([^\]]*)\]|(\.)")


def split_key_path(key_path: str | tuple) -> list[str | int]:
    """``"body[1].mass"`` -> ``["body", 1, "mass"]``; ``"body[link2].mass"`` -> ``["body",
    "link2", "mass"]`` (an item of a list addressed by its ``name``). A tuple is taken as is."""
    if isinstance(key_path, tuple):
        return list(key_path)
    parts: list[str | int] = []
    pos = 0
    for m in _TOKEN.finditer(key_path):
        if m.start() != pos:
            break
        pos = m.end()
        if m.group(1) is not None:
            parts.append(m.group(1))
        elif m.group(2) is not None:
            inner = m.group(2).strip().strip("\"'")
            parts.append(int(inner) if re.fullmatch(r"-?\d+", inner) else inner)
    if pos != len(key_path) or not parts:
        raise ModelError(
            f"invalid key path {key_path!r} (write e.g. 'solver.h', 'body[0].mass' or 'body[link2].mass')",
            key_path=str(key_path),
            reason="invalid key path",
        )
    return parts


def _key_error(parts: list, k: int, why: str) -> ModelError:
    shown = _join(parts[: k + 1])
    return ModelError(f"model: at `{shown}`: {why}", key_path=shown, reason=why)


def _join(parts: list) -> str:
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        else:
            out += ("." if out else "") + str(p)
    return out


def _child(node: Any, part: str | int, parts: list, k: int) -> Any:
    """The item ``part`` of ``node`` (a dict key, a list index, or a list item's ``name``)."""
    if isinstance(node, dict):
        if isinstance(part, int) or part not in node:
            raise _key_error(parts, k, "no such key")
        return node[part]
    if isinstance(node, list):
        if isinstance(part, int):
            if not -len(node) <= part < len(node):
                raise _key_error(parts, k, f"index out of range (the list has {len(node)} items)")
            return node[part]
        for item in node:
            if isinstance(item, dict) and item.get("name") == part:
                return item
        raise _key_error(parts, k, f"no item named {part!r}")
    raise _key_error(parts, k, f"`{_join(parts[:k])}` is a value, not a table or list")


class Model:
    """A multibody model as plain data, one to one with the model file.

    ``model.data`` is the dict (tables are dicts, arrays are lists; quantities are numbers in SI or
    strings with a unit such as ``"30 mm"``); ``model["solver.h"] = "0.5 ms"`` sets a key by its
    key path (``"body[0].mass"``, ``"body[link2].mass"``). A key set to ``None`` is left out.
    Relative paths in the model (FE body sources) are resolved against ``base_dir``, the model
    file's folder for a loaded model.
    """

    def __init__(self, data: Mapping[str, Any] | None = None, *, base_dir: PathLike | None = None) -> None:
        self.data: dict[str, Any] = copy.deepcopy(dict(data)) if data is not None else {}
        self.base_dir = Path(base_dir) if base_dir is not None else Path.cwd()
        self._file: Path | None = None
        self._text: str | None = None
        self._pristine: dict[str, Any] | None = None

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, base_dir: PathLike | None = None) -> "Model":
        """A model from a dict shaped like the model file (copied)."""
        return cls(data, base_dir=base_dir)

    @classmethod
    def from_toml(cls, text: str, *, base_dir: PathLike | None = None) -> "Model":
        """A model from model-file text."""
        base = Path(base_dir) if base_dir is not None else Path.cwd()
        return cls(_native.toml_loads(text, str(base / "<text>")), base_dir=base)

    @classmethod
    def load(cls, path: PathLike) -> "Model":
        """Reads a model file. Errors of the unchanged model name the file and line."""
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            from ._errors import IoError

            raise IoError(f"{path}: cannot read: {e}", path=str(path)) from None
        m = cls(_native.toml_loads(text, str(path)), base_dir=path.resolve().parent)
        m._file = path
        m._text = text
        m._pristine = copy.deepcopy(m.data)
        return m

    @property
    def file(self) -> Path | None:
        """The model file this model was loaded from (``None`` if built in Python)."""
        return self._file

    @property
    def name(self) -> str | None:
        """``model.name``."""
        return self.data.get("model", {}).get("name")

    def to_dict(self) -> dict[str, Any]:
        """A deep copy of the data."""
        return copy.deepcopy(self.data)

    def to_toml(self) -> str:
        """The model as model-file text (the file's own text if loaded and unchanged)."""
        return self._source()[0]

    def save(self, path: PathLike) -> None:
        """Writes the model as a model file."""
        Path(path).write_text(self.to_toml(), encoding="utf-8")

    def copy(self) -> "Model":
        """An independent copy (a change to it does not change this model)."""
        m = Model(self.data, base_dir=self.base_dir)
        m._file, m._text = self._file, self._text
        m._pristine = copy.deepcopy(self._pristine)
        return m

    def __getitem__(self, key_path: str | tuple) -> Any:
        parts = split_key_path(key_path)
        node: Any = self.data
        for k, part in enumerate(parts):
            node = _child(node, part, parts, k)
        return node

    def get(self, key_path: str | tuple, default: Any = None) -> Any:
        """The value at ``key_path``, or ``default`` if there is none."""
        try:
            return self[key_path]
        except ModelError:
            return default

    def __contains__(self, key_path: str | tuple) -> bool:
        try:
            self[key_path]
            return True
        except ModelError:
            return False

    def __setitem__(self, key_path: str | tuple, value: Any) -> None:
        parts = split_key_path(key_path)
        node: Any = self.data
        for k, part in enumerate(parts[:-1]):
            if isinstance(node, dict) and isinstance(part, str) and part not in node:
                node[part] = [] if isinstance(parts[k + 1], int) else {}
            node = _child(node, part, parts, k)
        last = parts[-1]
        if isinstance(node, dict) and isinstance(last, str):
            if value is None:
                node.pop(last, None)
            else:
                node[last] = copy.deepcopy(value)
        elif isinstance(node, list) and isinstance(last, int):
            if last == len(node):
                node.append(copy.deepcopy(value))
            else:
                _child(node, last, parts, len(parts) - 1)
                node[last] = copy.deepcopy(value)
        else:
            raise _key_error(parts, len(parts) - 1, "cannot be set (no such table or list item)")

    def __delitem__(self, key_path: str | tuple) -> None:
        parts = split_key_path(key_path)
        parent = self[tuple(parts[:-1])] if len(parts) > 1 else self.data
        last = parts[-1]
        if isinstance(parent, dict) and last in parent:
            del parent[last]
        elif isinstance(parent, list) and isinstance(last, int) and -len(parent) <= last < len(parent):
            del parent[last]
        else:
            raise _key_error(parts, len(parts) - 1, "no such key")

    def __iter__(self) -> Iterator[str]:
        return iter(self.data)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Model) and self.data == other.data

    def __repr__(self) -> str:
        where = f" from {self._file}" if self._file else ""
        return f"<flexmbs.Model {self.name!r}{where}>"

    def _source(self) -> tuple[str, str, bool]:
        """``(text, file, from_file)``: the file's own text while unchanged (errors name its lines),
        else TOML generated from the data (errors name the key path only)."""
        if self._text is not None and self._pristine is not None and self.data == self._pristine:
            return self._text, str(self._file), True
        label = self._file if self._file is not None else self.base_dir / "python_model.toml"
        text = _native.toml_dumps(self.data)
        return text, str(Path(self.base_dir) / Path(label).name), False


def as_model(model: Model | Mapping[str, Any] | PathLike) -> Model:
    """A :class:`Model` from a model, a dict, or a model file path."""
    if isinstance(model, Model):
        return model
    if isinstance(model, Mapping):
        return Model.from_dict(model)
    return Model.load(model)


def load(path: PathLike) -> Model:
    """Reads a model file into a :class:`Model`."""
    return Model.load(path)


def check(model: Model | Mapping[str, Any] | PathLike) -> dict[str, Any]:
    """Compiles a model without running it (as ``flexmbs check``); returns what it holds: name,
    bodies, frames, joints, constraint rows, loads, coordinates, signals, solver, t_end, warnings.
    Raises :class:`ModelError` with the key path of the first error."""
    text, file, from_file = as_model(model)._source()
    return _native.check(text, file, from_file)
