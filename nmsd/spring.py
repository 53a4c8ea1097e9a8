"""Link force of the NMSD spring, eqs 3-5 of seed 000: cubic below dl_c, linear above.

    f(dl) = k1 dl + k2 dl^3                          for |dl| <= dl_c
    f(dl) = sgn(dl) [A + B (|dl| - dl_c)]            for |dl| >  dl_c
    A = k1 dl_c + k2 dl_c^3,   B = k1 + 3 k2 dl_c^2  (force and slope continuous)

``dl`` is the link strain (l - l0)/l0 (dimensionless); f, k1, k2, A, B in nN.
"""

from __future__ import annotations

import numpy as np


def link_force(
    strain: np.ndarray, k1: float, k2: float, dl_c: float
) -> tuple[np.ndarray, np.ndarray]:
    """Force (nN) and its slope df/d(dl) (nN) of each link at the given strains."""
    a = k1 * dl_c + k2 * dl_c**3
    b = k1 + 3.0 * k2 * dl_c**2
    magnitude = np.abs(strain)
    low = magnitude <= dl_c
    linear = np.sign(strain) * (a + b * (magnitude - dl_c))
    force = np.where(low, k1 * strain + k2 * strain**3, linear)
    slope = np.where(low, k1 + 3.0 * k2 * strain**2, b)
    return force, slope
