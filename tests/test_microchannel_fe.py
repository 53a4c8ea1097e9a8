"""Duct flow by scikit-fem (P2, Newton) against the series and Rabinowitsch-Mooney solutions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from oocyte_fe.microchannel.duct_fe import radial_mesh, rectangle_mesh, solve_duct_flow
from oocyte_fe.microchannel.poiseuille import PoiseuilleFlow, rectangular_duct_flow_rate
from oocyte_fe.microchannel.rabinowitsch import fully_developed_flow
from oocyte_fe.microchannel.viscosity import Rheology

MU = 1.66e-6
CARREAU = Rheology.of("carreau", eta0=1.45, eta_inf=1e-12, time_constant=680.0, n=0.057)


def test_newtonian_rectangle_against_series() -> None:
    exact = rectangular_duct_flow_rate(250.0, 100.0, 6e-4, MU)
    errors = []
    for cells in (2, 4):
        flow = solve_duct_flow(
            rectangle_mesh(250.0, 100.0, cells), Rheology.of("newtonian", mu=MU), 6e-4
        )
        errors.append(abs(flow.flow_rate / exact - 1.0))
        assert flow.area == pytest.approx(25000.0)
    assert errors[-1] < 5e-3  # issue 7: within 0.5 %
    assert errors[0] / errors[1] > 6.0  # converging at better than h^2.5


def test_series_limits() -> None:
    # a very wide duct tends to the slit: q = 2 G h^3 / (3 mu) per width, h = half-height
    q = rectangular_duct_flow_rate(1e5, 10.0, 1e-3, MU) / 1e5
    slit = PoiseuilleFlow("slit", 5.0, 1e-3, MU).flow_rate
    assert q == pytest.approx(slit, rel=1e-3)


def test_carreau_pipe_axisymmetric_against_exact_integral() -> None:
    g = 6e-5  # wall Carreau number lambda * gamma_w ~ 2e4: the viscosity falls 1e4-fold
    exact = fully_developed_flow(CARREAU, "pipe", 125.0, g)
    flow = solve_duct_flow(radial_mesh(125.0, 16), CARREAU, g, axisymmetric=True, steps=4)
    assert flow.converged
    assert flow.flow_rate == pytest.approx(exact.flow_rate, rel=5e-3)  # issue 7: within 0.5 %
    r = np.array([0.0, 62.5, 100.0])
    u_fe = flow.basis.interpolator(flow.u)(r[None, :])
    np.testing.assert_allclose(u_fe, exact.velocity(r), rtol=5e-3)


def test_newtonian_pipe_axisymmetric_is_exact_for_p2() -> None:
    flow = solve_duct_flow(
        radial_mesh(125.0, 2), Rheology.of("newtonian", mu=MU), 6e-4, axisymmetric=True
    )
    assert flow.flow_rate == pytest.approx(
        PoiseuilleFlow("pipe", 125.0, 6e-4, MU).flow_rate, rel=1e-10
    )
    assert flow.area == pytest.approx(math.pi * 125.0**2)
