"""Sphere of finite radius (Sneddon's exact solution of the Hertz problem).

.. math::

    \\delta = \\frac{a}{2} \\ln\\frac{R+a}{R-a}, \\qquad
    F = \\frac{E}{2(1-\\nu^2)} \\left[(a^2+R^2) \\ln\\frac{R+a}{R-a} - 2aR\\right]

F force [nN], E Young's modulus [kPa], nu Poisson ratio [1], R sphere radius [um], a contact
radius [um] (found from delta by Newton's method), delta indentation [um]. Valid for a < R;
tends to ``hertz_paraboloid`` for delta << R. Its slope is dF/d(delta) = 2 a E/(1-nu^2).

Reference: I. N. Sneddon, Int. J. Eng. Sci. 3 (1965) 47-57, eq. 6.15.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from afm.models.hertz_paraboloid import TIP_RADIUS
from afm.models.registry import indentation_model

_NEWTON_STEPS = 30


def contact_radius(delta: np.ndarray, radius_um: float) -> np.ndarray:
    """Contact radius a [um] solving delta = (a/2) ln((R+a)/(R-a)) for each delta >= 0."""
    delta = np.asarray(delta, dtype=float)
    r = radius_um
    a = np.minimum(np.sqrt(r * delta), 0.999 * r)
    for _ in range(_NEWTON_STEPS):
        log_term = np.log((r + a) / (r - a))
        residual = 0.5 * a * log_term - delta
        slope = 0.5 * log_term + a * r / (r * r - a * a)
        step = np.divide(residual, slope, out=np.zeros_like(a), where=slope > 0)
        a = np.clip(a - step, 0.0, r * (1.0 - 1e-12))
        if np.all(np.abs(step) <= 1e-14 * r):
            break
    return a


def dshape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """d(F/E)/d(delta) = 2 a / (1 - nu^2), um."""
    return 2.0 * contact_radius(delta, geometry["radius_um"]) / (1.0 - nu**2)


@indentation_model(
    "hertz_sphere",
    name="Hertz sphere (exact, Sneddon)",
    equation="delta = (a/2) ln((R+a)/(R-a)); F = E/(2(1-nu^2)) [(a^2+R^2) ln((R+a)/(R-a)) - 2aR]",
    geometry=(TIP_RADIUS,),
    dshape=dshape,
    exponent=1.5,
    reference="Sneddon 1965, Int. J. Eng. Sci. 3:47",
)
def shape(delta: np.ndarray, geometry: Mapping[str, float], nu: float) -> np.ndarray:
    """F/E in um^2 from the contact radius of :func:`contact_radius`."""
    r = geometry["radius_um"]
    a = contact_radius(delta, r)
    log_term = np.log((r + a) / (r - a))
    return ((a * a + r * r) * log_term - 2.0 * a * r) / (2.0 * (1.0 - nu**2))
