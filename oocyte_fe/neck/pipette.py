"""The narrow-necked pipette: a cylindrical bore, a smooth taper and a cylindrical neck.

Inner wall radius along the axis ``Z`` [um], with ``Z = z_neck`` the start of the neck::

    R_w(Z) = R_b                                         Z <= z_neck - L_t        (bore)
    R_w(Z) = R_n + (R_b - R_n) (1 - cos(pi s)) / 2,       s = (z_neck - Z) / L_t   (taper)
    R_w(Z) = R_n                                         Z >= z_neck               (neck)

Seed 001, Section 3.2: inner diameter 200 um tapered to 150 um, 3 mm from the tip, by heat
treatment; the taper shape is not given. This model reads it as a cosine taper over ``L_t``
(no kinks where it meets bore and neck, as a heat-drawn glass; steepest half-angle
``atan(pi (R_b - R_n) / (2 L_t))``), drawn as a polyline of ``taper_points``. The glass is rigid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from oocyte_fe.checks import numeric_fields
from oocyte_fe.errors import InputError
from oocyte_fe.fe.obstacles import Polyline, necked_pipette_wall


@dataclass(frozen=True)
class NeckedPipette:
    """Bore radius ``R_b``, neck radius ``R_n``, taper length ``L_t`` and the modelled lengths of
    bore and neck (um); ``z_neck`` places the start of the neck on the axis."""

    bore_radius_um: float = 100.0
    neck_radius_um: float = 75.0
    taper_length_um: float = 200.0
    bore_length_um: float = 300.0
    neck_length_um: float = 500.0
    z_neck_um: float = 0.0
    taper_points: int = 41

    def __post_init__(self) -> None:
        numeric_fields(self, "NeckedPipette")
        for name in ("neck_radius_um", "taper_length_um", "bore_length_um", "neck_length_um"):
            if not getattr(self, name) > 0:
                raise InputError(
                    "NeckedPipette", name, "a positive length in um", getattr(self, name)
                )
        if not self.bore_radius_um > self.neck_radius_um:
            raise InputError(
                "NeckedPipette",
                "bore_radius_um",
                f"> neck_radius_um = {self.neck_radius_um:g}",
                self.bore_radius_um,
            )

    @property
    def taper_half_angle_deg(self) -> float:
        """Steepest half-angle of the taper, ``atan(pi (R_b - R_n) / (2 L_t))`` [deg]."""
        drop = self.bore_radius_um - self.neck_radius_um
        return math.degrees(math.atan2(math.pi * drop, 2.0 * self.taper_length_um))

    def profile(self) -> list[tuple[float, float]]:
        """Wall points ``(R, Z)`` in order of increasing ``Z``."""
        z0, lt = self.z_neck_um, self.taper_length_um
        s = np.linspace(1.0, 0.0, self.taper_points)
        drop = self.bore_radius_um - self.neck_radius_um
        radius = self.neck_radius_um + drop * (1.0 - np.cos(np.pi * s)) / 2.0
        taper = [(float(r), float(z0 - lt * si)) for r, si in zip(radius, s, strict=True)]
        return [
            (self.bore_radius_um, z0 - lt - self.bore_length_um),
            *taper,
            (self.neck_radius_um, z0 + self.neck_length_um),
        ]

    def wall_radius(self, z: NDArray) -> NDArray:
        """``R_w(Z)`` [um] at axial positions ``z`` (constant beyond the modelled ends)."""
        pts = np.asarray(self.profile())
        return np.interp(z, pts[:, 1], pts[:, 0])

    def obstacle(self) -> Polyline:
        """The rigid wall for :class:`oocyte_fe.fe.contact.Contact`."""
        return necked_pipette_wall(self.profile(), name="pipette")

    def moved_to(self, z_neck_um: float) -> NeckedPipette:
        """The same pipette with its neck starting at ``z_neck_um``."""
        return replace(self, z_neck_um=float(z_neck_um))

    def touching(self, sphere_radius_um: float, clearance_um: float) -> NeckedPipette:
        """This pipette moved along the axis so that a sphere of radius ``a`` centred at the
        origin is ``c = clearance_um`` from the wall (root of ``d(z_neck) = a + c``, ``d`` the
        distance from the origin to the wall polyline; the sphere must fit the bore)."""
        target = sphere_radius_um + clearance_um
        if not target < self.bore_radius_um:
            raise InputError(
                "NeckedPipette",
                "bore_radius_um",
                f"> the oocyte radius + clearance {target:g}",
                self.bore_radius_um,
            )
        origin = np.zeros((2, 1))

        def gap(z: float) -> float:
            return float(self.moved_to(z).obstacle().distance(origin)[0][0]) - target

        low, high = -sphere_radius_um, self.taper_length_um + sphere_radius_um
        return self.moved_to(brentq(gap, low, high, xtol=1e-9))
