"""Argument checks of the public ``nmsd`` functions: one helper, one error type.

:func:`number` refuses what is not a real, finite number in the stated range (``bool``,
strings, complex, NaN, inf, ``2.5`` where a count is expected) with
:class:`~nmsd.errors.NmsdInputError` naming the function, the argument and the expectation.
:func:`read_text` opens a user's file safely (regular file, no FIFO hang, UTF-8).
"""

from __future__ import annotations

import math
import numbers
import os
import stat
from pathlib import Path

from nmsd.errors import NmsdInputError

MAX_FILE_BYTES = 64 * 1024 * 1024


def _bounds(gt: float | None, ge: float | None, lt: float | None, le: float | None) -> str:
    parts = []
    if gt is not None:
        parts.append(f"> {gt:g}")
    if ge is not None:
        parts.append(f">= {ge:g}")
    if lt is not None:
        parts.append(f"< {lt:g}")
    if le is not None:
        parts.append(f"<= {le:g}")
    return " and ".join(parts)


def number(
    where: str,
    name: str,
    value: object,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    integer: bool = False,
) -> float:
    """``value`` as a float (or int if ``integer``) if real, finite and within the bounds.

    Raises :class:`NmsdInputError` ``"<where>: <name>: expected ..."`` otherwise.
    """
    what = "an integer" if integer else "a finite real number"
    bounds = _bounds(gt, ge, lt, le)
    expected = f"{what} {bounds}".strip()
    ok_type = isinstance(value, numbers.Integral if integer else numbers.Real)
    if isinstance(value, bool) or not ok_type:
        raise NmsdInputError(where, name, expected, got=value)
    x = int(value) if integer else float(value)  # type: ignore[arg-type]
    if not math.isfinite(x):
        raise NmsdInputError(where, name, expected, got=value)
    if (
        (gt is not None and not x > gt)
        or (ge is not None and not x >= ge)
        or (lt is not None and not x < lt)
        or (le is not None and not x <= le)
    ):
        raise NmsdInputError(where, name, expected, got=value)
    return x


def read_text(path: str | Path) -> str:
    """The text of a regular UTF-8 file; a directory, FIFO, loop or binary file is one line."""
    path = Path(path)
    where = str(path)
    if any(len(p.encode("utf-8", "surrogateescape")) > 255 for p in path.parts):
        raise NmsdInputError(where[:60] + "...", "", "file names of at most 255 bytes")
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        raise NmsdInputError(where, "", "a readable CSV file", got=exc.strerror) from None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fh.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise NmsdInputError(where, "", "a regular file (not a folder, FIFO or device)")
        data = fh.read(MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES or b"\x00" in data:
        raise NmsdInputError(where, "", f"a text file of at most {MAX_FILE_BYTES >> 20} MiB")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise NmsdInputError(where, f"line {line}", "UTF-8 text (save the file as UTF-8)") from None
