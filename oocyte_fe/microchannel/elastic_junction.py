"""The AFM-elastic cell loaded by the flow at the junction (issue 30 part 2, one-way).

The traction of the medium on the cell (:mod:`oocyte_fe.microchannel.vof.traction`: the
``alpha = 0.5`` contour of a VOF run at the junction crossing, ``t = sigma n``) loads the
layered plane-strain FE cell (the seed's 140 um cell with a 15 um ZP; the AFM moduli, ZP 7.0
and cytoplasm 1.55 kPa, nu = 0.5) as a free cell (``support = "inertia_relief"``: the net
force accelerates it as a rigid body). One-way reading: the traction is put on the undeformed
outline at the polar angle of each contour edge about the contour's centroid; the contour's
mean pressure is removed (a uniform pressure does not deform the incompressible cell). The
answer is the aspect ratio ``b/a`` of the deformed section (principal extents, see
:func:`oocyte_fe.experiment.analysis.outline_extents_um`).

Limits: one-way (the flow is computed around the liquid, deforming VOF cell, not around the
elastic one, and not recomputed), elastic (the traction's time at the junction, about a
millisecond, is short compared with the Prony times, so the instantaneous moduli apply), and
the VOF traction's own momentum check misses by 7-30 % (docs/microchannel.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import outline_extents_um
from oocyte_fe.experiment.driver import ExperimentResult
from oocyte_fe.experiment.loads import write_traction_table
from oocyte_fe.microchannel.tables import read_columns

COLUMNS = ("arc_angle_deg", "x_um", "y_um", "t_x_kPa", "t_y_kPa")


@dataclass(frozen=True)
class ElasticCellAtJunction:
    """The FE result, b/a of the deformed section, the table it was loaded with."""

    experiment: ExperimentResult
    b_over_a: float
    table: Path


def read_vof_traction(path: Path) -> np.ndarray:
    """The VOF traction CSV as rows (angle deg, x um, y um, t_x kPa, t_y kPa); checked."""
    cols = read_columns(path)  # finite numbers, every fault named with its line
    if any(c not in cols for c in COLUMNS):
        raise InputError(path, "columns", ", ".join(COLUMNS), got=", ".join(cols))
    if cols["x_um"].size < 8:
        raise InputError(path, "rows", "at least 8 rows")
    return np.column_stack([cols[c] for c in COLUMNS])


def fe_traction_table(rows: np.ndarray, radius_um: float, path: Path) -> Path:
    """The FE's traction table: each edge's traction on the undeformed outline at its polar
    angle about the contour's centroid (length-weighted), less the mean normal traction."""
    x = rows[:, 1:3]
    t = rows[:, 3:5]
    closed = np.vstack([x, x[:1]])
    ds = np.linalg.norm(np.diff(closed, axis=0), axis=1)  # rows are ordered around
    centre = (x * ds[:, None]).sum(axis=0) / ds.sum()
    d = x - centre
    n = d / np.linalg.norm(d, axis=1)[:, None]
    p_mean = -np.sum(np.einsum("ij,ij->i", t, n) * ds) / ds.sum()
    t = t + p_mean * n  # the mean pressure removed
    return write_traction_table(path, radius_um * n, t, "VOF traction, mean pressure removed")


def elastic_cell_at_junction(
    traction_csv: Path,
    folder: Path,
    zona_kPa: float = 7.0,
    cytoplasm_kPa: float = 1.55,
    diameter_um: float = 140.0,
    zona_um: float = 15.0,
    mesh_um: float = 4.0,
) -> ElasticCellAtJunction:
    """Load the layered plane-strain cell with the VOF traction; its b/a (see the module)."""
    rows = read_vof_traction(Path(traction_csv))
    table = fe_traction_table(rows, diameter_um / 2, Path(folder) / "elastic_cell_traction.csv")
    exp = Experiment.model_validate(
        {
            "cell": {
                "outer_diameter_um": diameter_um,
                "zona_thickness_um": zona_um,
                "symmetry": "plane_strain",
                "mesh_size_um": mesh_um,
                "materials": {
                    "zona": {"E_kPa": zona_kPa, "nu": 0.5},
                    "cytoplasm": {"E_kPa": cytoplasm_kPa, "nu": 0.5},
                },
            },
            "loads": {"flow": {"type": "traction", "table": str(table)}},
            "support": "inertia_relief",
            "time": {"duration_s": 1.0, "frames": 2},
        }
    )
    result = run_experiment(exp)
    a, b = outline_extents_um(result)
    return ElasticCellAtJunction(result, b / a, table)
