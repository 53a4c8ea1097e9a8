"""Sneddon's flat cylindrical punch.

.. math::

    F = \\frac{2 a E}{1-\\nu^2} \\, \\delta

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], a radius of the punch's flat
face [um], delta indentation [um] (kPa um^2 = nN). A rigid cylinder whose flat face is fully
in contact from the contact point on (contact radius a at every depth) on a linear-elastic
half-space, frictionless, small strain: the force is linear in delta. The contact radius
being constant, Lee and Radok's correspondence holds exactly for creep
(:func:`afm.creep.fit_creep_tip`): J(t) = 4 a delta(t) / ((1 - nu) F0). A tilted face, a
rounded edge or a face not yet fully in contact makes the start of the curve softer than
this line.

Reference: I. N. Sneddon, Int. J. Eng. Sci. 3 (1965) 47-57 (eq. 6.2, the flat-ended punch).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from afm.models.registry import Parameter, indentation_model

PUNCH_RADIUS = Parameter("radius_um", "um", 0.0, math.inf, "radius of the punch's flat face")


def _stiffness(geometry: Mapping[str, float], nu: float) -> float:
    """2 a / (1 - nu^2), um: F/E per um of indentation."""
    return 2.0 * geometry["radius_um"] / (1.0 - nu**2)


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 a / (1 - nu^2), um (the same at every depth)."""
    return np.full_like(np.asarray(delta, dtype=float), _stiffness(geometry, nu))


@indentation_model(
    "flat_punch",
    name="Flat cylindrical punch (Sneddon)",
    equation="F = 2 a E/(1-nu^2) delta",
    geometry=(PUNCH_RADIUS,),
    dshape=dshape,
    exponent=1.0,
    reference="Sneddon 1965, Int. J. Eng. Sci. 3:47",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E = 2 a delta / (1 - nu^2), um^2 (nN per kPa)."""
    return _stiffness(geometry, nu) * delta
