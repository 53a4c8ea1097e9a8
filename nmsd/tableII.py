"""Reading a measured force-displacement table (Table II of seed 000, or a lab's own press).

Columns, each with its unit in the name, converted to the internal um and nN on reading:

- ``displacement_<unit>``, unit one of :data:`DISPLACEMENT_UNITS` (nm, um, mm, m): strictly
  increasing, at least :data:`MIN_ROWS` rows, within the physical length bounds;
- ``force_experiment_<unit>``, unit one of :data:`FORCE_UNITS` (nN, uN, mN, N): the measured
  force, compression positive, not all equal (a constant force leaves nothing to calibrate
  and R^2 undefined);
- optionally ``force_simulation_<unit>``: the paper's model column (absent in a lab's file).

A force below ``-NEGATIVE_NOISE`` times the largest |force| is refused (compression recorded
negative); smaller negatives are baseline noise. A table whose peak force or displacement span
no pipette press of a cell can have (:data:`FORCE_PEAK_RANGE_NN`,
:data:`DISPLACEMENT_SPAN_RANGE_UM`) is refused naming the unit it looks like: forces in nN
written under ``_uN`` peak at tens of thousands of "uN".
"""

from __future__ import annotations

import csv
import difflib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError

UN_TO_NN = 1.0e3
MIN_ROWS = 3
"""Fewest rows of a table a calibration is fitted to (a curve, not a point)."""
DISPLACEMENT_UNITS = {"nm": 1.0e-3, "um": 1.0, "mm": 1.0e3, "m": 1.0e6}
"""Displacement column units and their factor to um."""
FORCE_UNITS = {"nN": 1.0, "uN": 1.0e3, "mN": 1.0e6, "N": 1.0e9}
"""Force column units and their factor to nN."""
FORCE_PEAK_RANGE_NN = (1.0, 1.0e6)
"""Largest |measured force| a pipette pressing a cell can give, nN: 1 nN (below the
resolution of a pipette force sensor) to 1 mN (Table II peaks at 55 uN)."""
DISPLACEMENT_SPAN_RANGE_UM = (1.0, 1.0e4)
"""Span of the displacements (largest less smallest), um: at least 1 um (the lattice spacing
of the Table I cell is 6.8 um, a press step 1.6 um), at most 1 cm (the largest cell)."""
NEGATIVE_NOISE = 0.05
"""Negative forces down to this fraction of the largest |force| are baseline noise."""


@dataclass(frozen=True, eq=False)
class ForceDisplacement:
    """Measured press: displacement (um), measured force (nN), the paper's model force (nN)."""

    displacement_um: np.ndarray
    force_nN: np.ndarray
    paper_model_nN: np.ndarray | None = None
    source: str = ""


def _column(path: Path, header: list[str], stem: str, units: Mapping[str, float]) -> str | None:
    """The one header name ``<stem>_<unit>`` with a unit of ``units``, or None."""
    found = [f"{stem}_{u}" for u in units if f"{stem}_{u}" in header]
    if len(found) > 1:
        raise InputError(path, found[1], f"one {stem} column (also {found[0]})")
    return found[0] if found else None


def _missing(path: Path, header: list[str], stem: str, units: Mapping[str, float]) -> InputError:
    """The error for a required column ``<stem>_<unit>`` the header lacks."""
    accepted = [f"{stem}_{u}" for u in units]
    close = [(h, m) for h in header for m in difflib.get_close_matches(h, accepted, n=1)]
    hint = f" (did you mean {close[0][1]!r} for {close[0][0]!r}?)" if close else ""
    return InputError(
        path, f"{stem}_<unit>", f"a column {' or '.join(accepted)} (units in the name){hint}"
    )


def _plausible(
    path: Path,
    column: str,
    value: float,
    bounds: tuple[float, float],
    units: Mapping[str, float],
    what: str,
) -> None:
    """Refuse ``value`` (internal units, read from ``column``) outside ``bounds``, naming the
    unit of the same quantity that would put it inside ("looks like nN")."""
    low, high = bounds
    if low <= value <= high:
        return
    internal = "um" if units is DISPLACEMENT_UNITS else "nN"
    looks = ""
    fits = checks.unit_that_fits(column, value, bounds, dict(units))
    if fits is not None:
        other, rescaled = fits
        looks = (
            f"; the values look like {other.rpartition('_')[2]}: {other} would give "
            f"{rescaled:.3g} {internal}"
        )
    expected = (
        f"{what} that a pipette press of a cell can have ({low:g} to {high:g} {internal}){looks}"
    )
    got = f"{value:.3g} {internal}"
    raise InputError(path, column, expected, got)


