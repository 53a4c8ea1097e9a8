"""Four-sided pyramid (Bilodeau's approximation).

.. math::

    F = 0.7453 \\frac{E}{1-\\nu^2} \\tan\\theta \\, \\delta^2

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], theta face angle (centre line to
face) of a regular four-sided pyramid [deg], delta indentation [um]. Sharp rigid pyramid on a
linear-elastic half-space; Bilodeau's fit to the exact solution is good to a few per cent.

Reference: G. G. Bilodeau, J. Appl. Mech. 59 (1992) 519-523.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from afm.models.registry import Parameter, indentation_model

FACE_ANGLE = Parameter("face_angle_deg", "deg", 0.0, 90.0, "face angle of the pyramid")
BILODEAU = 0.7453


def prefactor(c: float, geometry: Mapping[str, float], nu: float) -> float:
    """``c tan(theta) / (1 - nu^2)``: F/E per delta^2 of a pyramid with Bilodeau's constant c."""
    return c * math.tan(math.radians(geometry["face_angle_deg"])) / (1.0 - nu**2)


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 * 0.7453 tan(theta) delta / (1 - nu^2), um."""
    return 2.0 * prefactor(BILODEAU, geometry, nu) * delta


@indentation_model(
    "pyramid",
    name="Four-sided pyramid (Bilodeau)",
    equation="F = 0.7453 E/(1-nu^2) tan(theta) delta^2",
    geometry=(FACE_ANGLE,),
    dshape=dshape,
    exponent=2.0,
    reference="Bilodeau 1992, J. Appl. Mech. 59:519",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E = 0.7453 tan(theta) delta^2 / (1 - nu^2), um^2."""
    return prefactor(BILODEAU, geometry, nu) * delta**2
