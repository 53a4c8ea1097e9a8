"""The project's one validator: numbers, arrays and files a user hands in.

Every public function of ``afm``, ``nmsd`` and ``oocyte_fe`` checks its arguments here and
raises :class:`~oocyte_fe.errors.InputError` (``"<where>: <name>: expected ..., got ..."``,
one line) for anything else; this module imports nothing heavier than numpy, so ``afm`` and
``nmsd`` may use it without importing the FE.

Numbers: :func:`number` refuses what is not a real, finite number within the stated bounds
(``bool``, strings, complex, NaN, inf, ``2.5`` where a count is expected); :func:`quantity`
does so with the physical bounds of :data:`QUANTITIES` (a modulus of 1e308 or 1e-320 kPa is
not one); :func:`numbers_array` and :func:`float_array` check arrays.

Files: every file a user names goes through :func:`read_text` (or :func:`regular_file` when a
library reader opens it afterwards), which guarantees, before any parser sees a byte:

* each name in the path is at most 255 bytes (the limit of common file systems);
* the path is not a symlink loop, resolves to a *regular* file (not a directory, FIFO,
  socket or device) and is opened without blocking (``O_NONBLOCK``), so a FIFO never hangs;
* the file is at most :data:`MAX_BYTES` long and is UTF-8 text without NUL bytes.

:func:`inside` refuses a path that resolves outside a folder (``..``, absolute paths,
symlinks out): a case reads only files in its own folder. :func:`excerpt` is the only way file
content reaches an error message: a short, clearly marked piece of one line.
"""

from __future__ import annotations

import csv
import dataclasses
import errno
import math
import numbers
import os
import stat
import tomllib
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError

# --- numbers ---------------------------------------------------------------------------------


def _expected(integer: bool, gt, ge, lt, le) -> str:
    parts = [
        f"{op} {bound:g}"
        for op, bound in ((">", gt), (">=", ge), ("<", lt), ("<=", le))
        if bound is not None
    ]
    what = "an integer" if integer else "a finite real number"
    return f"{what} {' and '.join(parts)}".strip()


def _within(x: float, gt, ge, lt, le) -> bool:
    return not (
        (gt is not None and not x > gt)
        or (ge is not None and not x >= ge)
        or (lt is not None and not x < lt)
        or (le is not None and not x <= le)
    )


def number(
    where: str | Path,
    name: str,
    value: object,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    integer: bool = False,
    expected: str | None = None,
) -> float:
    """``value`` as a float (an int if ``integer``) if real, finite and within the bounds.

    ``expected`` replaces the generated expectation in the message (for example "a positive
    modulus in kPa"); the bounds are checked either way.
    """
    what = expected or _expected(integer, gt, ge, lt, le)
    kind = numbers.Integral if integer else numbers.Real
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, kind):
        raise InputError(where, name, what, got=value)
    x = int(value) if integer else float(value)  # type: ignore[arg-type]
    if not (math.isfinite(x) and _within(x, gt, ge, lt, le)):
        raise InputError(where, name, what, got=value)
    return x


TINY = 1e-30
HUGE = 1e30
"""Range of a positive physical quantity in internal units (um, nN, kPa, s and their products):
wide enough for every real one (water's density is 1e-15 nN s^2/um^4), narrow enough that the
closed forms' products of a few of them stay finite."""


def positive(where: str | Path, name: str, value: object, expected: str | None = None) -> float:
    """``value`` if a real number in [:data:`TINY`, :data:`HUGE`] (see :func:`number`)."""
    return number(where, name, value, ge=TINY, le=HUGE, expected=expected)


def fraction(where: str | Path, name: str, value: object) -> float:
    """``value`` if a real number in the open interval (0, 1)."""
    return number(where, name, value, gt=0, lt=1, expected="a fraction in (0, 1)")


def integer(where: str | Path, name: str, value: object, low: int, high: int) -> int:
    """``value`` if an int (not a bool) in [low, high]."""
    return int(
        number(
            where,
            name,
            value,
            ge=low,
            le=high,
            integer=True,
            expected=f"an integer in [{low}, {high}]",
        )
    )


