"""Time histories as CSV with the unit in each column name (``time_s``, ``force_nN``).

Values are written as given (the internal units um, nN, kPa, s unless the caller converted
them); the unit string names what they are. A dimensionless column has the unit ``""`` and
keeps its bare name. The file is written to a temporary name and renamed into place.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np


def history_header(name: str, unit: str) -> str:
    """Column name with its unit: ``force`` + ``nN`` -> ``force_nN``; ``""`` -> ``force``."""
    if not unit or name.endswith(f"_{unit}"):
        return name
    return f"{name}_{unit}"


def write_history_csv(
    path: str | Path, columns: Mapping[str, np.ndarray], units: Mapping[str, str]
) -> Path:
    """Write equally long 1D ``columns`` (in their insertion order) to ``path`` as CSV; every
    column needs an entry in ``units``. Returns ``path``."""
    path = Path(path)
    if not columns:
        raise ValueError("write_history_csv: no columns")
    missing = [name for name in columns if name not in units]
    if missing:
        raise ValueError(f"write_history_csv: no unit for column(s) {missing}")
    data = [np.asarray(values, dtype=float) for values in columns.values()]
    lengths = {name: arr.shape for name, arr in zip(columns, data, strict=True)}
    if any(arr.ndim != 1 for arr in data) or len({arr.size for arr in data}) != 1:
        raise ValueError(f"write_history_csv: columns must be 1D of one length, got {lengths}")
    header = ",".join(history_header(name, units[name]) for name in columns)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.partial")
    try:
        np.savetxt(
            tmp, np.column_stack(data), delimiter=",", header=header, comments="", fmt="%.10g"
        )
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path
