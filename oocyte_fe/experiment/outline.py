"""The cell's deformed outline and whether it passes through itself.

A continuum without self-contact lets a fold of its surface go on through the other side of
the fold: the FE converges to a state that is not one of the solid. The outline (the outer
surface at its quadrature points, ordered around the section) is checked for crossings at
every output frame (:mod:`~oocyte_fe.experiment.driver`); a crossing inside a rigid tool is
the contact penalty's give (both sides of a thin blade pressed into it), and one within a
facet's length of a tool is a facet turned round the tool's corner, a wrinkle smaller than the
mesh resolves there (the surface's facets at a blade's corner, 2.5 um, pressed 50 um), not a
fold.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from oocyte_fe.fe.body import Body


def body_outline_um(body: Body, x: NDArray, nodes: bool = False) -> NDArray:
    """The deformed outline of the whole section (k, 2) [um] for the state ``x``, closed and
    ordered around it by the reference polar angle, at the outer surface's quadrature points
    (axisymmetric: the meridional half mirrored about the axis). With ``nodes`` the facets'
    end vertices are in it too, so that the polygon passes through the surface's corners
    rather than cutting them (the surface wrapped round a tool's corner: the quadrature-point
    polygon alone can cross itself there while the surface does not)."""
    fb = body.facet_basis("outer_surface")
    X = np.asarray(fb.global_coordinates()).reshape(2, -1)
    current = X + np.asarray(fb.interpolate(body.displacement(x))).reshape(2, -1)
    if nodes:
        v = np.unique(body.mesh.facets[:, body.facets("outer_surface")])
        X = np.concatenate([X, body.mesh.p[:, v]], axis=1)
        current = np.concatenate([current, X[:, -len(v) :] + body.vertex_displacement(x)[:, v]], 1)
    current = current[:, np.argsort(np.arctan2(X[0], X[1]))]
    if body.axisym:
        current = np.concatenate([current, current[:, ::-1] * [[-1.0], [1.0]]], axis=1)
    return current.T


def facet_length_um(body: Body, x: NDArray, points: NDArray) -> NDArray:
    """The reference length [um] of the outer-surface facet nearest to each of ``points``
    (n, 2) in the state ``x`` (nearest by the facet's deformed midpoint): the mesh's
    resolution of the surface there."""
    facets = body.mesh.facets[:, body.facets("outer_surface")]  # (2, nf) vertices
    moved = body.vertex_displacement(x)
    current = body.mesh.p[:, : moved.shape[1]] + moved
    _, nearest = cKDTree((0.5 * (current[:, facets[0]] + current[:, facets[1]])).T).query(points)
    ends = body.mesh.p[:, facets[:, nearest]]
    return np.linalg.norm(ends[:, 1] - ends[:, 0], axis=0)


def _orient(p: NDArray, q: NDArray, r: NDArray) -> NDArray:
    """``(q - p) x (r - p)`` of rows of points: > 0 where ``r`` lies left of ``p -> q``."""
    return (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])


def crossing_points(x: NDArray) -> NDArray:
    """Where a closed polygon ``x`` (k, 2) crosses itself, (n, 2): one point per pair of edges
    that are not neighbours and cross properly (the ends of each strictly on either side of
    the other, by the signs of ``orient``), at ``p + t (q - p)``,
    ``t = orient(r, s, p) / (orient(r, s, p) - orient(r, s, q))`` for the edges ``p q`` and
    ``r s``. Only edges whose midpoints lie within the longest edge of each other can cross;
    those pairs are found with a k-d tree."""
    a, b = x, np.roll(x, -1, axis=0)
    k = len(x)
    longest = float(np.max(np.linalg.norm(b - a, axis=1)))
    pairs = cKDTree(0.5 * (a + b)).query_pairs(longest * (1 + 1e-9), output_type="ndarray")
    if len(pairs) == 0:
        return np.zeros((0, 2))
    i, j = pairs.min(axis=1), pairs.max(axis=1)
    apart = (j - i > 1) & ~((i == 0) & (j == k - 1))  # neighbours share a vertex
    i, j = i[apart], j[apart]
    on_p, on_q = _orient(a[j], b[j], a[i]), _orient(a[j], b[j], b[i])
    cross = (_orient(a[i], b[i], a[j]) * _orient(a[i], b[i], b[j]) < 0) & (on_p * on_q < 0)
    t = on_p[cross] / (on_p[cross] - on_q[cross])
    return a[i[cross]] + t[:, None] * (b[i[cross]] - a[i[cross]])


def polygon_crossings(x: NDArray) -> int:
    """The number of crossings of a closed polygon ``x`` (k, 2) with itself
    (:func:`crossing_points`)."""
    return len(crossing_points(x))
