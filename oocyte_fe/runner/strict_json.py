"""JSON that strict readers accept: no bare ``NaN`` or ``Infinity``.

A non-finite number (a metric that could not be computed, a diverged value) is written as
``null`` and its place and value are listed under the top-level key ``"non_finite"``, for
example ``{"metrics.E0_kPa": "nan (not a finite number)"}``; ``json.dumps`` runs with
``allow_nan=False``, so nothing non-finite can slip through.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np


def _clean(value: Any, where: str, found: dict[str, str]) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, float) and not math.isfinite(value):
        found[where] = f"{value} (not a finite number)"
        return None
    if isinstance(value, dict):
        return {k: _clean(v, f"{where}.{k}" if where else str(k), found) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_clean(v, f"{where}.{i}", found) for i, v in enumerate(value)]
    return value


def strict_dumps(record: dict[str, Any], indent: int | None = 2) -> str:
    """``record`` as strict JSON; non-finite numbers become ``null``, listed in ``non_finite``."""
    found: dict[str, str] = {}
    clean = _clean(record, "", found)
    if found:
        clean["non_finite"] = found
    return json.dumps(clean, indent=indent, allow_nan=False, default=str)
