"""Pierce-through fits on curves from a generator written here (not afm/synthetic.py's).

Sneddon cone (half angle 10 deg, nu 0.5) on both layers, cantilever k; at each piezo position
z the force solves F = model(x) with x = z - F/k (brentq). The ZP rises from its contact x0 to
the pierce force, the force drops to a residual level, and the second segment follows one of
the two readings documented in afm/pierce.py:

A. F = F_res + E_cyt shape(x - x_after)        (indented from the tip position after the drop)
B. F = F_res + E_cyt [shape(x - x0) - shape(x_after - x0)]   (the cone keeps its depth)
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from afm.curve import ForceCurve
from afm.pierce import fit_pierce

K = 100.0  # nN/um
X0 = 4.0  # um, ZP contact (tip position)
E_ZP, E_CYT = 7.01, 1.55  # kPa
F_PIERCE, F_RES, F_TRIGGER = 8.0, 2.4, 12.0  # nN
CONE = 2.0 / math.pi * math.tan(math.radians(10.0)) / (1.0 - 0.5**2)  # F/(E delta^2), um^0


def cone(delta: float) -> float:
    return CONE * max(delta, 0.0) ** 2


def _force_at(z: float, law) -> float:
    # F - law(z - F/k) rises with F: one root between 0 and k z + the largest force
    return brentq(lambda f: f - law(z - f / K), -1.0, K * abs(z) + 100.0, xtol=1e-13)


def pierce_curve_independent(
    reading: str, e_cyt: float = E_CYT, x_ref: float | None = None, noise_nN: float = 0.02
):
    depth = math.sqrt(F_PIERCE / (E_ZP * CONE))
    z_pierce = X0 + depth + F_PIERCE / K
    x_after = z_pierce - F_RES / K
    reference = x_after if reading == "A" else (X0 if x_ref is None else x_ref)

    def second(x: float) -> float:
        base = 0.0 if reading == "A" else e_cyt * cone(x_after - reference)
        return F_RES + e_cyt * cone(x - reference) - base

    z_end = brentq(lambda z: _force_at(z, second) - F_TRIGGER, z_pierce, z_pierce + 50.0)
    piezo = np.linspace(0.0, z_end, 1000)
    force = np.array(
        [
            _force_at(z, lambda x: E_ZP * cone(x - X0)) if z < z_pierce else _force_at(z, second)
            for z in piezo
        ]
    )
    rng = np.random.default_rng(5)
    measured = force + 0.3 + noise_nN * rng.standard_normal(piezo.size)
    return ForceCurve(piezo, measured, K, f"independent_{reading}"), x_after, depth


@pytest.mark.parametrize(("reading", "e_cyt"), [("A", E_CYT), ("B", E_CYT), ("A", 4.0), ("B", 4.0)])
def test_both_readings_give_both_moduli(reading, e_cyt):
    curve, x_after, depth = pierce_curve_independent(reading, e_cyt)
    fit = fit_pierce(curve)
    assert fit.zp.E_kPa == pytest.approx(E_ZP, rel=0.03)
    assert fit.cytoplasm.E_kPa == pytest.approx(e_cyt, rel=0.03)
    expected_x1 = x_after if reading == "A" else X0
    assert fit.cytoplasm.contact_point_um == pytest.approx(expected_x1, abs=0.1)
    assert fit.cytoplasm.quality == "good"
    if (reading, e_cyt) == ("B", 4.0):
        # the second segment is shorter than the depth at the drop: the old bound
        # (x_after - segment length) clipped x1 here and gave E_cyt = 4.96 kPa (+24 %), "good"
        assert float(np.ptp(fit.cytoplasm.tip_position_um)) < depth


def test_contact_reference_on_its_bound_lowers_the_rating():
    # reference far before the ZP contact (x0 - 3 um): x1 ends on its lower bound x0 - D/2
    curve, _, _ = pierce_curve_independent("B", x_ref=X0 - 3.0)
    fit = fit_pierce(curve)
    assert "x1 (lower)" in fit.cytoplasm.at_bound
    assert fit.cytoplasm.quality.startswith("poor:") and "bound" in fit.cytoplasm.quality