QUANTITIES: dict[str, tuple[float, float, str]] = {
    "modulus_kPa": (1e-6, 1e9, "kPa"),
    "length_um": (1e-6, 1e6, "um"),
    "time_s": (1e-9, 1e9, "s"),
    "force_nN": (1e-9, 1e12, "nN"),
    "pressure_kPa": (1e-9, 1e6, "kPa"),
    "viscosity_kPa_s": (1e-12, 1e9, "kPa s"),
    "stiffness_nN_per_um": (1e-9, 1e12, "nN/um"),
    "shear_rate_per_s": (1e-9, 1e12, "1/s"),
    "cone_half_angle_deg": (0.1, 89.0, "deg"),
}
"""Physical bounds of each quantity a user gives, in internal units: (smallest, largest, unit).

Wider than any oocyte experiment by orders of magnitude (an AFM modulus of 1 mPa to 1 TPa, a
length of 1 pm to 1 m, a time of 1 ns to 30 years), narrow enough that a typing slip of
``1e308`` or a denormal ``1e-320`` is refused with the bound named instead of giving inf or a
division by zero downstream (docs/units.md). A cone's half angle lies in [0.1, 89] deg: the
sharpest AFM tips have about 5 deg, and at 90 deg Sneddon's tan(alpha) diverges (a flat
punch); both bounds lie inside the tip model's (1e-3, 90) deg, so what passes validation
passes the fit."""


def quantity(where: str | Path, name: str, value: object, kind: str) -> float:
    """``value`` within the physical bounds of :data:`QUANTITIES` ``[kind]`` (positive)."""
    low, high, unit = QUANTITIES[kind]
    return number(
        where, name, value, ge=low, le=high, expected=f"a number in [{low:g}, {high:g}] {unit}"
    )


def unit_that_fits(
    column: str, value: float, bounds: tuple[float, float], scales: dict[str, float]
) -> tuple[str, float] | None:
    """The likely unit mistake behind ``value`` (internal units, read from the column
    ``<stem>_<unit>``) lying outside ``bounds``: the column ``<stem>_<other>`` whose unit,
    nearest in scale to the column's own (``scales``: unit suffix -> factor to the internal
    unit), would read the same numbers as a value within ``bounds``, and that value; None
    when no unit does (or the column's own unit is not in ``scales``). Metres written under
    ``piezo_um`` (8e-06) give ``("piezo_m", 8.0)``."""
    stem, _, unit = column.rpartition("_")
    own = scales.get(unit)
    if not own:
        return None
    low, high = bounds
    for other in sorted(scales, key=lambda u: abs(math.log(scales[u] / own))):
        rescaled = value * scales[other] / own
        if other != unit and low <= rescaled <= high:
            return f"{stem}_{other}", rescaled
    return None


def float_array(where: str | Path, name: str, values: object) -> np.ndarray:
    """``values`` as a float array (NaN kept: raw data); what numpy cannot read is refused."""
    try:
        array = np.asarray(values)
        if array.dtype == bool or np.iscomplexobj(array):
            raise TypeError
        return array.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(where, name, "an array of real numbers") from None


