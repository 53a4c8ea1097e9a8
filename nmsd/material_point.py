"""A material point of the lattice (e.g. the spindle), carried by the triangle it lies in.

The point's barycentric weights ``w`` in its reference Delaunay triangle (vertices ``i``)
stay fixed; its current position is ``x = sum_k w_k x_{i_k}`` (linear interpolation of the
nodal displacement, um).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nmsd.lattice import Lattice
from oocyte_fe.errors import InputError


@dataclass(frozen=True, eq=False)
class MaterialPoints:
    """Vertex indices (p, 3) and barycentric weights (p, 3) of points in the rest lattice."""

    vertices: np.ndarray
    weights: np.ndarray

    def positions(self, node_positions: np.ndarray) -> np.ndarray:
        """Current positions (p, 2) um for node positions (n, 2) um."""
        return np.einsum("pk,pkd->pd", self.weights, node_positions[self.vertices])


def locate(lattice: Lattice, points: np.ndarray) -> MaterialPoints:
    """Find the reference triangle and weights of each point (um, cell-centred axes)."""
    points = np.atleast_2d(np.asarray(points, dtype=float))
    tri = lattice.triangulation
    simplex = tri.find_simplex(points)
    if np.any(simplex < 0):
        bad = points[np.argmin(simplex)]
        raise InputError("locate", "points", "points inside the lattice", got=bad.tolist())
    transform = tri.transform[simplex]
    partial = np.einsum("pij,pj->pi", transform[:, :2], points - transform[:, 2])
    weights = np.column_stack([partial, 1.0 - partial.sum(axis=1)])
    return MaterialPoints(tri.simplices[simplex], weights)
