"""Closed-form fully developed flow in a pipe and a slit: Newtonian and power-law fluids.

Pressure gradient ``G = -dp/dx`` in kPa/um, viscosity ``mu`` in kPa s, lengths in um, so
velocities come out in um/s and flow rates in um^3/s (pipe) or um^2/s per unit width (slit).
The slit has half-height ``h`` (gap ``2h``), walls at ``y = +-h``.

Newtonian (Hagen-Poiseuille / plane Poiseuille)::

    pipe:  u(r) = G (R^2 - r^2) / (4 mu),  Q = pi G R^4 / (8 mu),  U = Q / (pi R^2),
           wall shear rate 4 U / R,        wall shear stress G R / 2
    slit:  u(y) = G (h^2 - y^2) / (2 mu),  q = 2 G h^3 / (3 mu),   U = q / (2 h),
           wall shear rate 3 U / h,        wall shear stress G h

Power law ``eta = K gamma^(n-1)``, wall shear stress ``tau_w``::

    pipe:  Q = pi R^3 n / (3 n + 1) (tau_w / K)^(1/n)
    slit:  q = 2 h^2 n / (2 n + 1) (tau_w / K)^(1/n)

Reference: Bird, Stewart, Lightfoot, Transport Phenomena (2nd ed.), Sections 2.3, 8.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from oocyte_fe.checks import HUGE, number, positive
from oocyte_fe.errors import InputError

Geometry = Literal["pipe", "slit"]
GEOMETRIES = ("pipe", "slit")


def check_geometry(where: str, geometry: object) -> None:
    """Refuse a geometry other than ``"pipe"`` or ``"slit"`` (never read one as the other)."""
    if geometry not in GEOMETRIES:
        raise InputError(where, "geometry", "'pipe' or 'slit'", got=geometry)


@dataclass(frozen=True)
class PoiseuilleFlow:
    """Newtonian fully developed flow; ``size`` is the pipe radius or slit half-height (um)."""

    geometry: Geometry
    size: float
    pressure_gradient: float
    viscosity: float

    def __post_init__(self) -> None:
        check_geometry("PoiseuilleFlow", self.geometry)
        object.__setattr__(self, "size", positive("PoiseuilleFlow", "size", self.size))
        object.__setattr__(
            self,
            "pressure_gradient",
            number("PoiseuilleFlow", "pressure_gradient", self.pressure_gradient, ge=0, le=HUGE),
        )
        object.__setattr__(
            self, "viscosity", positive("PoiseuilleFlow", "viscosity", self.viscosity)
        )

    @property
    def wall_shear_stress(self) -> float:
        """kPa: ``G R / 2`` (pipe) or ``G h`` (slit)."""
        return self.pressure_gradient * self.size / (2.0 if self.geometry == "pipe" else 1.0)

    @property
    def max_velocity(self) -> float:
        """Centre-line velocity, um/s."""
        factor = 4.0 if self.geometry == "pipe" else 2.0
        return self.pressure_gradient * self.size**2 / (factor * self.viscosity)

    @property
    def mean_velocity(self) -> float:
        """um/s: half the centre-line velocity (pipe), two thirds of it (slit)."""
        return self.max_velocity * (0.5 if self.geometry == "pipe" else 2.0 / 3.0)

    @property
    def flow_rate(self) -> float:
        """um^3/s (pipe) or um^2/s per unit width (slit)."""
        area = math.pi * self.size**2 if self.geometry == "pipe" else 2.0 * self.size
        return self.mean_velocity * area

    @property
    def wall_shear_rate(self) -> float:
        """1/s: ``4 U / R`` (pipe) or ``3 U / h`` (slit)."""
        return self.wall_shear_stress / self.viscosity

    def velocity(self, position: np.ndarray) -> np.ndarray:
        """u (um/s) at radius r or transverse coordinate y (um)."""
        x = np.asarray(position, dtype=float)
        return self.max_velocity * (1.0 - (x / self.size) ** 2)


def pressure_gradient_for_mean_velocity(
    geometry: Geometry, size: float, mean_velocity: float, viscosity: float
) -> float:
    """``G`` (kPa/um) driving Newtonian flow at ``mean_velocity``: ``8 mu U / R^2`` (pipe),
    ``3 mu U / h^2`` (slit)."""
    where = "pressure_gradient_for_mean_velocity"
    check_geometry(where, geometry)
    size = positive(where, "size", size)
    mean_velocity = number(where, "mean_velocity", mean_velocity, ge=0, le=HUGE)
    viscosity = positive(where, "viscosity", viscosity)
    factor = 8.0 if geometry == "pipe" else 3.0
    return factor * viscosity * mean_velocity / size**2


def power_law_flow_rate(
    geometry: Geometry, size: float, wall_shear_stress: float, consistency: float, n: float
) -> float:
    """Closed-form power-law flow rate (see the module docstring)."""
    where = "power_law_flow_rate"
    check_geometry(where, geometry)
    size = positive(where, "size", size)
    wall_shear_stress = number(where, "wall_shear_stress", wall_shear_stress, ge=0, le=HUGE)
    consistency = positive(where, "consistency", consistency)
    n = number(where, "n", n, ge=0.05, le=5)
    try:
        rate = (wall_shear_stress / consistency) ** (1.0 / n)
    except OverflowError:
        rate = math.inf
    if not rate < HUGE:
        raise InputError(
            where,
            "wall_shear_stress/consistency/n",
            f"(tau_w / K)^(1/n) below {HUGE:g} (a finite flow rate)",
            got=(wall_shear_stress, consistency, n),
        )
    if geometry == "pipe":
        return math.pi * size**3 * n / (3.0 * n + 1.0) * rate
    return 2.0 * size**2 * n / (2.0 * n + 1.0) * rate


def rectangular_duct_flow_rate(
    width: float, height: float, pressure_gradient: float, viscosity: float, terms: int = 200
) -> float:
    """Newtonian flow rate (um^3/s) through a ``width`` x ``height`` rectangle (um)::

        Q = G h^3 w / (12 mu) [1 - 192 h / (pi^5 w) sum_{k odd} tanh(k pi w / (2 h)) / k^5]

    with ``h <= w`` the shorter side (Bruus, Theoretical Microfluidics, 2008, eq. 4.47). The
    series is summed over ``terms`` odd k; the truncation error is below ``terms^-4``.
    """
    where = "rectangular_duct_flow_rate"
    width = positive(where, "width", width)
    height = positive(where, "height", height)
    pressure_gradient = number(where, "pressure_gradient", pressure_gradient, ge=0, le=HUGE)
    viscosity = positive(where, "viscosity", viscosity)
    terms = number(where, "terms", terms, ge=1, le=100_000, integer=True)
    h, w = sorted((height, width))
    k = 2.0 * np.arange(terms) + 1.0
    series = np.sum(np.tanh(k * math.pi * w / (2.0 * h)) / k**5)
    return (
        pressure_gradient
        * h**3
        * w
        / (12.0 * viscosity)
        * (1.0 - 192.0 * h / (math.pi**5 * w) * series)
    )
