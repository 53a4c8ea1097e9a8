"""Reading a force-displacement table (Table II of seed 000) with its units in the header.

Columns: ``displacement_um`` (strictly increasing, at least :data:`MIN_ROWS` rows, within the
physical length bounds), ``force_experiment_uN`` (not all equal: a constant force leaves
nothing to calibrate and R^2 undefined) and optionally ``force_simulation_uN`` (the paper's
model); forces within the physical force bounds (``oocyte_fe.checks.QUANTITIES``) and
converted to nN on reading.
"""

from __future__ import annotations

import csv
import difflib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError

UN_TO_NN = 1.0e3
MIN_ROWS = 3
"""Fewest rows of a table a calibration is fitted to (a curve, not a point)."""


@dataclass(frozen=True, eq=False)
class ForceDisplacement:
    """Measured press: displacement (um), measured force (nN), the paper's model force (nN)."""

    displacement_um: np.ndarray
    force_nN: np.ndarray
    paper_model_nN: np.ndarray | None = None
    source: str = ""


def read_force_displacement(path: str | Path) -> ForceDisplacement:
    """Read the CSV; raise :class:`InputError` naming file and column on bad content."""
    path = Path(path)
    try:
        reader = csv.DictReader(checks.read_text(path).splitlines())
        rows, lines = [], []  # each row and its line in the file (blank lines are skipped)
        for row in reader:
            rows.append(row)
            lines.append(reader.line_num)
    except csv.Error as exc:
        raise InputError(str(path), "", f"a comma-separated table ({exc})") from None
    header = set(reader.fieldnames or ())
    for column in ("displacement_um", "force_experiment_uN"):
        if column not in header:
            close = difflib.get_close_matches(column, [str(h) for h in header], n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise InputError(str(path), column, f"this column (units in the name){hint}")
    columns = {}
    for name in ("displacement_um", "force_experiment_uN", "force_simulation_uN"):
        if name not in header:
            continue
        values = []
        for line, row in zip(lines, rows, strict=True):
            try:
                values.append(float(row[name]))
            except (TypeError, ValueError):
                raise InputError(
                    str(path), name, f"numbers in every row (line {line})", got=row[name]
                ) from None
        columns[name] = np.array(values)
        if not np.all(np.isfinite(columns[name])):
            raise InputError(str(path), name, "finite numbers in every row (no nan, inf)")
    d = columns["displacement_um"]
    if len(d) < MIN_ROWS:
        raise InputError(str(path), "displacement_um", f"at least {MIN_ROWS} rows", got=len(d))
    if np.any(np.diff(d) <= 0) or d[0] < 0 or d[-1] > checks.QUANTITIES["length_um"][1]:
        bad = np.flatnonzero(np.diff(d) <= 0)
        where = f" (line {lines[bad[0] + 1]} is not above line {lines[bad[0]]})" if len(bad) else ""
        raise InputError(
            str(path),
            "displacement_um",
            f"non-negative, strictly increasing, at most 1e6 um{where}",
        )
    high = checks.QUANTITIES["force_nN"][1]
    forces = {}
    for name in ("force_experiment_uN", "force_simulation_uN"):
        if name in columns:
            if np.any(np.abs(columns[name]) > high / UN_TO_NN):  # before scaling: no overflow
                raise InputError(
                    str(path), name, f"forces of a physical size (|F| <= {high / UN_TO_NN:g} uN)"
                )
            forces[name] = columns[name] * UN_TO_NN
    if np.ptp(forces["force_experiment_uN"]) == 0:
        raise InputError(
            str(path),
            "force_experiment_uN",
            "forces that vary (a constant force calibrates nothing; R^2 is undefined)",
        )
    return ForceDisplacement(
        d,
        forces["force_experiment_uN"],
        forces.get("force_simulation_uN"),
        str(path),
    )
