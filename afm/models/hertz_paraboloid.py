"""Hertz: paraboloid (a sphere in the small-indentation limit, delta << R).

.. math::

    F = \\frac{4}{3} \\frac{E}{1-\\nu^2} \\sqrt{R} \\, \\delta^{3/2}

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], R tip radius [um], delta
indentation [um]. Linear-elastic half-space, frictionless; for a sphere valid while the contact
radius sqrt(R delta) stays small against R (see ``hertz_sphere`` for the exact sphere).

Reference: H. Hertz, J. Reine Angew. Math. 92 (1881) 156-171.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from afm.models.registry import Parameter, indentation_model

TIP_RADIUS = Parameter("radius_um", "um", 0.0, math.inf, "tip (sphere) radius")


def _prefactor(geometry: Mapping[str, float], nu: float) -> float:
    return 4.0 / 3.0 * math.sqrt(geometry["radius_um"]) / (1.0 - nu**2)


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 sqrt(R) delta^(1/2) / (1 - nu^2), um."""
    return 1.5 * _prefactor(geometry, nu) * np.sqrt(delta)


@indentation_model(
    "hertz_paraboloid",
    name="Hertz paraboloid",
    equation="F = (4/3) E/(1-nu^2) sqrt(R) delta^(3/2)",
    geometry=(TIP_RADIUS,),
    dshape=dshape,
    exponent=1.5,
    reference="Hertz 1881, J. Reine Angew. Math. 92:156",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E = (4/3) sqrt(R) delta^(3/2) / (1 - nu^2), um^2."""
    return _prefactor(geometry, nu) * delta**1.5
