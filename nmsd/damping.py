"""Nodal damping of eq 6, seed 000: a drag on each node growing with its displacement.

    F_d = (d0 + d1 |r - r0|) v

r, r0 (um): current and rest position of the node; v (um/s) its velocity; d0 (nN s/um),
d1 (nN s/um^2); F_d in nN. The paper writes the damper per node (absolute velocity, a drag
against the surrounding medium) although Fig. 3 draws Voigt dampers along the links; we
follow the equation.
"""

from __future__ import annotations

import numpy as np


def nodal_damping(
    displacement: np.ndarray, velocity: np.ndarray, d0: float, d1: float
) -> tuple[np.ndarray, np.ndarray]:
    """Damping force (n, 2) in nN and the coefficient d0 + d1 |u| (n,) in nN s/um."""
    coefficient = d0 + d1 * np.linalg.norm(displacement, axis=1)
    return coefficient[:, None] * velocity, coefficient
