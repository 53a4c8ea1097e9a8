"""Sneddon's conical indenter.

.. math::

    F = \\frac{2}{\\pi} \\frac{E}{1-\\nu^2} \\tan\\alpha \\, \\delta^2

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], alpha half opening angle of the
cone [deg], delta indentation depth [um]. With E in kPa and delta in um, F is in nN
(kPa um^2 = nN). Assumes a sharp, rigid, infinitely long cone on a linear-elastic half-space,
frictionless contact, small strain. The seed paper (001, eq. 1) uses nu = 0.5, alpha = 10 deg.

Reference: I. N. Sneddon, Int. J. Eng. Sci. 3 (1965) 47-57.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from afm.models.registry import Parameter, indentation_model

HALF_ANGLE = Parameter(
    "half_angle_deg", "deg", 1e-3, 90.0, "half opening angle of the cone", default=10.0
)


def _prefactor(geometry: Mapping[str, float], nu: float) -> float:
    return 2.0 / math.pi * math.tan(math.radians(geometry["half_angle_deg"])) / (1.0 - nu**2)


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 (2/pi) tan(alpha) delta / (1 - nu^2), um."""
    return 2.0 * _prefactor(geometry, nu) * delta


@indentation_model(
    "sneddon_cone",
    name="Sneddon cone",
    equation="F = (2/pi) E/(1-nu^2) tan(alpha) delta^2",
    geometry=(HALF_ANGLE,),
    dshape=dshape,
    exponent=2.0,
    reference="Sneddon 1965, Int. J. Eng. Sci. 3:47",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E = (2/pi) tan(alpha) delta^2 / (1 - nu^2), um^2 (nN per kPa)."""
    return _prefactor(geometry, nu) * delta**2
