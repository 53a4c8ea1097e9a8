"""Derived fields for output: Cauchy stress, von Mises stress, mean stress, contact pressure.

Cauchy stress from the first Piola-Kirchhoff stress, ``sigma = P F^T / J`` [kPa], with the
deviatoric part relaxed by the Prony history of the last accepted step
(``S_dev = g_inf S0 + sum g_i h_i``). Von Mises ``sqrt(3/2 s:s)``, ``s`` the deviator. Values
at quadrature points are averaged per element, then to the vertices (area-weighted), which is
what a VTU point field and a figure need; they are not used in the solution.
"""

from __future__ import annotations

import numpy as np
import skfem
from numpy.typing import NDArray

from oocyte_fe.errors import InputError
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.material import response
from oocyte_fe.fe.solver import Frame, Problem


def element_to_vertices(mesh, values: NDArray, area: NDArray) -> NDArray:
    """Area-weighted average at the vertices of per-element ``values``."""
    acc = np.zeros(mesh.nvertices)
    weight = np.zeros(mesh.nvertices)
    for corner in mesh.t[:3]:
        np.add.at(acc, corner, values * area)
        np.add.at(weight, corner, area)
    return acc / np.where(weight > 0, weight, 1.0)


def stress_fields(problem: Problem, x: NDArray) -> dict[str, NDArray]:
    """Vertex fields ``von_mises`` and ``mean_stress`` [kPa] of the accepted state ``x``."""
    body = problem.body
    ne = body.mesh.nelements
    fields = {"von_mises": np.zeros(ne), "mean_stress": np.zeros(ne)}
    area = np.zeros(ne)
    for k, region in enumerate(body.regions):
        kin, pq = problem.region_kinematics(x, k)
        elastic = response(kin, np.zeros_like(pq), region.material, None, 0.0)
        S_dev = elastic.S0
        prony = region.material.prony
        if prony.g:
            h = problem.histories[k].h
            S_dev = prony.g_inf * elastic.S0 + np.einsum("i,i...->...", np.asarray(prony.g), h)
        if kin.small:  # the linear solid: sigma = S_dev + p I
            sigma = S_dev + pq * np.eye(3)[:, :, None, None]
        else:
            P = np.einsum("iK...,KJ...->iJ...", kin.F, S_dev) + pq * kin.J * kin.FinvT
            sigma = np.einsum("iJ...,kJ...->ik...", P, kin.F) / kin.J
        mean = np.trace(sigma) / 3.0
        dev = sigma - mean * np.eye(3)[:, :, None, None]
        vm = np.sqrt(1.5 * np.einsum("ij...,ij...->...", dev, dev))
        dx = region.ubasis.dx
        elements = region.ubasis.tind
        area[elements] = dx.sum(axis=1)
        fields["von_mises"][elements] = (vm * dx).sum(axis=1) / area[elements]
        fields["mean_stress"][elements] = (mean * dx).sum(axis=1) / area[elements]
    return {name: element_to_vertices(body.mesh, v, area) for name, v in fields.items()}


def contact_pressure_at_vertices(problem: Problem, frame: Frame) -> NDArray:
    """Contact pressure [kPa] at the vertices (sum over obstacles, facet-averaged)."""
    body = problem.body
    nv = body.mesh.nvertices
    acc, total = np.zeros(nv), np.zeros(nv)
    for c, fb in problem.contacts:
        p = frame.contact_pressure[c.name].mean(axis=1)
        verts = body.mesh.facets[:, fb.find]
        for end in range(2):
            np.add.at(acc, verts[end], p)
            np.add.at(total, verts[end], 1.0)
    return acc / np.where(total > 0, total, 1.0)


def point_probes(body: Body, points_um: np.ndarray):
    """Matrix (2 p, n_u) giving the displacement components at reference points (p, 2) um.

    scikit-fem cannot locate points in a curved ``MeshTri2``, so the points are located and
    the P2 field evaluated on the straight-sided mesh of the same vertices and elements (the
    same dof numbering); that differs only in the curved outer elements, by less than the
    sagitta ``h^2 / (8 R)`` of their outer edge.
    """
    mesh = body.mesh
    straight = skfem.MeshTri(mesh.p, mesh.t)
    basis = skfem.Basis(straight, body.uelem, intorder=body.intorder)
    if basis.N != body.n_u:
        raise InputError(body.source, "mesh", "a mesh whose straight copy has the same dofs")
    return basis.probes(np.asarray(points_um, dtype=float).T)
