"""Writing OpenFOAM dictionaries and fields (ASCII), reading fields back.

A dictionary is a nested Python ``dict``: values are numbers, strings (written verbatim, so
``"uniform (0 0 0)"`` or ``"Gauss linear"``), lists (written as ``( ... )``) or dicts
(sub-dictionaries). Keys are written in insertion order. Fields are written with
``internalField nonuniform List<scalar|vector>`` from numpy arrays, or ``uniform``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from oocyte_fe.errors import InputError

_HEADER = (
    "FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class {cls};\n    object {obj};\n}}\n"
)


def _value(value: Any, indent: int) -> str:
    pad = "    " * indent
    if isinstance(value, Mapping):
        body = "".join(_entry(k, v, indent + 1) for k, v in value.items())
        return f"\n{pad}{{\n{body}{pad}}}"
    if isinstance(value, list | tuple):
        return "(" + " ".join(_value(v, indent).strip() for v in value) + ")"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.10g}"
    return str(value)


def _entry(key: str, value: Any, indent: int) -> str:
    pad = "    " * indent
    if isinstance(value, Mapping):
        return f"{pad}{key}{_value(value, indent)}\n"
    return f"{pad}{key} {_value(value, indent)};\n"


def dictionary_text(cls: str, obj: str, entries: Mapping[str, Any]) -> str:
    """The text of an OpenFOAM file of class ``cls`` named ``obj``."""
    return _HEADER.format(cls=cls, obj=obj) + "".join(_entry(k, v, 0) for k, v in entries.items())


def write_dictionary(path: Path, entries: Mapping[str, Any], cls: str = "dictionary") -> Path:
    """Write ``entries`` to ``path`` (parent folders created)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(dictionary_text(cls, path.name, entries))
    return path


def field_values(values: np.ndarray) -> str:
    """``nonuniform List<scalar>`` (1-D array) or ``List<vector>`` (n x 3 array)."""
    v = np.asarray(values, dtype=float)
    if v.ndim == 1:
        body = "\n".join(f"{x:.10g}" for x in v)
        return f"nonuniform List<scalar>\n{len(v)}\n(\n{body}\n)"
    body = "\n".join(f"({a:.10g} {b:.10g} {c:.10g})" for a, b, c in v)
    return f"nonuniform List<vector>\n{len(v)}\n(\n{body}\n)"


def write_field(
    path: Path,
    dimensions: str,
    internal: np.ndarray | str,
    boundary: Mapping[str, Mapping[str, Any]],
) -> Path:
    """Write a volScalarField / volVectorField: ``internal`` is an array or ``"uniform ..."``."""
    vector = (isinstance(internal, str) and "(" in internal) or np.ndim(internal) == 2
    cls = "volVectorField" if vector else "volScalarField"
    inner = internal if isinstance(internal, str) else field_values(internal)
    entries = {"dimensions": dimensions, "internalField": inner, "boundaryField": boundary}
    return write_dictionary(path, entries, cls)


_LIST = re.compile(r"internalField\s+nonuniform\s+List<(scalar|vector)>\s*(\d+)\s*\(", re.S)
_UNIFORM = re.compile(r"internalField\s+uniform\s+(\([^)]*\)|[-+0-9.eE]+)\s*;")


def read_internal_field(path: Path, n_cells: int | None = None) -> np.ndarray:
    """The internal field of an ASCII OpenFOAM field file as an array (n,) or (n, 3).

    A ``uniform`` field is expanded to ``n_cells`` values (required then).
    """
    try:
        text = Path(path).read_text()
    except OSError as exc:
        raise InputError(path, "", "a readable OpenFOAM field file", got=exc.strerror) from None
    match = _LIST.search(text)
    if match:
        kind, count = match.group(1), int(match.group(2))
        start = match.end()
        end = text.index("\n)", start)
        body = text[start:end].replace("(", " ").replace(")", " ")
        values = np.array(body.split(), dtype=float)
        return values.reshape(count, 3) if kind == "vector" else values
    match = _UNIFORM.search(text)
    if match and n_cells is not None:
        raw = match.group(1).strip("()").split()
        value = np.array(raw, dtype=float)
        return np.tile(value, (n_cells, 1)) if value.size == 3 else np.full(n_cells, value[0])
    raise InputError(path, "internalField", "an ASCII nonuniform List<scalar|vector> field")
