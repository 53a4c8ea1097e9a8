"""Exact fully developed generalized-Newtonian flow in a pipe and a slit (Rabinowitsch-Mooney).

In a pipe of radius R the shear stress is linear in r, ``tau(r) = tau_w r / R`` with the wall
shear stress ``tau_w = G R / 2`` (G = -dp/dx in kPa/um); in a slit of half-height h,
``tau(y) = tau_w y / h`` with ``tau_w = G h``. With ``gamma(tau)`` the inverse of the flow curve
``tau = eta(gamma) gamma`` (:meth:`Rheology.shear_rate`)::

    pipe:  Q = pi R^3 / tau_w^3 int_0^tau_w tau^2 gamma(tau) dtau            (um^3/s)
           u(r) = R / tau_w int_{tau_w r/R}^{tau_w} gamma(tau) dtau         (um/s)
    slit:  q = 2 h^2 / tau_w^2 int_0^tau_w tau gamma(tau) dtau               (um^2/s per width)
           u(y) = h / tau_w int_{tau_w y/h}^{tau_w} gamma(tau) dtau

(Rabinowitsch, Z. Phys. Chem. A 145 (1929) 1; Mooney, J. Rheol. 2 (1931) 210). The integrals are
evaluated with ``scipy.integrate.quad``, the inverse flow curve with Brent's method; no slip at
the wall, the flow is steady, incompressible and unidirectional.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad

from oocyte_fe.checks import positive
from oocyte_fe.microchannel.poiseuille import Geometry, check_geometry
from oocyte_fe.microchannel.viscosity import Rheology

_QUAD = {"epsabs": 0.0, "epsrel": 1e-11, "limit": 200}


@dataclass(frozen=True)
class GeneralizedFlow:
    """Fully developed flow of a generalized-Newtonian fluid; ``size`` = R or h (um)."""

    geometry: Geometry
    size: float
    pressure_gradient: float
    wall_shear_stress: float
    wall_shear_rate: float
    flow_rate: float
    rheology: Rheology

    @property
    def area(self) -> float:
        """um^2 (pipe) or um per unit width (slit)."""
        return math.pi * self.size**2 if self.geometry == "pipe" else 2.0 * self.size

    @property
    def mean_velocity(self) -> float:
        return self.flow_rate / self.area

    def velocity(self, position: np.ndarray) -> np.ndarray:
        """u (um/s) at radius r or transverse coordinate y (um), |position| <= size."""
        x = np.abs(np.atleast_1d(np.asarray(position, dtype=float)))
        tau_w, gamma = self.wall_shear_stress, self.rheology.shear_rate
        return np.array(
            [self.size / tau_w * quad(gamma, tau_w * xi / self.size, tau_w, **_QUAD)[0] for xi in x]
        )


def fully_developed_flow(
    rheology: Rheology, geometry: Geometry, size: float, pressure_gradient: float
) -> GeneralizedFlow:
    """Flow rate and wall quantities for ``rheology`` in a pipe (R = size) or slit (h = size)."""
    check_geometry("fully_developed_flow", geometry)
    size = positive("fully_developed_flow", "size", size)
    pressure_gradient = positive("fully_developed_flow", "pressure_gradient", pressure_gradient)
    gamma = rheology.shear_rate
    tau_w = (0.5 if geometry == "pipe" else 1.0) * pressure_gradient * size
    wall_rate = gamma(tau_w)  # first: a wall stress beyond the rheology's range is refused here
    if geometry == "pipe":
        integral = quad(lambda t: t * t * gamma(t), 0.0, tau_w, **_QUAD)[0]
        flow_rate = math.pi * size**3 / tau_w**3 * integral
    else:
        integral = quad(lambda t: t * gamma(t), 0.0, tau_w, **_QUAD)[0]
        flow_rate = 2.0 * size**2 / tau_w**2 * integral
    return GeneralizedFlow(geometry, size, pressure_gradient, tau_w, wall_rate, flow_rate, rheology)
