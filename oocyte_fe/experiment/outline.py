"""The cell's deformed outline and whether it passes through itself.

A continuum without self-contact lets a fold of its surface go on through the other side of
the fold: the FE converges to a state that is not one of the solid. The outline (the outer
surface at its quadrature points, ordered around the section) is checked for crossings at
every output frame (:mod:`~oocyte_fe.experiment.driver`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from oocyte_fe.fe.body import Body


def body_outline_um(body: Body, x: NDArray) -> NDArray:
    """The deformed outline of the whole section (k, 2) [um] for the state ``x``, closed and
    ordered around it by the reference polar angle, at the outer surface's quadrature points
    (axisymmetric: the meridional half mirrored about the axis)."""
    fb = body.facet_basis("outer_surface")
    X = np.asarray(fb.global_coordinates()).reshape(2, -1)
    current = X + np.asarray(fb.interpolate(body.displacement(x))).reshape(2, -1)
    current = current[:, np.argsort(np.arctan2(X[0], X[1]))]
    if body.axisym:
        current = np.concatenate([current, current[:, ::-1] * [[-1.0], [1.0]]], axis=1)
    return current.T


def _orient(p: NDArray, q: NDArray, r: NDArray) -> NDArray:
    """``(q - p) x (r - p)`` of rows of points: > 0 where ``r`` lies left of ``p -> q``."""
    return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])


def polygon_crossings(x: NDArray) -> int:
    """The number of crossings of a closed polygon ``x`` (k, 2) with itself: pairs of edges
    that are not neighbours and cross properly (the ends of each strictly on either side of
    the other, by the signs of ``orient``). Only edges whose midpoints lie within the longest
    edge of each other can cross; those pairs are found with a k-d tree."""
    a, b = x, np.roll(x, -1, axis=0)
    k = len(x)
    longest = float(np.max(np.linalg.norm(b - a, axis=1)))
    pairs = cKDTree(0.5 * (a + b)).query_pairs(longest * (1 + 1e-9), output_type="ndarray")
    if len(pairs) == 0:
        return 0
    i, j = pairs.min(axis=1), pairs.max(axis=1)
    apart = (j - i > 1) & ~((i == 0) & (j == k - 1))  # neighbours share a vertex
    i, j = i[apart], j[apart]
    cross = (_orient(a[i], b[i], a[j]) * _orient(a[i], b[i], b[j]) < 0) & (
        _orient(a[j], b[j], a[i]) * _orient(a[j], b[j], b[i]) < 0
    )
    return int(np.count_nonzero(cross))
