"""Three-sided pyramid (Bilodeau's approximation).

.. math::

    F = 0.8887 \\frac{E}{1-\\nu^2} \\tan\\theta \\, \\delta^2

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], theta face angle (centre line to
face) of a regular three-sided pyramid [deg], delta indentation [um]. Sharp rigid pyramid on a
linear-elastic half-space, as :mod:`afm.models.pyramid` (four-sided, 0.7453). Both are the same
delta^2 law, so a modulus fitted with one converts exactly to the other:
``E_3 = E_4 * 0.7453 / 0.8887``. This is nanite's ``hertz_pyr3s``.

Reference: G. G. Bilodeau, J. Appl. Mech. 59 (1992) 519-523.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from afm.models.pyramid import FACE_ANGLE, prefactor
from afm.models.registry import indentation_model

BILODEAU_THREE_SIDED = 0.8887


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 * 0.8887 tan(theta) delta / (1 - nu^2), um."""
    return 2.0 * prefactor(BILODEAU_THREE_SIDED, geometry, nu) * delta


@indentation_model(
    "pyramid_3s",
    name="Three-sided pyramid (Bilodeau)",
    equation="F = 0.8887 E/(1-nu^2) tan(theta) delta^2",
    geometry=(FACE_ANGLE,),
    dshape=dshape,
    exponent=2.0,
    reference="Bilodeau 1992, J. Appl. Mech. 59:519",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E = 0.8887 tan(theta) delta^2 / (1 - nu^2), um^2."""
    return prefactor(BILODEAU_THREE_SIDED, geometry, nu) * delta**2
