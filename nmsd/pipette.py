"""The micropipette as a rigid truncated wedge, and its frictionless penalty contact.

Table I of seed 000 gives the pipette as a width ``d_inj`` = 20.628 um and a tip angle
``theta_inj`` = 25.238 deg. We read them as a pulled glass pipette: a flat mouth of width
``d_inj`` (the tube end) whose flanks open backwards at the included angle ``theta_inj``.
In the pipette frame (xi along the motion, eta across, mouth centre at the origin) the
pipette is the convex set

    xi <= 0   and   |eta| <= d_inj / 2 - xi tan(theta_inj / 2)

written as three half-planes ``n_f . (x - m) - c_f <= 0``. The gap of a node is
``g = max_f (n_f . (x - m) - c_f)`` (< 0 inside); a node inside is pushed out along the
normal of that face with the penalty force ``-kappa g n_f`` (nN, kappa in nN/um), whose
tangent is ``kappa n_f n_f^T``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError

TABLE_I_WIDTH_UM = 20.628  # d_inj, seed 000 Table I
TABLE_I_TIP_ANGLE_DEG = 25.238  # theta_inj, seed 000 Table I
CONTACT_STIFFNESS_NN_PER_UM = 2.0e4  # penalty kappa of the default press
HOLD_HALF_WIDTH_UM = 25.0  # half-width of the held far-side rim (holding pipette mouth)


@dataclass(frozen=True)
class Pipette:
    """Rigid pipette: mouth width (um), included tip angle (deg), start, direction, stiffness.

    ``start``: mouth centre at zero advance (um); ``direction``: unit vector of motion;
    ``contact_stiffness``: penalty kappa, nN/um.
    """

    width_um: float = TABLE_I_WIDTH_UM
    tip_angle_deg: float = TABLE_I_TIP_ANGLE_DEG
    start: tuple[float, float] = (60.0, 0.0)
    direction: tuple[float, float] = (-1.0, 0.0)
    contact_stiffness: float = CONTACT_STIFFNESS_NN_PER_UM
    source: str = "Pipette"

    def __post_init__(self) -> None:
        checks.number(self.source, "width_um", self.width_um, gt=0, le=1e6)
        checks.number(self.source, "tip_angle_deg", self.tip_angle_deg, ge=0, lt=180)
        checks.number(self.source, "contact_stiffness", self.contact_stiffness, gt=0)
        if len(self.start) != 2 or len(self.direction) != 2:
            raise InputError(self.source, "start/direction", "(x, y) pairs")
        for name, pair in (("start", self.start), ("direction", self.direction)):
            for value in pair:
                checks.number(self.source, name, value, ge=-1e9, le=1e9)
        if not 0 <= self.tip_angle_deg < 180:
            raise InputError(self.source, "tip_angle_deg", "in [0, 180)", self.tip_angle_deg)
        if not self.contact_stiffness > 0:
            raise InputError(self.source, "contact_stiffness", "> 0", self.contact_stiffness)
        norm = float(np.hypot(*self.direction))
        if norm == 0:
            raise InputError(self.source, "direction", "a non-zero vector")
        object.__setattr__(self, "direction", (self.direction[0] / norm, self.direction[1] / norm))

    def faces(self) -> tuple[np.ndarray, np.ndarray]:
        """Outward normals (3, 2) and offsets (3,) um of the half-planes, in world axes."""
        a = np.asarray(self.direction)
        b = np.array([-a[1], a[0]])
        half = np.radians(self.tip_angle_deg) / 2
        s, c = np.sin(half), np.cos(half)
        normals = np.array([a, s * a + c * b, s * a - c * b])
        offsets = np.array([0.0, 0.5 * self.width_um * c, 0.5 * self.width_um * c])
        return normals, offsets

    def mouth(self, advance_um: float) -> np.ndarray:
        """Mouth centre after advancing ``advance_um`` along the direction, um."""
        return np.asarray(self.start) + advance_um * np.asarray(self.direction)

    def gap(self, points: np.ndarray, advance_um: float) -> tuple[np.ndarray, np.ndarray]:
        """Gap (n,) um, negative inside the pipette, and the normal (n, 2) of the nearest face."""
        normals, offsets = self.faces()
        signed = (points - self.mouth(advance_um)) @ normals.T - offsets
        nearest = np.argmax(signed, axis=1)
        return signed[np.arange(len(points)), nearest], normals[nearest]

    def contains(self, points: np.ndarray, advance_um: float) -> np.ndarray:
        """Mask of the points strictly inside the pipette."""
        return self.gap(points, advance_um)[0] < 0

    def outline(self, advance_um: float, length_um: float = 60.0) -> np.ndarray:
        """Polygon (4, 2) of the pipette's first ``length_um`` behind the mouth, for plots."""
        a = np.asarray(self.direction)
        b = np.array([-a[1], a[0]])
        m = self.mouth(advance_um)
        back = 0.5 * self.width_um + length_um * np.tan(np.radians(self.tip_angle_deg) / 2)
        return np.array(
            [
                m + 0.5 * self.width_um * b,
                m - 0.5 * self.width_um * b,
                m - length_um * a - back * b,
                m - length_um * a + back * b,
            ]
        )
