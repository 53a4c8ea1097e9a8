"""Closed-form channel flow, Reynolds number, and Rabinowitsch-Mooney integrals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.channel import Channel, reynolds_number
from oocyte_fe.microchannel.poiseuille import PoiseuilleFlow, power_law_flow_rate
from oocyte_fe.microchannel.rabinowitsch import fully_developed_flow
from oocyte_fe.microchannel.viscosity import Rheology

MU = 1.66e-3 * units.VISCOSITY["Pa_s"]  # kPa s
RHO = 1008.0 * units.DENSITY["kg_m3"]  # nN s^2/um^4


def seed_channel() -> Channel:
    return Channel(250.0, RHO, MU, 106.5, 300.0 * units.PRESSURE["hPa"])


def test_reynolds_is_unit_independent() -> None:
    si = reynolds_number(1008.0, 0.7, 250e-6, 1.66e-3)
    internal = reynolds_number(RHO, 0.7 * units.VELOCITY["m_s"], 250.0, MU)
    assert internal == pytest.approx(si, rel=1e-12)
    assert RHO == pytest.approx(1.008e-12)


def test_seed_operating_point() -> None:
    ch = seed_channel()
    # U = Re mu / (rho d) = 106.5 * 1.66e-3 / (1008 * 250e-6) m/s
    assert ch.velocity_ref == pytest.approx(106.5 * 1.66e-3 / (1008 * 250e-6) * 1e6, rel=1e-12)
    # Poiseuille at the reference point gives back the velocity and Re
    p = 30.0
    assert ch.reynolds(p) == pytest.approx(106.5, rel=1e-12)
    flow = PoiseuilleFlow("pipe", ch.radius, p / ch.hydraulic_length, MU)
    assert flow.mean_velocity == pytest.approx(ch.velocity_ref, rel=1e-12)
    assert ch.reynolds(90.0) == pytest.approx(3 * 106.5) and bool(ch.is_laminar(90.0))


def test_pressure_out_of_range() -> None:
    ch = seed_channel()
    with pytest.raises(InputError, match="case.toml: inputs.pressures_hPa: expected positive"):
        ch.check_pressures([20.0, -1.0], "case.toml", "inputs.pressures_hPa")
    with pytest.raises(InputError, match=r"Re < 2000"):
        ch.check_pressures([20.0, 600.0], "case.toml", "inputs.pressures_hPa")


@pytest.mark.parametrize("geometry", ["pipe", "slit"])
def test_poiseuille_closed_form_consistency(geometry: str) -> None:
    f = PoiseuilleFlow(geometry, 50.0, 2e-4, MU)
    x = np.linspace(0.0, 50.0, 2001)
    u = f.velocity(x)
    integral = (
        np.trapezoid(2 * math.pi * x * u, x) if geometry == "pipe" else 2 * np.trapezoid(u, x)
    )
    assert integral == pytest.approx(f.flow_rate, rel=1e-6)
    wall_rate = -np.gradient(u, x)[-1]
    assert wall_rate == pytest.approx(f.wall_shear_rate, rel=1e-3)
    assert f.wall_shear_rate == pytest.approx(
        (4.0 if geometry == "pipe" else 3.0) * f.mean_velocity / 50.0
    )


@pytest.mark.parametrize("geometry", ["pipe", "slit"])
def test_rabinowitsch_newtonian(geometry: str) -> None:
    newton = Rheology.of("newtonian", mu=MU)
    exact = PoiseuilleFlow(geometry, 125.0, 6e-4, MU)
    flow = fully_developed_flow(newton, geometry, 125.0, 6e-4)
    assert flow.flow_rate == pytest.approx(exact.flow_rate, rel=1e-6)
    assert flow.wall_shear_rate == pytest.approx(exact.wall_shear_rate, rel=1e-6)
    r = np.array([0.0, 40.0, 100.0, 125.0])
    np.testing.assert_allclose(flow.velocity(r), exact.velocity(r), rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize("geometry", ["pipe", "slit"])
@pytest.mark.parametrize("n", [0.13, 0.5, 1.4])
def test_rabinowitsch_power_law(geometry: str, n: float) -> None:
    k = 4e-3
    flow = fully_developed_flow(Rheology.of("power_law", consistency=k, n=n), geometry, 125.0, 1e-4)
    assert flow.flow_rate == pytest.approx(
        power_law_flow_rate(geometry, 125.0, flow.wall_shear_stress, k, n), rel=1e-6
    )
    # power-law profile: u(x) = u(0) (1 - (x/size)^(1 + 1/n))
    x = np.array([0.0, 50.0, 110.0])
    u = flow.velocity(x)
    np.testing.assert_allclose(u, u[0] * (1 - (x / 125.0) ** (1 + 1 / n)), rtol=1e-6)


def test_carreau_flow_between_its_newtonian_bounds() -> None:
    car = Rheology.of("carreau", eta0=1.45, eta_inf=1e-6, time_constant=680.0, n=0.06)
    flow = fully_developed_flow(car, "pipe", 125.0, 6e-5)
    low = PoiseuilleFlow("pipe", 125.0, 6e-5, 1.45).flow_rate
    high = PoiseuilleFlow("pipe", 125.0, 6e-5, 1e-6).flow_rate
    assert low < flow.flow_rate < high
    assert flow.mean_velocity == pytest.approx(flow.flow_rate / (math.pi * 125.0**2))
