"""Reading and writing force curves and creep records; units converted here, at the boundary.

Plain text (``.csv``, ``.tsv``, ``.txt``): one header row of column names that carry their unit,
then numbers; comma, tab, semicolon or whitespace separated (with semicolons a decimal comma
is read as a decimal point: ``0,25;1,5`` is 0.25 and 1.5). Lines starting with ``#`` before
the header hold metadata as ``# key = value``. A header naming none of the columns below (no
header, or other names) is refused with the first row shown.

* piezo travel: ``piezo_um``, ``piezo_nm``, ``piezo_m``, ``height_um``, ``height_nm`` or
  ``height_m``, either sign: increasing towards the sample (a piezo extension) or decreasing
  (a JPK-style height); :func:`afm.curve.approach_segment` orients it and keeps the rows up
  to the turn when the file goes on into the retract
* force: ``force_nN``, ``force_pN``, ``force_uN`` or ``force_N``; or deflection
  ``deflection_nm`` / ``deflection_um`` (times k), or ``deflection_V`` (times sensitivity
  and k)
* optional ``time_s``
* metadata: ``spring_constant_N_per_m`` (required), ``sensitivity_nm_per_V`` (for volts),
  ``group`` (batch grouping; default: the folder name)

A force curve whose approach travel or force range cannot be an AFM's in the declared unit
(:data:`TRAVEL_RANGE_UM`, :data:`FORCE_RANGE_NN`) is refused, naming the unit it looks like:
metres written under ``piezo_um`` give a travel of a few pm.

Creep records (:func:`read_creep`): ``time_s``, a force column, and ``indentation_um`` (or
``indentation_nm``, ``indentation_m``), or a piezo/height column with metadata
``contact_point_um``; the indentation is then ``height - contact_point - F/k``. A mean clamp
force or a given indentation outside the same ranges is refused the same way.

Instrument files (JPK ``.jpk-force``, Asylum ``.ibw``, AFM-Workshop ``.csv``, NT-MDT ``.txt``
and the other formats afmformats reads) go to :mod:`afm.instrument_io`: every file whose
suffix only afmformats reads, and every ``.csv``/``.txt`` that one of afmformats' format
recipes recognises, unless its header row names one of the columns above (afmformats accepts
any ``.csv`` as AFM-Workshop's).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from afm.creep_data import CreepData
from afm.curve import (
    ForceCurve,
    approach_segment,
    force_from_deflection,
    spring_constant_nN_per_um,
)
from afm.instrument_io import (
    hdf5_map_keys,
    iter_instrument_curves,
    read_instrument_creep,
    read_instrument_file,
    recognises,
)
from oocyte_fe.checks import excerpt, unit_that_fits
from oocyte_fe.errors import InputError

TEXT_SUFFIXES = {".csv", ".tsv", ".txt"}
PIEZO_COLUMNS = {
    "piezo_um": 1.0,
    "piezo_nm": 1e-3,
    "piezo_m": 1e6,
    "height_um": 1.0,
    "height_nm": 1e-3,
    "height_m": 1e6,
}
FORCE_COLUMNS = {"force_nN": 1.0, "force_pN": 1e-3, "force_uN": 1e3, "force_N": 1e9}
DEFLECTION_COLUMNS = {"deflection_um": 1.0, "deflection_nm": 1e-3}
INDENTATION_COLUMNS = {"indentation_um": 1.0, "indentation_nm": 1e-3, "indentation_m": 1e6}

TRAVEL_RANGE_UM = (1e-3, 1e3)
"""Approach travel (largest less smallest piezo position) an AFM force curve can have, um:
1 nm (below it no contact can be resolved) to 1 mm (piezo scanners reach 15-100 um)."""
FORCE_RANGE_NN = (1e-3, 1e6)
"""Force range (largest less smallest) an AFM force curve can have, nN: 1 pN (the thermal
noise of the softest cantilevers is several pN) to 1 mN (a 100 N/m lever bent 10 um)."""
_UNIT_NAMES = {
    "m": "metres",
    "um": "micrometres",
    "nm": "nanometres",
    "N": "newtons",
    "uN": "micronewtons",
    "nN": "nanonewtons",
    "pN": "piconewtons",
}


def read_table(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """Columns (name -> float array) and ``# key = value`` metadata of a text table."""
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except FileNotFoundError:
        raise InputError(path, "", "an existing file") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "a text table (CSV/TSV)") from None
    meta: dict[str, str] = {}
    body = []
    numbers = []  # each row's line in the file (1 = the first)
    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            key, sep, value = stripped.lstrip("#").partition("=")
            if sep and not body:
                meta[key.strip()] = value.strip()
            continue
        body.append(stripped)
        numbers.append(number)
    if not body:
        raise InputError(path, "", "a header row and data rows (the file is empty)")
    delimiter = next((d for d in ("\t", ";", ",") if d in body[0]), None)
    names = [n.strip() for n in re.split(delimiter or r"\s+", body[0])]
    if len(names) < 2:
        raise InputError(path, "header", "at least two columns (piezo and force)", body[0])
    if not OWN_COLUMNS & set(names):
        raise InputError(path, "header", HEADER_EXPECTED, excerpt(body[0]))
    if delimiter == ";":  # a European export: decimal commas
        body = [body[0], *(row.replace(",", ".") for row in body[1:])]
    if len(body) < 2:
        raise InputError(path, "", "data rows below the header")
    try:
        data = np.loadtxt(body[1:], delimiter=delimiter, ndmin=2)
    except ValueError:
        raise _bad_row(path, body, numbers, delimiter) from None
    if data.shape[1] != len(names):
        raise InputError(path, "header", f"{data.shape[1]} column names", len(names))
    return {n: data[:, i] for i, n in enumerate(names)}, meta


