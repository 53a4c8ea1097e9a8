"""Lattice fields continued into the cells off the fluid, with the walls' conditions, and the
index pairs of the lattice's faces."""

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


def face_pairs(axis: int) -> tuple[tuple[slice, slice], tuple[slice, slice]]:
    """Index pairs ``(lo, hi)`` of the lattice's interior faces normal to ``axis`` (0: y, the
    rows; 1: x, the columns): ``field[lo]`` and ``field[hi]`` are the two cells of each face,
    ``hi`` on the side its normal points to."""
    if axis == 0:
        return (slice(None, -1), slice(None)), (slice(1, None), slice(None))
    return (slice(None), slice(None, -1)), (slice(None), slice(1, None))
