"""Reading a numeric table (comma, tab or semicolon separated): a header row of column names,
then rows of finite numbers.

The file is opened through :mod:`oocyte_fe.checks` (a regular UTF-8 file, never a FIFO);
every fault is one :class:`~oocyte_fe.errors.InputError` naming the file, the column and the
line. Units are the caller's business (e.g. :mod:`oocyte_fe.microchannel.tables`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError


def read_table_columns(
    path: Path, name: Callable[[str], str] = str.strip
) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """The columns of a table with a header row (``#`` lines are comments) as float arrays,
    each named by ``name(header)`` (default: the header as written, stripped), and each
    name's header as written in the file.

    Cells are separated by tabs or semicolons if the header row holds one, else by commas
    (:func:`oocyte_fe.checks.table_delimiter`); with semicolons a decimal comma in a cell is
    read as a point. The file is opened through :mod:`oocyte_fe.checks` (a regular UTF-8
    file); every cell must be a finite number.
    """
    text = checks.read_text(path)
    header_line = next(
        (line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")),
        "",
    )
    delimiter = checks.table_delimiter(header_line)
    what = checks.SEPARATORS[delimiter]
    rows = checks.csv_lines(path, text, delimiter)
    rows = [(n, row) for n, row in rows if any(c.strip() for c in row)]
    if len(rows) < 2:
        raise InputError(path, "", "a header row and at least one data row")
    header = [h.strip() for h in rows[0][1]]
    names = [name(h) for h in header]
    if len(set(names)) != len(names):
        raise InputError(path, "header", "distinct column names", got=", ".join(header)[:80])
    columns: dict[str, list[float]] = {n: [] for n in names}
    for line, row in rows[1:]:
        if len(row) != len(header):
            raise InputError(path, f"line {line}", f"{len(header)} {what}-separated values")
        for head, key, cell in zip(header, names, row, strict=True):
            if delimiter == ";":
                cell = cell.replace(",", ".")
            value = checks.number_cell(path, f"{head} (line {line})", cell)
            if not math.isfinite(value):
                raise InputError(path, f"{head} (line {line})", "a finite number", got=value)
            columns[key].append(value)
    return {k: np.array(v) for k, v in columns.items()}, dict(zip(names, header, strict=True))


def read_columns(path: Path) -> dict[str, np.ndarray]:
    """All columns of a table with a header row (:func:`read_table_columns`: comma, tab or
    semicolon separated), by their header as written."""
    return read_table_columns(path)[0]