def _bad_row(path: Path, body: list[str], numbers: list[int], delimiter: str | None) -> InputError:
    """The error for the first data row ``np.loadtxt`` refuses, named by its line in the file."""
    width = len(re.split(delimiter or r"\s+", body[0]))
    for row, number in zip(body[1:], numbers[1:], strict=True):
        cells = [c.strip() for c in re.split(delimiter or r"\s+", row)]
        try:
            [float(c) for c in cells]
        except ValueError:
            return InputError(path, f"line {number}", "numbers in every data row", excerpt(row))
        if len(cells) != width:
            return InputError(path, f"line {number}", f"{width} cells, as the header", len(cells))
    return InputError(path, "", "numbers in every data row")


def _pick(columns: dict, options: dict[str, float]) -> np.ndarray | None:
    name = _name(columns, options)
    return None if name is None else columns[name] * options[name]


def _name(columns: dict, options: dict[str, float]) -> str | None:
    """The first of ``options``' column names the table has."""
    return next((name for name in options if name in columns), None)


def _meta_float(meta: dict[str, str], key: str, given: float | None, path: Path) -> float | None:
    if given is not None:
        return float(given)
    if key not in meta:
        return None
    try:
        return float(meta[key])
    except ValueError:
        raise InputError(path, key, "a number", meta[key]) from None


def _force(
    columns: dict, meta: dict, k_N_per_m: float, sensitivity: float | None, path: Path
) -> np.ndarray:
    force = _pick(columns, FORCE_COLUMNS)
    if force is not None:
        return force
    deflection = _pick(columns, DEFLECTION_COLUMNS)
    if deflection is not None:
        return deflection * spring_constant_nN_per_um(k_N_per_m, str(path))
    if "deflection_V" in columns:
        s = _meta_float(meta, "sensitivity_nm_per_V", sensitivity, path)
        if s is None:
            raise InputError(path, "sensitivity_nm_per_V", "the sensitivity for deflection_V")
        return force_from_deflection(columns["deflection_V"], s, k_N_per_m, str(path))
    names = [*FORCE_COLUMNS, *DEFLECTION_COLUMNS, "deflection_V"]
    raise InputError(path, "header", f"a force column: one of {', '.join(names)}")


OWN_COLUMNS = {
    *PIEZO_COLUMNS,
    *FORCE_COLUMNS,
    *DEFLECTION_COLUMNS,
    *INDENTATION_COLUMNS,
    "deflection_V",
    "time_s",
}
HEADER_EXPECTED = (
    f"a header row of unit-named columns: travel {'|'.join(PIEZO_COLUMNS)}, force "
    f"{'|'.join(FORCE_COLUMNS)} (or {'|'.join(DEFLECTION_COLUMNS)}|deflection_V), optional "
    "time_s; comma, tab or semicolon separated"
)


