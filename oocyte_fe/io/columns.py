"""Reading a numeric CSV table: a header row of column names, then rows of finite numbers.

The file is opened through :mod:`oocyte_fe.checks` (a regular UTF-8 file, never a FIFO);
every fault is one :class:`~oocyte_fe.errors.InputError` naming the file, the column and the
line. Units are the caller's business (e.g. :mod:`oocyte_fe.microchannel.tables`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError


def read_columns(path: Path) -> dict[str, np.ndarray]:
    """All columns of a CSV file with a header row, as float arrays; ``#`` lines are comments.

    The file is opened through :mod:`oocyte_fe.checks` (a regular UTF-8 file, never a FIFO);
    every cell must be a finite number.
    """
    text = checks.read_text(path)
    numbered = [(n, row) for n, row in checks.csv_lines(path, text) if any(c.strip() for c in row)]
    if len(numbered) < 2:
        raise InputError(path, "", "a header row and at least one data row")
    header = [h.strip() for h in numbered[0][1]]
    if len(set(header)) != len(header):
        raise InputError(path, "header", "distinct column names", got=", ".join(header)[:80])
    columns: dict[str, list[float]] = {h: [] for h in header}
    for line, row in numbered[1:]:
        if len(row) != len(header):
            raise InputError(path, f"line {line}", f"{len(header)} comma-separated values")
        for name, cell in zip(header, row, strict=True):
            value = checks.number_cell(path, f"{name} (line {line})", cell)
            if not math.isfinite(value):
                raise InputError(path, f"{name} (line {line})", "a finite number", got=value)
            columns[name].append(value)
    return {k: np.array(v) for k, v in columns.items()}
