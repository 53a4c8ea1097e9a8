"""Peripheral deformation at material points of the outer surface (seed 001, Fig. 5c).

The paper compares the deformation of the oocyte edge at five surface locations with its
micrographs. Here the five material points are the outer-surface vertices nearest to the polar
angles ``theta`` (measured from the front pole, the direction of travel +Z) of 30, 60, 90, 120
and 150 deg: equally spaced over the periphery, the poles left out (on the axis ``u_R = 0``).

Measures at a point with reference position ``(R, Z)`` and displacement ``(u_R, u_Z)`` [um]:

* radial inward displacement ``d_r = -u_R`` (towards the axis; independent of the
  translation along the pipette, so it is what an edge-to-edge width measurement sees);
* deformation ``|u - (0, w)|`` with ``w`` the volume-mean axial displacement (translation of
  the centroid): the displacement magnitude with the rigid advance removed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from skfem import Mesh

POLAR_DEG = (30.0, 60.0, 90.0, 120.0, 150.0)


@dataclass(frozen=True)
class MaterialPoints:
    """Vertex indices of the chosen surface points and their actual polar angles [deg]."""

    vertices: NDArray
    polar_deg: NDArray

    @classmethod
    def on_surface(
        cls, mesh: Mesh, centre_z_um: float = 0.0, polar_deg: tuple[float, ...] = POLAR_DEG
    ) -> MaterialPoints:
        """Nearest ``outer_surface`` vertices to ``polar_deg`` (from +Z towards +R)."""
        verts = np.unique(mesh.facets[:, mesh.boundaries["outer_surface"]])
        theta = np.degrees(np.arctan2(mesh.p[0, verts], mesh.p[1, verts] - centre_z_um))
        pick = [int(np.argmin(np.abs(theta - a))) for a in polar_deg]
        return cls(verts[pick], theta[pick])

    def radial_inward(self, u_vertices: NDArray) -> NDArray:
        """``-u_R`` [um] at the points; ``u_vertices`` (2, nverts)."""
        return -u_vertices[0, self.vertices]

    def deformation(self, u_vertices: NDArray, centroid_advance_um: float) -> NDArray:
        """``|u - (0, w)|`` [um] at the points, ``w`` the centroid advance."""
        rel = u_vertices[:, self.vertices] - np.array([[0.0], [centroid_advance_um]])
        return np.linalg.norm(rel, axis=0)
