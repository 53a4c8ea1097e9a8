"""Reading the microchannel tables (CSV with units in the column names) into internal units.

A column is ``<stem>_<unit>``, e.g. ``viscosity_Pa_s`` or ``pressure_hPa``; the unit suffix
is looked up in :mod:`oocyte_fe.microchannel.units`. Every error names the file, the column and
what was expected.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.io.columns import read_columns
from oocyte_fe.microchannel import units


def _suggest(name: str, columns: dict[str, np.ndarray]) -> str:
    close = difflib.get_close_matches(name, list(columns), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def quantity(columns: dict[str, np.ndarray], stem: str, kind: str, path: Path) -> np.ndarray:
    """The column ``<stem>_<unit>`` converted to internal units (unit from the name)."""
    table = units.QUANTITIES[kind]
    found = [(name, name[len(stem) + 1 :]) for name in columns if name.startswith(stem + "_")]
    if not found:
        raise InputError(
            path,
            stem,
            f"a column {stem}_<unit> with unit one of {', '.join(table)}"
            + _suggest(f"{stem}_{next(iter(table))}", columns),
        )
    name, unit = found[0]
    if unit not in table:
        raise InputError(path, name, f"a {kind} unit, one of {', '.join(table)}", got=unit)
    return columns[name] * table[unit]


def _physical(values: np.ndarray, path: Path, column: str, kind: str) -> np.ndarray:
    """``values`` (internal units) within the physical bounds of ``checks.QUANTITIES[kind]``."""
    low, high, unit = checks.QUANTITIES[kind]
    bad = ~((values >= low) & (values <= high))
    if np.any(bad):
        raise InputError(
            path, column, f"values in [{low:g}, {high:g}] {unit}", got=float(values[bad][0])
        )
    return values


@dataclass(frozen=True)
class FlowCurve:
    """Viscosity (kPa s) against shear rate (1/s), e.g. Table 2 of seed 001."""

    shear_rate: np.ndarray
    viscosity: np.ndarray
    source: str


def read_flow_curve(path: Path) -> FlowCurve:
    """Read ``strain_rate_1_s`` (or ``shear_rate_1_s``) and ``viscosity_<unit>`` columns."""
    columns = read_columns(path)
    stem = "strain_rate" if any(c.startswith("strain_rate_") for c in columns) else "shear_rate"
    rate = _physical(quantity(columns, stem, "shear_rate", path), path, stem, "shear_rate_per_s")
    eta = _physical(
        quantity(columns, "viscosity", "viscosity", path), path, "viscosity", "viscosity_kPa_s"
    )
    return FlowCurve(rate, eta, str(path))


@dataclass(frozen=True)
class DeformationTable:
    """Axis ratio (minor/major, <= 1) of the deformed oocyte against driving pressure (kPa)."""

    pressure: np.ndarray
    ratio_experiment: np.ndarray
    ratio_simulation: np.ndarray
    source: str


def read_deformation_table(path: Path) -> DeformationTable:
    """Read ``pressure_<unit>``, ``ratio_experiment`` and ``ratio_simulation`` columns."""
    columns = read_columns(path)
    pressure = _physical(
        quantity(columns, "pressure", "pressure", path), path, "pressure", "pressure_kPa"
    )
    name = next(c for c in columns if c.startswith("pressure_"))
    values, counts = np.unique(columns[name], return_counts=True)
    if np.any(counts > 1):  # two rows of one pressure: which one is compared (and fitted)?
        raise InputError(path, name, "each pressure on one row", got=float(values[counts > 1][0]))
    ratios = []
    for name in ("ratio_experiment", "ratio_simulation"):
        if name not in columns:
            raise InputError(
                path, name, "this column (axis ratio, dimensionless)" + _suggest(name, columns)
            )
        r = columns[name]
        if not np.all((r > 0) & (r <= 1)):
            raise InputError(
                path, name, "axis ratios in (0, 1]", got=float(r[(r <= 0) | (r > 1)][0])
            )
        ratios.append(r)
    order = np.argsort(pressure)
    return DeformationTable(pressure[order], ratios[0][order], ratios[1][order], str(path))