def numbers_array(
    where: str | Path,
    name: str,
    value: object,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
) -> np.ndarray:
    """``value`` as a float array (scalars allowed) whose every element passes :func:`number`."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(where, name, "an array of real numbers") from None
    if array.dtype == bool or not np.issubdtype(array.dtype, np.number) or np.iscomplexobj(array):
        raise InputError(where, name, "an array of real numbers", got=str(array.dtype))
    array = array.astype(float)
    bad = ~(np.isfinite(array) & _vector_within(array, gt, ge, lt, le))
    if np.any(bad):
        bounds = _expected(False, gt, ge, lt, le).removeprefix("a finite real number")
        expected = f"an array of finite real numbers{bounds}"
        raise InputError(where, name, expected, got=float(array[bad].flat[0]))
    return array


def finite_column(where: str | Path, name: str, values: object) -> np.ndarray:
    """``values`` as a 1-D float array of finite numbers; a NaN or inf is refused naming its
    data row (1 = the first row below the header)."""
    array = float_array(where, name, values)
    if array.ndim != 1:
        raise InputError(where, name, "a 1-D column of numbers", got=f"shape {array.shape}")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        row = int(bad[0])
        value = float(array[row])
        raise InputError(where, name, f"finite numbers (data row {row + 1} holds {value!r})")
    return array


def increasing(where: str | Path, name: str, values: object, unit: str = "s") -> np.ndarray:
    """``values`` as a 1-D float array of finite numbers increasing row by row (a time column).

    Refused, naming the first bad data row (1 = the first row below the header): a NaN or
    inf (:func:`finite_column`), a value not larger than the one above it (a decreasing or
    repeated time: rows shuffled, approach and retract mixed, or a clock reset).
    """
    array = finite_column(where, name, values)
    back = np.flatnonzero(np.diff(array) <= 0)
    if back.size:
        row = int(back[0]) + 1
        raise InputError(
            where,
            name,
            f"values increasing row by row (data row {row + 1} after data row {row})",
            got=f"{array[row]:.6g} {unit} after {array[row - 1]:.6g} {unit}",
        )
    return array


def _vector_within(a: np.ndarray, gt, ge, lt, le) -> np.ndarray:
    ok = np.ones(a.shape, dtype=bool)
    if gt is not None:
        ok &= a > gt
    if ge is not None:
        ok &= a >= ge
    if lt is not None:
        ok &= a < lt
    if le is not None:
        ok &= a <= le
    return ok


def numeric_fields(obj: object, where: str, max_abs: float = 1e12) -> None:
    """Every ``float``/``int`` field of the dataclass ``obj`` real, finite and ``|x| <= max_abs``
    (its own range checks follow in its ``__post_init__``)."""
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        if f.type in ("float", "int", float, int):
            is_int = f.type in ("int", int)
            number(where, f.name, getattr(obj, f.name), ge=-max_abs, le=max_abs, integer=is_int)


# --- files -----------------------------------------------------------------------------------

MAX_NAME_BYTES = 255
"""Longest file or folder name accepted (bytes, UTF-8)."""
MAX_BYTES = 64 * 1024 * 1024
"""Largest text file read (64 MiB): a case file or a data table, never a bulk recording."""
EXCERPT_CHARS = 40


def excerpt(text: str) -> str:
    """A short, clearly marked piece of one line of a file (for an error message)."""
    line = text.splitlines()[0] if text else ""
    cut = line[:EXCERPT_CHARS] + (" ..." if len(line) > EXCERPT_CHARS else "")
    return f"[excerpt: {cut!r}]"


SEPARATORS = {",": "comma", "\t": "tab", ";": "semicolon"}
"""Cell separators of the text tables read, by name (for messages)."""


def table_delimiter(header: str) -> str:
    """The cell separator of a table whose header row is ``header``: a tab or a semicolon if
    the row holds one (a spreadsheet's or a European export), else a comma."""
    return next((d for d in ("\t", ";") if d in header), ",")


def csv_lines(path: str | Path, text: str, delimiter: str = ",") -> list[tuple[int, list[str]]]:
    """The rows of a ``delimiter``-separated text (one of :data:`SEPARATORS`) with the file's
    own line numbers (1 = the first line), blank lines and ``#`` comment lines left out; a row
    the CSV reader refuses is named by its line."""
    rows = []
    for line, text_line in enumerate(text.splitlines(), start=1):
        if not text_line.strip() or text_line.lstrip().startswith("#"):
            continue
        try:
            rows.append((line, next(csv.reader([text_line], delimiter=delimiter))))
        except csv.Error as exc:
            what = f"{SEPARATORS[delimiter]}-separated values ({exc})"
            raise InputError(path, f"line {line}", what) from None
    return rows


def number_cell(path: str | Path, field: str, cell: str, expected: str = "a number") -> float:
    """A table cell as a float, or :class:`InputError` quoting the cell (:func:`excerpt`)."""
    try:
        return float(cell)
    except ValueError:
        raise InputError(path, field, expected, got=excerpt(cell)) from None


def _kind_of(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def _check_names(path: Path, field: str) -> None:
    for part in path.parts:
        if len(part.encode("utf-8", "surrogateescape")) > MAX_NAME_BYTES:
            raise InputError(
                path.name[:40] + "...",
                field,
                f"file and folder names of at most {MAX_NAME_BYTES} bytes",
            )


def regular_file(path: str | Path, field: str = "") -> Path:
    """``path`` if it names an existing regular file; :class:`InputError` naming it otherwise."""
    path = Path(path)
    _check_names(path, field)
    try:
        info = path.stat()
    except FileNotFoundError:
        raise InputError(path, field, "an existing file") from None
    except OSError as exc:
        reason = "a path without a symlink loop" if exc.errno == errno.ELOOP else "a readable file"
        raise InputError(path, field, reason, got=exc.strerror) from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(path, field, "a regular file", got=_kind_of(info.st_mode))
    if info.st_size > MAX_BYTES:
        raise InputError(path, field, f"a file of at most {MAX_BYTES // 2**20} MiB")
    return path


def read_bytes(path: str | Path, field: str = "") -> bytes:
    """The bytes of a regular file (checked as :func:`regular_file`; never blocks on a FIFO)."""
    path = regular_file(path, field)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        raise InputError(path, field, "a readable file", got=exc.strerror) from None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):  # swapped since the check
            raise InputError(path, field, "a regular file")
        return fh.read(MAX_BYTES + 1)


def decode_text(data: bytes, path: str | Path, field: str = "") -> str:
    """UTF-8 text (a BOM is dropped); a NUL byte or another encoding is one clear line."""
    if b"\x00" in data:
        line = data[: data.index(b"\x00")].count(b"\n") + 1
        raise InputError(path, field or f"line {line}", "a text file (UTF-8), not binary data")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise InputError(
            path,
            field or f"line {line}",
            "UTF-8 text (save the file as UTF-8)",
            got=f"byte 0x{data[exc.start]:02x}",
        ) from None


def read_text(path: str | Path, field: str = "") -> str:
    """The text of a regular UTF-8 file; every fault is one :class:`InputError` line."""
    return decode_text(read_bytes(path, field), path, field)


def inside(path: str | Path, folder: str | Path, where: str | Path, field: str) -> Path:
    """``path`` (relative to ``folder``, or absolute) resolved; refused if outside ``folder``.

    ``where`` and ``field`` name the file and key that gave the path (for the error).
    """
    folder = Path(folder)
    candidate = Path(path)
    _check_names(candidate, field)
    full = candidate if candidate.is_absolute() else folder / candidate
    try:
        resolved = full.resolve(strict=False)
        root = folder.resolve(strict=False)
    except (OSError, RuntimeError):
        raise InputError(where, field, "a path without a symlink loop", got=str(path)) from None
    if not resolved.is_relative_to(root):
        raise InputError(
            where,
            field,
            "a file inside the case folder (nothing outside it is read; copy the file in)",
            got=str(path),
        )
    return resolved


def read_toml(path: str | Path, field: str = "") -> dict:
    """A TOML file's tables, read through :func:`read_text`; a fault of the TOML (or nesting
    deep enough to exhaust the parser) is one :class:`InputError` naming the file."""
    text = read_text(path, field)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(path, field, f"valid TOML ({exc})") from None
    except RecursionError:
        raise InputError(path, field, "TOML nested less deeply") from None


def toml_table(
    where: str | Path, data: dict, key: str, allowed: set[str], required: bool = True
) -> dict:
    """The table ``key`` of a TOML file's ``data`` holding only ``allowed`` keys (``{}`` when
    it is left out and not ``required``); otherwise :class:`InputError` naming the key."""
    table = data.get(key)
    if table is None:
        if required:
            raise InputError(where, f"[{key}]", "this table (it is required)")
        return {}
    if not isinstance(table, dict):
        raise InputError(where, key, "a table")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise InputError(where, f"{key}.{unknown[0]}", f"one of {sorted(allowed)}")
    return table
