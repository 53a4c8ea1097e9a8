"""Files: VTU/PVD field series for ParaView and CSV time histories (results), numeric CSV
tables (inputs, :mod:`oocyte_fe.io.columns`).

The writers load on first use, so reading a CSV table does not import meshio.
"""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {
    "FieldSeriesWriter": "oocyte_fe.io.vtu",
    "write_history_csv": "oocyte_fe.io.history_csv",
}

__all__ = ["FieldSeriesWriter", "write_history_csv"]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
