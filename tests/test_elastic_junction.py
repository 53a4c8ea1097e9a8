"""The AFM-elastic cell under a VOF traction table (issue 30 part 2, one-way).

Closed form: a homogeneous disc (plane strain, nu = 1/2) under the normal traction
``s cos 2 theta`` takes ``u_r = s R cos 2 theta / E`` (Airy; docs/fe.md), an ellipse of
``b/a = (R - u) / (R + u)`` to first order (tolerance 1 %: s/E = 0.01). A uniform pressure
added to the table must not change it (the mean pressure is removed; the cell is
incompressible anyway).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.elastic_junction import elastic_cell_at_junction

R = 70.0


def _vof_csv(path: Path, s_kPa: float, p0_kPa: float = 0.0, centre=(-8.0, -19.0)) -> Path:
    """A VOF-style contour (44 edges, radius within +-4 % like a 12.5 um lattice) and its
    traction t = (s cos 2 theta - p0) n."""
    theta = np.radians(np.arange(4.0, 360.0, 360.0 / 44))
    r = R * (1 + 0.04 * np.sin(7 * theta))
    x, y = centre[0] + r * np.cos(theta), centre[1] + r * np.sin(theta)
    tn = s_kPa * np.cos(2 * theta) - p0_kPa
    rows = [
        f"{np.degrees(a):.6f},{xa:.6f},{ya:.6f},{t * np.cos(a):.9g},{t * np.sin(a):.9g}"
        for a, xa, ya, t in zip(theta, x, y, tn, strict=True)
    ]
    path.write_text("arc_angle_deg,x_um,y_um,t_x_kPa,t_y_kPa\n" + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("p0", [0.0, 5.0])
def test_cosine_traction_gives_the_ellipse(tmp_path: Path, p0: float):
    E, s = 1.0, 0.01
    csv = _vof_csv(tmp_path / "t.csv", s, p0)
    cell = elastic_cell_at_junction(csv, tmp_path, zona_kPa=E, cytoplasm_kPa=E)
    u = s * R / E
    assert cell.experiment.success
    assert 1 - cell.b_over_a == pytest.approx(1 - (R - u) / (R + u), rel=0.01)


def test_a_table_without_the_columns_is_refused(tmp_path: Path):
    (tmp_path / "t.csv").write_text("x,y\n1,2\n")
    with pytest.raises(InputError, match="arc_angle_deg"):
        elastic_cell_at_junction(tmp_path / "t.csv", tmp_path)