def _first_row(path: Path) -> str | None:
    """The first line of ``path`` that is neither blank nor a ``#`` comment (None: none)."""
    with path.open(errors="replace") as fh:
        for line in fh:
            stripped = line.strip()
            if stripped and not stripped.startswith("#"):
                return stripped
    return None


def _is_own_table(path: Path) -> bool:
    """True when the first row that is not a ``#`` comment names one of this module's columns,
    or, in a ``.csv``/``.tsv``, is a row of comma-, tab- or semicolon-separated cells (a table
    without a valid header, which :func:`read_table` refuses naming the row; afmformats'
    AFM-Workshop ``.csv`` starts with the line ``Force-Distance Curve``)."""
    try:
        row = _first_row(path)
    except OSError:
        return True
    if row is None:
        return True
    if OWN_COLUMNS & {n.strip() for n in re.split(r"[,;\t\s]+", row)}:
        return True
    return path.suffix.lower() in {".csv", ".tsv"} and any(d in row for d in ",;\t")


def is_instrument_file(path: str | Path) -> bool:
    """True when ``path`` goes to afmformats (module docstring), False for a plain table."""
    path = Path(path)
    if path.suffix.lower() not in TEXT_SUFFIXES:
        return True
    return not _is_own_table(path) and recognises(path)


def iter_curves(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
    selection: range | None = None,
) -> Iterator[ForceCurve]:
    """Every approach curve of a file, one at a time (:func:`read_curves`); an afmformats
    HDF5 force map is read as the curves are taken. ``selection``: only the curves at these
    positions in file order (an HDF5 map reads no other; :func:`count_curves`)."""
    if is_instrument_file(path):
        yield from iter_instrument_curves(
            path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel, selection
        )
    elif selection is None or 0 in selection:
        yield read_curve(path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel)


