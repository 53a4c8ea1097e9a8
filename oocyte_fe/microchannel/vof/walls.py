"""Lattice fields continued into the cells off the fluid, with the walls' conditions."""

from __future__ import annotations

import numpy as np
from scipy import ndimage


def walled(field: np.ndarray, fluid: np.ndarray, wall_value: float | None) -> np.ndarray:
    """``field`` continued into the lattice cells off the fluid (walls, outside the channel):
    the nearest fluid cell's value (zero normal gradient, the walls' condition for alpha and
    p) or ``wall_value`` (no slip: U = 0)."""
    if fluid.all():
        return field
    if wall_value is not None:
        return np.where(fluid, field, wall_value)
    index = ndimage.distance_transform_edt(~fluid, return_distances=False, return_indices=True)
    return field[tuple(index)]