def read_force_displacement(path: str | Path) -> ForceDisplacement:
    """Read the table (cells separated by commas, or by tabs or semicolons if the header row
    holds one, a decimal comma read as a point with semicolons: a spreadsheet's export); raise
    :class:`InputError` naming file and column on bad content."""
    path = Path(path)
    text = checks.read_text(path).splitlines()
    delimiter = checks.table_delimiter(next((line for line in text if line.strip()), ""))
    try:
        reader = csv.DictReader(text, delimiter=delimiter)
        rows, lines = [], []  # each row and its line in the file (blank lines are skipped)
        for row in reader:
            rows.append(row)
            lines.append(reader.line_num)
    except csv.Error as exc:
        what = checks.SEPARATORS[delimiter]
        raise InputError(str(path), "", f"a {what}-separated table ({exc})") from None
    header = [str(h) for h in reader.fieldnames or ()]
    if not header:
        raise InputError(path, "", "a header row and data rows (the file is empty)")
    if not rows:
        raise InputError(path, "", "data rows below the header (the file has none)")
    names = {}
    for stem, units, required in (
        ("displacement", DISPLACEMENT_UNITS, True),
        ("force_experiment", FORCE_UNITS, True),
        ("force_simulation", FORCE_UNITS, False),
    ):
        name = _column(path, header, stem, units)
        if name is None and required:
            raise _missing(path, header, stem, units)
        if name is not None:
            names[stem] = name
    columns = {}
    for stem, name in names.items():
        values = []
        for line, row in zip(lines, rows, strict=True):
            cell = row[name]
            if delimiter == ";" and isinstance(cell, str):  # a European export's decimal comma
                cell = cell.replace(",", ".")
            try:
                value = float(cell)
            except (TypeError, ValueError):
                raise InputError(
                    str(path), name, f"numbers in every row (line {line})", got=row[name]
                ) from None
            if not np.isfinite(value):
                raise InputError(
                    path, name, f"finite numbers in every row (no nan, inf; line {line})", value
                )
            values.append(value)
        columns[stem] = np.array(values)
    d_name = names["displacement"]
    d = columns["displacement"] * DISPLACEMENT_UNITS[d_name.rpartition("_")[2]]
    if len(d) < MIN_ROWS:
        raise InputError(str(path), d_name, f"at least {MIN_ROWS} rows", got=len(d))
    if np.any(np.diff(d) <= 0) or d[0] < 0 or d[-1] > checks.QUANTITIES["length_um"][1]:
        bad = np.flatnonzero(np.diff(d) <= 0)
        where = f" (line {lines[bad[0] + 1]} is not above line {lines[bad[0]]})" if len(bad) else ""
        raise InputError(
            str(path),
            d_name,
            f"non-negative, strictly increasing, at most 1e6 um{where}",
        )
    high = checks.QUANTITIES["force_nN"][1]
    forces = {}
    for stem in ("force_experiment", "force_simulation"):
        if stem not in names:
            continue
        name, raw = names[stem], columns[stem]
        unit = name.rpartition("_")[2]
        if np.any(np.abs(raw) > high / FORCE_UNITS[unit]):  # before scaling: no overflow
            raise InputError(
                path,
                name,
                f"forces of a physical size (|F| <= {high / FORCE_UNITS[unit]:g} {unit})",
            )
        below = np.flatnonzero(raw < -NEGATIVE_NOISE * np.abs(raw).max())
        if len(below):
            raise InputError(
                path,
                name,
                f"forces >= 0: compression is positive (line {lines[below[0]]}; flip the sign of "
                f"a curve recorded with compression negative; negatives within "
                f"{100 * NEGATIVE_NOISE:g} % of the peak are read as baseline noise)",
                got=float(raw[below[0]]),
            )
        forces[stem] = raw * FORCE_UNITS[unit]
    f_name = names["force_experiment"]
    if np.ptp(forces["force_experiment"]) == 0:
        raise InputError(
            str(path),
            f_name,
            "forces that vary (a constant force calibrates nothing; R^2 is undefined)",
        )
    peak = float(np.abs(forces["force_experiment"]).max())
    _plausible(path, f_name, peak, FORCE_PEAK_RANGE_NN, FORCE_UNITS, "a peak force")
    span = float(np.ptp(d))
    _plausible(path, d_name, span, DISPLACEMENT_SPAN_RANGE_UM, DISPLACEMENT_UNITS, "a span")
    return ForceDisplacement(
        d,
        forces["force_experiment"],
        forces.get("force_simulation"),
        str(path),
    )
