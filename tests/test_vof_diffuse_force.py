"""The force of a diffuse interface (oocyte_fe.microchannel.vof.diffuse_force) on closed forms."""

import numpy as np
import pytest

from oocyte_fe.microchannel.vof.control_volume import MixtureFields
from oocyte_fe.microchannel.vof.diffuse_force import diffuse_force

DX = 2.0  # um


def _disc(n: int = 80, radius: float = 40.0, width: float = 3.0):
    x = (np.arange(n) - n / 2 + 0.5) * DX
    xx, yy = np.meshgrid(x, x)  # rows: y
    alpha = 0.5 * (1.0 - np.tanh((np.hypot(xx, yy) - radius) / width))
    return xx, yy, alpha


def _fields(alpha, p, ux, uy, mu=1e-3):
    rho = np.full_like(alpha, 1e-15)
    return MixtureFields(alpha, p, ux, uy, rho, np.full_like(alpha, mu))


def test_a_pressure_gradient_pushes_the_cell_by_minus_G_times_its_area():
    """p = G x: F = -sum (-p I) . grad(alpha) dA = -G sum alpha dA (summation by parts,
    exact for central differences on a band inside the lattice), to round-off."""
    xx, yy, alpha = _disc()
    G = 0.003  # kPa/um
    f = _fields(alpha, G * xx + 1.7, 0 * xx, 0 * xx)
    force, load = diffuse_force(f, DX)
    area = alpha.sum() * DX * DX
    assert force[0] == pytest.approx(-G * area, rel=1e-9)
    assert abs(force[1]) < 1e-9 * G * area
    # the load: |p - p_mean| over the band, about G r on a disc of radius r: 4 G r^2 in all
    assert load == pytest.approx(4.0 * G * 40.0**2, rel=0.05)


def test_a_uniform_pressure_and_a_simple_shear_exert_no_net_force():
    """A constant stress integrates to zero over the closed band (sum grad alpha = 0)."""
    xx, yy, alpha = _disc()
    gamma = 50.0  # 1/s: u_x = gamma y, sigma_xy = mu gamma everywhere
    f = _fields(alpha, np.full_like(alpha, 2.5), gamma * yy, 0 * yy)
    force, load = diffuse_force(f, DX)
    scale = 2.5 * 2.0 * np.pi * 40.0
    assert np.all(np.abs(force) < 1e-12 * scale)
    assert load > 0.0


def test_a_wall_next_to_the_band_takes_the_walls_conditions():
    """Cells off the fluid (NaN, a wall) two cells from the interface's centre: the sum runs
    over the fluid, the differences next to the wall take zero-gradient alpha and p and U = 0.
    The pressure gradient's force stays -G A within 1 % (alpha is about 0.03 at the wall)."""
    xx, yy, alpha = _disc(width=1.5)
    G = 0.003
    p = G * xx + 1.7
    wall = yy > 44.0  # the disc's edge at 40 um: the wall two cells beyond it
    ux, uy = 0 * xx, 0 * xx
    for field in (alpha, p, ux, uy):
        field[wall] = np.nan
    force, load = diffuse_force(_fields(alpha, p, ux, uy), DX)
    area = np.nansum(alpha) * DX * DX
    assert force[0] == pytest.approx(-G * area, rel=0.01)
    assert np.isfinite(load) and load > 0.0
