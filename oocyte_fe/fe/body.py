"""A discretised body: mesh, material regions, finite-element spaces and the global dof layout.

Unknowns ``x = [u | p_region_1 | p_region_2 | ...]``: displacement ``u`` (vector P2, or MINI
P1+bubble with ``order=1``) over the whole mesh, and one continuous P1 pressure per material
region, so the pressure may jump across a material interface (ZP/cytoplasm) while the
displacement stays continuous (bonded layers, shared nodes). Taylor-Hood P2/P1 and MINI are
inf-sup stable: no volumetric locking at ``nu = 0.5``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from skfem import (
    Basis,
    ElementTriMini,
    ElementTriP1,
    ElementTriP2,
    ElementVector,
    FacetBasis,
    Mesh,
    MeshTri2,
)

from oocyte_fe.errors import InputError
from oocyte_fe.fe.material import Material
from oocyte_fe.mesh.quality import check_mesh

Form = Literal["axisymmetric", "plane_strain"]


@dataclass(frozen=True)
class Region:
    """One material region: its bases and its pressure block in ``x``."""

    name: str
    material: Material
    ubasis: Basis
    pbasis: Basis
    p_offset: int  # index of this region's first pressure dof in x
    p_used: NDArray  # pressure dofs (local numbering) that belong to the region


class Body:
    """Mesh + materials per named subdomain + plane-strain/axisymmetric form.

    Parameters
    ----------
    mesh
        scikit-fem triangle mesh (``MeshTri`` or quadratic ``MeshTri2``) with named subdomains.
    materials
        ``{subdomain name: Material}``; every element must belong to exactly one of them.
    form
        ``"axisymmetric"`` (``x[0] = R >= 0``, ``x[1] = Z`` the axis) or ``"plane_strain"``.
    order
        2 (P2/P1 Taylor-Hood, default) or 1 (MINI P1+bubble/P1).
    kinematics
        ``"finite_strain"`` (default) or ``"small_strain"``: the linear solid of small-strain
        elasticity (the assumption of Sneddon's and Hertz's solutions), see
        :func:`~oocyte_fe.fe.material.response`; contact and pressures still act on the
        displaced surface.
    """

    def __init__(
        self,
        mesh: Mesh,
        materials: dict[str, Material],
        form: Form = "axisymmetric",
        order: int = 2,
        intorder: int | None = None,
        source: str = "mesh",
        kinematics: Literal["finite_strain", "small_strain"] = "finite_strain",
    ) -> None:
        if form not in ("axisymmetric", "plane_strain"):
            raise InputError(source, "form", "'axisymmetric' or 'plane_strain'", got=form)
        if kinematics not in ("finite_strain", "small_strain"):
            raise InputError(
                source, "kinematics", "'finite_strain' or 'small_strain'", got=kinematics
            )
        self.small_strain = kinematics == "small_strain"
        if order not in (1, 2):
            raise InputError(source, "order", "1 or 2", got=order)
        if isinstance(mesh, MeshTri2) and order != 2:
            raise InputError(source, "order", "2 with a quadratic (MeshTri2) mesh", got=order)
        check_mesh(mesh, source)  # inverted or degenerate elements are named, not solved
        self.mesh = mesh
        self.form = form
        self.axisym = 1.0 if form == "axisymmetric" else 0.0
        if self.axisym and mesh.p[0].min() < -1e-9 * np.ptp(mesh.p[0]):
            raise InputError(source, "mesh", "r = x >= 0 everywhere in an axisymmetric mesh")
        self.source = source
        intorder = intorder or (4 if order == 2 else 3)
        scalar = ElementTriP2() if order == 2 else ElementTriMini()
        self.uelem = ElementVector(scalar)
        self.intorder = intorder
        self.ubasis = Basis(mesh, self.uelem, intorder=intorder)
        self.n_u = self.ubasis.N
        subdomains = mesh.subdomains or {}
        missing = sorted(set(materials) - set(subdomains))
        if missing:
            raise InputError(
                source,
                f"subdomain {missing[0]!r}",
                "a physical group of the mesh (present: "
                f"{', '.join(sorted(subdomains)) or 'none'})",
            )
        count = np.zeros(mesh.nelements, dtype=int)
        for name in materials:
            count[subdomains[name]] += 1
        if np.any(count != 1):
            raise InputError(source, "subdomains", "every element in exactly one material region")
        self.regions: list[Region] = []
        offset = self.n_u
        for name, material in materials.items():
            elements = subdomains[name]
            ub = Basis(mesh, self.uelem, intorder=intorder, elements=elements)
            pb = Basis(mesh, ElementTriP1(), intorder=intorder, elements=elements)
            used = np.unique(pb.element_dofs)
            self.regions.append(Region(name, material, ub, pb, offset, used))
            offset += pb.N
        self.n_dofs = offset
        unused = [r.p_offset + np.setdiff1d(np.arange(r.pbasis.N), r.p_used) for r in self.regions]
        self.unused_pressure_dofs = np.concatenate(unused) if unused else np.array([], dtype=int)

    # --- dof helpers ------------------------------------------------------------------------

    def displacement(self, x: NDArray) -> NDArray:
        return x[: self.n_u]

    def pressure(self, x: NDArray, region: Region) -> NDArray:
        return x[region.p_offset : region.p_offset + region.pbasis.N]

    def boundary_dofs(self, boundary: str, component: int) -> NDArray:
        """Displacement dofs of component 0 (x or R) or 1 (y or Z) on a named boundary."""
        if component not in (0, 1):
            raise InputError(self.source, "component", "0 or 1", got=component)
        return self.ubasis.get_dofs(facets=self.facets(boundary)).all(f"u^{component + 1}")

    def point_dofs(self, point: tuple[float, float], component: int) -> NDArray:
        """The displacement dof of component 0/1 at the mesh vertex at ``point`` [um]."""
        dist = np.hypot(self.mesh.p[0] - point[0], self.mesh.p[1] - point[1])
        k = int(np.argmin(dist))
        if dist[k] > 1e-6 * float(np.ptp(self.mesh.p)):
            raise InputError(self.source, "point", "a mesh vertex", got=tuple(point))
        if component not in (0, 1):
            raise InputError(self.source, "component", "0 or 1", got=component)
        return self.ubasis.nodal_dofs[component, [k]]

    def facets(self, boundary: str) -> NDArray:
        boundaries = self.mesh.boundaries or {}
        if boundary not in boundaries:
            raise InputError(
                self.source,
                f"boundary {boundary!r}",
                "a physical group of the mesh (present: "
                f"{', '.join(sorted(boundaries)) or 'none'})",
            )
        return boundaries[boundary]

    def facet_basis(self, boundary: str, intorder: int | None = None) -> FacetBasis:
        """The boundary's facet basis, integrated at Gauss order ``intorder`` (default: the
        body's)."""
        return FacetBasis(
            self.mesh, self.uelem, facets=self.facets(boundary), intorder=intorder or self.intorder
        )

    def node_dofs(self) -> NDArray:
        """(2, nverts) displacement dofs at the mesh vertices."""
        return self.ubasis.nodal_dofs

    def vertex_displacement(self, x: NDArray) -> NDArray:
        """(2, nverts) displacement at the mesh vertices ``mesh.p[:, :mesh.nvertices]``."""
        return self.displacement(x)[self.ubasis.nodal_dofs]
