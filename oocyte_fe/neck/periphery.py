"""Peripheral deformation at material points of the outer surface (seed 001, Fig. 5c).

The paper compares the deformation of the oocyte edge at five surface locations with its
micrographs. Here the five material points lie on the outer surface at the polar angles
``theta`` (measured from the front pole, the direction of travel +Z) of 30, 60, 90, 120 and
150 deg: equally spaced over the periphery, the poles left out (on the axis ``u_R = 0``).
Each point is where the ray from the centre at ``theta`` crosses the meshed surface; its
displacement is the P2 trace on that surface facet (no snapping to the nearest vertex, which
would move the point by up to half an element between meshes and show up in a mesh study).

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
from skfem import Basis, Mesh

from oocyte_fe.errors import InputError

POLAR_DEG = (30.0, 60.0, 90.0, 120.0, 150.0)


@dataclass(frozen=True)
class MaterialPoints:
    """Surface material points: facet, end vertices, position ``s`` in [0, 1] along it.

    ``polar_deg`` are the points' polar angles [deg], ``position_um`` (2, n) their reference
    coordinates (R, Z).
    """

    facets: NDArray
    vertices: NDArray  # (2, n): the facet's end vertices a, b (s = 0 at a)
    s: NDArray
    polar_deg: NDArray
    position_um: NDArray

    @classmethod
    def on_surface(
        cls, mesh: Mesh, centre_z_um: float = 0.0, polar_deg: tuple[float, ...] = POLAR_DEG
    ) -> MaterialPoints:
        """Points where rays from ``(0, centre_z_um)`` at ``polar_deg`` (from +Z towards +R)
        cross the ``outer_surface`` facets."""
        facets = mesh.boundaries["outer_surface"]
        a, b = mesh.facets[:, facets]
        pa = mesh.p[:, a] - np.array([[0.0], [centre_z_um]])
        pb = mesh.p[:, b] - np.array([[0.0], [centre_z_um]])
        found = []
        for angle in polar_deg:
            d = np.array([np.sin(np.deg2rad(angle)), np.cos(np.deg2rad(angle))])
            # ray t d = pa + s (pb - pa): solve for (t, s) on each facet
            e = pb - pa
            det = d[0] * (-e[1]) - d[1] * (-e[0])
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (pa[0] * (-e[1]) - pa[1] * (-e[0])) / det
                s = (d[0] * pa[1] - d[1] * pa[0]) / det
            hit = np.flatnonzero((t > 0) & (s >= -1e-12) & (s <= 1 + 1e-12))
            if hit.size == 0:
                raise InputError(
                    "outer_surface", "polar angle", "a ray crossing the surface", angle
                )
            k = hit[np.argmax(t[hit])]  # outermost crossing
            found.append((facets[k], a[k], b[k], float(np.clip(s[k], 0.0, 1.0))))
        f, va, vb, s = (np.array(v) for v in zip(*found, strict=True))
        position = (1 - s) * mesh.p[:, va] + s * mesh.p[:, vb]
        theta = np.degrees(np.arctan2(position[0], position[1] - centre_z_um))
        return cls(f, np.vstack([va, vb]), s, theta, position)

    def displacement(self, basis: Basis, u: NDArray) -> NDArray:
        """(2, n) displacement [um] at the points: the quadratic (P2) trace on each facet,
        ``u(s) = (1-s)(1-2s) u_a + s(2s-1) u_b + 4s(1-s) u_mid``."""
        s = self.s
        na, nb, nm = (1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)
        ua = u[basis.nodal_dofs[:, self.vertices[0]]]
        ub = u[basis.nodal_dofs[:, self.vertices[1]]]
        um = u[basis.facet_dofs[:, self.facets]]
        return na * ua + nb * ub + nm * um

    @staticmethod
    def radial_inward(u_points: NDArray) -> NDArray:
        """``-u_R`` [um] from the points' displacement (2, n)."""
        return -u_points[0]

    @staticmethod
    def deformation(u_points: NDArray, centroid_advance_um: float) -> NDArray:
        """``|u - (0, w)|`` [um] at the points, ``w`` the centroid advance."""
        rel = u_points - np.array([[0.0], [centroid_advance_um]])
        return np.linalg.norm(rel, axis=0)