def count_curves(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> int | None:
    """How many curves :func:`iter_curves` gives for these arguments, where that is known
    without reading them (an afmformats HDF5 map); else None. Lets
    :func:`afm.batch.fit_batch` hand parts of one large map to several processes."""
    keys = hdf5_map_keys(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    return None if keys is None else len(keys)


def read_curves(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> list[ForceCurve]:
    """Every approach curve of a file: one for a table or single curve, all of a force map.

    Arguments override the file's metadata; ``height_channel`` applies to instrument files
    (:mod:`afm.instrument_io`).
    """
    return list(iter_curves(path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel))


def read_curve(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> ForceCurve:
    """Read one approach curve (the first of a force map); see :func:`read_curves`.

    A text table has one travel column (``height_channel`` ``"auto"`` or ``"piezo"``).
    """
    if is_instrument_file(path):
        return read_instrument_file(
            path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel
        )
    if height_channel not in ("auto", "piezo"):
        raise InputError(path, "height_channel", "auto or piezo for a text table", height_channel)
    return _read_table_curve(Path(path), spring_constant_N_per_m, sensitivity_nm_per_V)


@dataclass(frozen=True)
class TableTravel:
    """A curve table's rows as read: the travel towards the sample [um] (a height decreasing
    towards it turned round: :func:`afm.curve.approach_segment`), the force [nN], the end
    (exclusive) of the approach, the spring constant [nN/um], the columns and metadata."""

    towards_um: np.ndarray
    force_nN: np.ndarray
    approach_end: int
    spring_constant_nN_per_um: float
    columns: dict[str, np.ndarray]
    meta: dict[str, str]


def read_table_travel(
    path: str | Path, spring_constant_N_per_m: float | None, sensitivity_nm_per_V: float | None
) -> TableTravel:
    """Read a curve table (:func:`read_table`) into internal units, the approach's direction
    found from the rows (either sign of the piezo/height column), the approach's travel and
    force range checked against what an AFM force curve can have (:data:`TRAVEL_RANGE_UM`,
    :data:`FORCE_RANGE_NN`: a unit mistake is refused, naming the unit it looks like)."""
    path = Path(path)
    columns, meta = read_table(path)
    k = _meta_float(meta, "spring_constant_N_per_m", spring_constant_N_per_m, path)
    if k is None:
        raise InputError(path, "spring_constant_N_per_m", "the spring constant (metadata)")
    k_internal = spring_constant_nN_per_um(k, str(path))
    piezo_name = _name(columns, PIEZO_COLUMNS)
    if piezo_name is None:
        raise InputError(path, "header", f"a piezo column: one of {', '.join(PIEZO_COLUMNS)}")
    force = _force(columns, meta, k, sensitivity_nm_per_V, path)
    piezo = columns[piezo_name] * PIEZO_COLUMNS[piezo_name]
    force_name = _name(columns, {**FORCE_COLUMNS, **DEFLECTION_COLUMNS}) or "deflection_V"
    head = _swapped_head(piezo, force)
    if head is not None:
        raise InputError(
            path,
            f"{piezo_name}, {force_name}",
            "the travel in the piezo/height column and the force in the force column",
            f"columns that look swapped: {force_name} moves one way in even steps, like a "
            f"travel, and {piezo_name} changes by {100 * head:.2g} % of its range over its "
            "first tenth of the rows, like a force before contact",
        )
    towards, end = approach_segment(piezo, force, str(path), piezo_name)
    _check_range(path, piezo_name, np.ptp(towards[:end]), TRAVEL_RANGE_UM, "an approach travel")
    _check_range(path, force_name, np.ptp(force[:end]), FORCE_RANGE_NN, "a force range")
    return TableTravel(towards, force, end, k_internal, columns, meta)


SWAP_EVEN_STEPS = 0.05
"""Largest spread of a column's steps (SD over mean) that reads as a travel's even steps."""
SWAP_HEAD_SPAN = 0.05
"""Largest change over the first tenth of the rows (a fraction of the column's range) that
reads as a force's baseline: a travel in even steps changes by about a tenth there."""


def _swapped_head(travel: np.ndarray, force: np.ndarray) -> float | None:
    """When the columns look swapped (``force`` moves one way in even steps, like a travel,
    and ``travel`` hardly changes over its first tenth of the rows, like a force before
    contact, whose noise makes a force never move in even steps), the change of ``travel``
    over that tenth as a fraction of its range; else None."""
    if travel.size < 20 or not (np.all(np.isfinite(travel)) and np.all(np.isfinite(force))):
        return None
    steps = np.diff(force)
    one_way = bool(np.all(steps > 0) or np.all(steps < 0))
    if not one_way or np.std(steps) > SWAP_EVEN_STEPS * abs(steps.mean()):
        return None
    span = float(np.ptp(travel))
    head = float(np.ptp(travel[: travel.size // 10])) / span if span > 0 else 0.0
    return head if head < SWAP_HEAD_SPAN else None


def _read_table_curve(
    path: Path, spring_constant_N_per_m: float | None, sensitivity_nm_per_V: float | None
) -> ForceCurve:
    table = read_table_travel(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    end, time = table.approach_end, table.columns.get("time_s")
    return ForceCurve(
        table.towards_um[:end],
        table.force_nN[:end],
        table.spring_constant_nN_per_um,
        str(path),
        table.meta.get("group", path.parent.name),
        None if time is None else time[:end],
    )


def _check_range(
    path: Path, column: str, span: float, bounds: tuple[float, float], what: str
) -> None:
    """Refuse a travel [um] or force range [nN] (``span``, largest less smallest, in internal
    units) outside ``bounds`` that was read from ``column``. The message names the column of
    the same quantity whose unit would put it inside: metres under ``piezo_um`` give a travel
    of 8e-06 um, which as ``piezo_m`` is ``8e-06 * 1e6`` = 8 um ("looks like metres")."""
    low, high = bounds
    if span == 0 or not np.isfinite(span) or low <= span <= high:  # a flat column is no unit
        return  # mistake (the fit says why); NaN or inf is refused, by row, where the curve is made
    options = next(
        (group for group in (PIEZO_COLUMNS, INDENTATION_COLUMNS) if column in group),
        {**FORCE_COLUMNS, **DEFLECTION_COLUMNS},
    )
    unit = "nN" if column not in {**PIEZO_COLUMNS, **INDENTATION_COLUMNS} else "um"
    stem = column.rpartition("_")[0] + "_"
    scales = {n.removeprefix(stem): f for n, f in options.items() if n.startswith(stem)}
    got = f"{what} of {span:.3g} {unit}"
    fits = unit_that_fits(column, span, bounds, scales)  # deflection_V: no guess
    if fits is not None:
        other, rescaled = fits
        name = _UNIT_NAMES[other.removeprefix(stem)]
        got += f": looks like {name} ({other} would give {rescaled:.3g} {unit})"
    expected = f"{what} that an AFM force curve can have ({low:g} to {high:g} {unit})"
    raise InputError(path, column, expected, got)


def write_curve(curve: ForceCurve, path: str | Path) -> Path:
    """Write ``curve`` as CSV (``piezo_um, force_nN``) with its spring constant and group."""
    path = Path(path)
    header = (
        f"# spring_constant_N_per_m = {float(curve.spring_constant_nN_per_um) / 1e3!r}\n"
        f"# group = {curve.group}\n"
        "piezo_um,force_nN\n"
    )
    rows = np.column_stack([curve.piezo_um, curve.force_nN])
    with path.open("w") as fh:
        fh.write(header)
        np.savetxt(fh, rows, delimiter=",", fmt="%.9g")
    return path


def read_creep(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    height_channel: str = "auto",
) -> CreepData:
    """Read a force-clamp hold as :class:`afm.creep_data.CreepData`.

    A creep table (module docstring), or an instrument force-clamp file
    (:func:`afm.instrument_io.read_instrument_creep`; ``spring_constant_N_per_m`` and
    ``height_channel`` apply to those).
    """
    path = Path(path)
    if is_instrument_file(path):
        return read_instrument_creep(path, spring_constant_N_per_m, None, height_channel)
    columns, meta = read_table(path)
    if "time_s" not in columns:
        raise InputError(path, "header", "a time_s column")
    k = _meta_float(meta, "spring_constant_N_per_m", None, path)
    force = _force(columns, meta, k if k is not None else float("nan"), None, path)
    indentation = _pick(columns, INDENTATION_COLUMNS)
    if indentation is None:
        height = _pick(columns, PIEZO_COLUMNS)
        contact = _meta_float(meta, "contact_point_um", None, path)
        if height is None or contact is None or k is None:
            raise InputError(
                path,
                "header",
                "indentation_um, or a height column with metadata contact_point_um and "
                "spring_constant_N_per_m",
            )
        indentation = height - contact - force / spring_constant_nN_per_um(k, str(path))
    else:  # a unit mistake in the file's own indentation column ("looks like metres")
        name = _name(columns, INDENTATION_COLUMNS) or ""
        _check_range(
            path, name, float(np.max(np.abs(indentation))), TRAVEL_RANGE_UM, "an indentation"
        )
    force_name = _name(columns, {**FORCE_COLUMNS, **DEFLECTION_COLUMNS}) or "deflection_V"
    level = abs(float(np.mean(force)))
    _check_range(path, force_name, level, FORCE_RANGE_NN, "a mean clamp force")
    return CreepData(columns["time_s"], force, indentation, str(path))


def write_creep(
    path: str | Path,
    time_s: np.ndarray,
    force_nN: np.ndarray,
    height_um: np.ndarray,
    contact_point_um: float,
    spring_constant_N_per_m: float,
    note: str = "",
) -> Path:
    """Write a creep record as CSV (``time_s, force_nN, height_um``) with its metadata."""
    path = Path(path)
    lines = [f"# {line}" for line in note.splitlines()]
    lines += [
        f"# contact_point_um = {float(contact_point_um)!r}",
        f"# spring_constant_N_per_m = {float(spring_constant_N_per_m)!r}",
        "time_s,force_nN,height_um",
    ]
    with path.open("w") as fh:
        fh.write("\n".join(lines) + "\n")
        np.savetxt(fh, np.column_stack([time_s, force_nN, height_um]), delimiter=",", fmt="%.10g")
    return path
