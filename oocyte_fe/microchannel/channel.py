"""The microfluidic channel's operating points: Reynolds number, mean velocity, laminar check.

``Re = rho U d / mu`` (rho in nN s^2/um^4, U in um/s, d in um, mu in kPa s: dimensionless).
Seed 001 (Section 2.4) measured the medium's velocity at one driving pressure and reports
``Re``; taking the flow as Hagen-Poiseuille, ``U = Dp R^2 / (8 mu L)``, that one point fixes the
effective hydraulic length ``L = Dp R^2 / (8 mu U)`` (channel plus tubing, all the resistance the
pressure box drives), and with it ``U`` and ``Re`` at every other pressure (``U`` proportional to
``Dp``). Laminar while ``Re < 2000`` (straight circular pipe); the laminar entrance length is
``L_e = 0.06 Re d`` (Shah and London, Laminar Flow Forced Convection in Ducts, 1978).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oocyte_fe.checks import positive
from oocyte_fe.errors import InputError

LAMINAR_LIMIT = 2000.0


def reynolds_number(density: float, velocity: float, diameter: float, viscosity: float) -> float:
    """``Re = rho U d / mu``; any consistent units, the result is dimensionless."""
    return density * velocity * diameter / viscosity


def velocity_from_reynolds(
    reynolds: float, density: float, diameter: float, viscosity: float
) -> float:
    """``U = Re mu / (rho d)`` (um/s in internal units)."""
    return reynolds * viscosity / (density * diameter)


def entrance_length(reynolds: float, diameter: float) -> float:
    """Laminar hydrodynamic entrance length ``0.06 Re d`` (um)."""
    return 0.06 * reynolds * diameter


@dataclass(frozen=True)
class Channel:
    """A circular channel driven by a pressure box, calibrated by one measured Reynolds number.

    diameter (um), density (nN s^2/um^4) and viscosity (kPa s) of the medium, and the reference
    pressure (kPa) at which ``reynolds_ref`` was measured.
    """

    diameter: float
    density: float
    viscosity: float
    reynolds_ref: float
    pressure_ref: float

    def __post_init__(self) -> None:
        for name in ("diameter", "density", "viscosity", "reynolds_ref", "pressure_ref"):
            object.__setattr__(self, name, positive("Channel", name, getattr(self, name)))

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter

    @property
    def velocity_ref(self) -> float:
        """Mean velocity (um/s) implied by the reference Reynolds number."""
        return velocity_from_reynolds(
            self.reynolds_ref, self.density, self.diameter, self.viscosity
        )

    @property
    def hydraulic_length(self) -> float:
        """Effective Poiseuille length ``L = Dp R^2 / (8 mu U)`` (um) at the reference point."""
        return self.pressure_ref * self.radius**2 / (8.0 * self.viscosity * self.velocity_ref)

    def mean_velocity(self, pressure: np.ndarray) -> np.ndarray:
        """Mean velocity (um/s) at driving pressure (kPa): ``Dp R^2 / (8 mu L)``."""
        return (
            np.asarray(pressure, dtype=float)
            * self.radius**2
            / (8.0 * self.viscosity * self.hydraulic_length)
        )

    def pressure_gradient(self, pressure: np.ndarray) -> np.ndarray:
        """``G = Dp / L`` (kPa/um) along the effective hydraulic length at driving pressure
        ``Dp`` (kPa): the gradient a fluid filling the whole driven path would carry."""
        return np.asarray(pressure, dtype=float) / self.hydraulic_length

    def reynolds(self, pressure: np.ndarray) -> np.ndarray:
        return reynolds_number(
            self.density, self.mean_velocity(pressure), self.diameter, self.viscosity
        )

    def wall_shear_rate(self, pressure: np.ndarray) -> np.ndarray:
        """Newtonian wall shear rate ``8 U / d`` (1/s)."""
        return 8.0 * self.mean_velocity(pressure) / self.diameter

    def is_laminar(self, pressure: np.ndarray) -> np.ndarray:
        return self.reynolds(pressure) < LAMINAR_LIMIT

    def check_pressures(self, pressure: np.ndarray, source: str, field: str) -> np.ndarray:
        """The pressures (kPa) if all are positive and laminar (Poiseuille applies), else an
        :class:`InputError` naming ``source`` and ``field``."""
        p = np.atleast_1d(np.asarray(pressure, dtype=float))
        if not np.all(np.isfinite(p) & (p > 0)):
            raise InputError(source, field, "positive driving pressures", got=p.tolist())
        p_max = LAMINAR_LIMIT * self.pressure_ref / self.reynolds_ref
        if np.any(p >= p_max):
            raise InputError(
                source,
                field,
                f"pressures below {p_max:.4g} kPa (Re < {LAMINAR_LIMIT:g}, laminar Poiseuille)",
                got=float(p.max()),
            )
        return p
