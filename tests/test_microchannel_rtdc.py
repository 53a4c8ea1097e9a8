"""Stokes flow past a sphere in a tube, and the one-way elastic cell against RT-DC's table.

Closed forms and peers (tolerances stated per test):

* Haberman & Sayre (1958): drag on a sphere moving along the axis of a tube, ``lambda = a/R``,
  ``F = 6 pi mu a U K``, ``K = (1 - 0.75857 l^5) / (1 - 2.1050 l + 2.0865 l^3 - 1.7068 l^5 +
  0.72603 l^6)`` (their formula is itself within about 0.5 % of exact solutions at
  lambda <= 0.4): measured FE/HS 0.9999 at 0.2, 1.0027 at 0.4 (1 um elements).
* Faxen's law for the force-free sphere in Poiseuille flow, ``U = U_max (1 - 2/3 lambda^2)``
  (walls enter at lambda^5 = 3e-4 at 0.2): measured +0.006 %.
* The force on the cell from its traction, from the constraint reaction and from the fluid's
  momentum balance (the stresses on the wall and ends): within 0.2 % of each other.
* dclab's LE-2D-FEM-19 (Mokbel et al. 2017, fully coupled): the modulus it reads from the
  one-way FE's deformation and area, in the small-deformation limit (d about 7e-4): measured
  0.98 of the modulus put in; checked at 3 %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.rtdc import (
    RtdcSetting,
    cell_in_channel,
    flow_in_channel,
    lut_moduli_kPa,
)
from oocyte_fe.microchannel.sphere_in_tube import SphereInTube, flow_past_cell

MU = 1.5e-5  # kPa s (15 mPa s)
R = 10.0  # um


def haberman_sayre(lam: float) -> float:
    num = 1 - 0.75857 * lam**5
    den = 1 - 2.1050 * lam + 2.0865 * lam**3 - 1.7068 * lam**5 + 0.72603 * lam**6
    return num / den


@pytest.fixture(scope="module", params=[0.2, 0.4])
def flow(request):
    lam = request.param
    return lam, flow_past_cell(SphereInTube(R, lam * R, 6 * R, 1.0, 0.125), MU, 4e7)


def test_drag_of_a_sphere_in_a_tube_meets_haberman_sayre(flow):
    lam, f = flow
    stokes = 6 * np.pi * MU * lam * R * haberman_sayre(lam)
    assert f.drag_per_speed_nN_s_um == pytest.approx(stokes, rel=5e-3)


def test_force_free_speed_meets_faxen(flow):
    """Faxen's law leaves out the walls' O(lambda^5): 3e-4 at 0.2, 1e-2 at 0.4 (measured
    +0.006 % and +0.23 %)."""
    lam, f = flow
    speed = f.speed_um_s / (2 * f.mean_velocity_um_s)
    assert speed == pytest.approx(1 - 2 / 3 * lam**2, rel=max(1e-3, lam**5 / 2))


def test_force_on_the_cell_three_ways(flow):
    _, f = flow
    for k in range(2):  # Poiseuille past the still cell; the channel sliding past it
        ref = f.force_reaction_nN[k]
        assert f.force_traction_nN[k] == pytest.approx(ref, rel=2e-3)
        assert f.force_balance_nN[k] == pytest.approx(ref, rel=2e-3)
    # force-free: the traction's resultant is a small fraction of the drag scale
    drag = f.drag_per_speed_nN_s_um * f.speed_um_s
    assert abs(np.sum(f.traction_kPa[1] * f.weights_um2)) < 2e-3 * drag


@pytest.mark.parametrize(
    ("field", "value"),
    [("sphere_radius_um", 9.8), ("half_length_um", 20.0), ("surface_size_um", 2.0)],
)
def test_a_channel_that_cannot_be_meshed_is_refused(field, value):
    args = {
        "channel_radius_um": R,
        "sphere_radius_um": 4.0,
        "half_length_um": 60.0,
        "size_um": 1.0,
        "surface_size_um": 0.125,
        field: value,
    }
    with pytest.raises(InputError, match=field):
        SphereInTube(**args)


@pytest.mark.slow
def test_one_way_elastic_cell_meets_the_rtdc_table(tmp_path: Path):
    setting = RtdcSetting()
    E = 16.0
    cell = cell_in_channel(flow_in_channel(6.0, setting), E, tmp_path, setting)
    assert cell.experiment.success
    assert cell.area_um2 == pytest.approx(np.pi * 36.0, rel=2e-3)
    assert lut_moduli_kPa([cell], setting)[0] == pytest.approx(E, rel=0.03)
