"""Stokes flow past a sphere on the axis of a cylindrical channel (axisymmetric, scikit-fem).

The real-time deformability cytometry setting: a cell of radius ``a`` carried by a pressure-
driven flow ``Q`` through a channel of radius ``R``; Reynolds numbers of 0.01-0.1, so the flow
is Stokes flow. In the frame of the cell (at rest), the wall moves at ``-U`` and the ends carry
Poiseuille's profile less ``U``; ``U`` is the speed at which the rigid cell is force-free.
Unknowns: velocity ``(u_r, u_z)`` [um/s], pressure ``p`` [kPa], viscosity ``mu`` [kPa s];
Taylor-Hood elements (P2/P1) on curved 6-node triangles, weakly (``dV = r dr dz``)::

    int mu [2 e(u):e(v) + 2 u_r v_r / r^2] r  -  int p div v r  = 0
    int q div u r = 0,          div u = d_r u_r + u_r / r + d_z u_z

    u = 0 on the cell,  u = (0, -U) on the wall,  u = (0, 2 Q/(pi R^2) (1 - r^2/R^2) - U) at
    the ends,  u_r = 0 on the axis.

The solution is linear in ``(Q, U)``: two solves with one factorisation (Poiseuille past the
cell held still; the channel sliding past it at unit speed) give the force on the cell
``F(U) = F_Q + U F_U`` and the force-free speed ``U = -F_Q / F_U``. The traction on the cell,
``t = sigma . n`` with ``sigma = -p I + mu (grad u + grad u^T)`` and ``n`` the cell's outward
normal, is returned at the facet quadrature points, the pressure referred to its mean over
the cell's surface (a uniform pressure does not deform an incompressible cell). The force on
the cell (its integral over ``2 pi r ds``) is checked against the reaction of the cell's
velocity constraints and the momentum balance of the fluid (the stresses on the channel's
wall and ends).
"""

from __future__ import annotations

from dataclasses import dataclass

import gmsh
import numpy as np
import scipy.sparse as sp
import skfem
from numpy.typing import NDArray
from skfem import BilinearForm, ElementTriP1, ElementTriP2, ElementVector, asm
from skfem.helpers import ddot, sym_grad

from oocyte_fe.errors import InputError
from oocyte_fe.fe.linear import SparseLU
from oocyte_fe.mesh.cache import cached_mesh
from oocyte_fe.mesh.gmsh_session import add_physical, distance_to_curves, refine_near

OUTER = ("wall", "inlet", "outlet")


@dataclass(frozen=True)
class SphereInTube:
    """A sphere of radius ``sphere_radius_um`` centred on the axis of a channel of radius
    ``channel_radius_um``, ``half_length_um`` up- and downstream; element sizes [um]."""

    channel_radius_um: float
    sphere_radius_um: float
    half_length_um: float
    size_um: float
    surface_size_um: float

    def __post_init__(self) -> None:
        src = "SphereInTube"
        for name in ("channel_radius_um", "sphere_radius_um", "half_length_um", "size_um"):
            if not np.isfinite(getattr(self, name)) or getattr(self, name) <= 0:
                raise InputError(src, name, "a positive number", getattr(self, name))
        if not 0 < self.surface_size_um <= self.size_um:
            raise InputError(src, "surface_size_um", "in (0, size_um]", self.surface_size_um)
        if self.sphere_radius_um >= 0.95 * self.channel_radius_um:
            raise InputError(
                src, "sphere_radius_um", "below 0.95 channel_radius_um", self.sphere_radius_um
            )
        if self.half_length_um < 3 * self.channel_radius_um:
            raise InputError(
                src, "half_length_um", ">= 3 channel radii (developed flow at the ends)"
            )


def _build(g: SphereInTube) -> float:
    geo = gmsh.model.geo
    a, R, L = g.sphere_radius_um, g.channel_radius_um, g.half_length_um
    centre = geo.addPoint(0.0, 0.0, 0.0)
    south, east, north = geo.addPoint(0, -a, 0), geo.addPoint(a, 0, 0), geo.addPoint(0, a, 0)
    top, top_wall = geo.addPoint(0, L, 0), geo.addPoint(R, L, 0)
    bottom, bottom_wall = geo.addPoint(0, -L, 0), geo.addPoint(R, -L, 0)
    axis_low = geo.addLine(bottom, south)
    arcs = [geo.addCircleArc(south, centre, east), geo.addCircleArc(east, centre, north)]
    axis_high = geo.addLine(north, top)
    outlet = geo.addLine(top, top_wall)
    wall = geo.addLine(top_wall, bottom_wall)
    inlet = geo.addLine(bottom_wall, bottom)
    loop = geo.addCurveLoop([axis_low, *arcs, axis_high, outlet, wall, inlet])
    fluid = geo.addPlaneSurface([loop])
    geo.synchronize()
    add_physical(2, [fluid], "fluid")
    add_physical(1, arcs, "cell")
    add_physical(1, [axis_low, axis_high], "axis")
    add_physical(1, [wall], "wall")
    add_physical(1, [inlet], "inlet")
    add_physical(1, [outlet], "outlet")
    refine_near(distance_to_curves(arcs), g.size_um, g.surface_size_um, 0.1 * a)
    return g.size_um


def channel_mesh(geom: SphereInTube) -> skfem.Mesh:
    """The fluid's section (r >= 0), curved 6-node triangles, cached by its parameters."""
    return cached_mesh(geom, 2, lambda: _build(geom))


@dataclass(frozen=True)
class FlowPastCell:
    """The force-free state: cell speed ``speed_um_s``, the traction on the cell at its facet
    quadrature points (``points_um`` (2, n), ``traction_kPa`` (2, n), ``weights_um2`` (n,):
    ``2 pi r ds``), the axial force on the cell from the traction integral, from the
    reaction and from the fluid's momentum balance [nN] for the two unit problems, the drag
    per unit speed of the still channel [nN s/um], and the sizes."""

    geometry: SphereInTube
    viscosity_kPa_s: float
    flow_rate_um3_s: float
    speed_um_s: float
    points_um: NDArray
    traction_kPa: NDArray
    weights_um2: NDArray
    force_traction_nN: tuple[float, float]
    force_reaction_nN: tuple[float, float]
    force_balance_nN: tuple[float, float]
    drag_per_speed_nN_s_um: float
    n_dofs: int

    @property
    def mean_velocity_um_s(self) -> float:
        return self.flow_rate_um3_s / (np.pi * self.geometry.channel_radius_um**2)


def _forms(mu: float) -> tuple[BilinearForm, BilinearForm]:
    @BilinearForm
    def viscous(u, v, w):
        r = w.x[0]
        return mu * (2.0 * ddot(sym_grad(u), sym_grad(v)) + 2.0 * u[0] * v[0] / r**2) * r

    @BilinearForm
    def divergence(u, q, w):
        r = w.x[0]
        return -(u.grad[0][0] + u[0] / r + u.grad[1][1]) * q * r

    return viscous, divergence


def _stress_on(ub, pb, mesh, boundary: str, mu: float, x: NDArray, n_u: int):
    """Points, traction sigma.n (n: the fluid's outward normal) and 2 pi r ds on a boundary."""
    facets = mesh.boundaries[boundary]
    fu = skfem.FacetBasis(mesh, ub.elem, facets=facets, intorder=6)
    fp = skfem.FacetBasis(mesh, pb.elem, facets=facets, intorder=6)
    u = fu.interpolate(x[:n_u])
    p = np.asarray(fp.interpolate(x[n_u:]))
    g = np.asarray(u.grad)  # (2, 2, nf, nq): g[i, j] = d u_i / d x_j
    sigma = mu * (g + g.transpose(1, 0, 2, 3)) - p * np.eye(2)[:, :, None, None]
    n = np.asarray(fu.normals)
    X = np.asarray(fu.global_coordinates())
    t = np.einsum("ijfq,jfq->ifq", sigma, n)
    w = 2.0 * np.pi * X[0] * fu.dx
    return X.reshape(2, -1), t.reshape(2, -1), w.ravel()


def flow_past_cell(
    geom: SphereInTube, viscosity_kPa_s: float, flow_rate_um3_s: float
) -> FlowPastCell:
    """Solve the two unit problems and combine them into the force-free state (see module)."""
    for name, value in (("viscosity_kPa_s", viscosity_kPa_s), ("flow_rate_um3_s", flow_rate_um3_s)):
        if not np.isfinite(value) or value <= 0:
            raise InputError("flow_past_cell", name, "a positive number", value)
    mesh = channel_mesh(geom)
    ub = skfem.Basis(mesh, ElementVector(ElementTriP2()), intorder=4)
    pb = skfem.Basis(mesh, ElementTriP1(), intorder=4)
    viscous, divergence = _forms(viscosity_kPa_s)
    A, B = asm(viscous, ub), asm(divergence, ub, pb)
    K = sp.bmat([[A, B.T], [B, None]], format="csr")
    n_u = ub.N
    R = geom.channel_radius_um
    umax = 2.0 * flow_rate_um3_s / (np.pi * R**2)
    loc = ub.doflocs
    fixed, values_q, values_u = [], [], []
    for b in ("cell", *OUTER):
        for c, name in enumerate(("u^1", "u^2")):
            d = ub.get_dofs(b).all(name)
            poiseuille = umax * (1.0 - (loc[0, d] / R) ** 2) if b in ("inlet", "outlet") else 0.0
            fixed.append(d)
            values_q.append(np.zeros(d.size) + (poiseuille if c == 1 else 0.0))
            values_u.append(np.full(d.size, -1.0 if (c == 1 and b != "cell") else 0.0))
    axis = ub.get_dofs("axis").all("u^1")
    # p is defined up to a constant: 0 at the outlet on the axis
    p_ref = n_u + int(np.argmin(np.hypot(pb.doflocs[0], pb.doflocs[1] - geom.half_length_um)))
    fixed += [axis, np.array([p_ref])]
    values_q += [np.zeros(axis.size), np.zeros(1)]
    values_u += [np.zeros(axis.size), np.zeros(1)]
    D = np.concatenate(fixed)
    order = np.unique(D, return_index=True)[1]
    D = D[order]
    free = np.setdiff1d(np.arange(K.shape[0]), D)
    lu = SparseLU().factorize(K[free][:, free])
    solutions = []
    for values in (values_q, values_u):
        x = np.zeros(K.shape[0])
        x[D] = np.concatenate(values)[order]
        rhs = -(K[free][:, D] @ x[D])
        x[free] = lu.solve(rhs)
        solutions.append(x)
    cell_z = ub.get_dofs("cell").all("u^2")
    forces = []
    for x in solutions:
        reaction = K @ x  # the force the constraints exert on the fluid (weak form / 2 pi)
        on_cell = -2.0 * np.pi * reaction[cell_z].sum()
        _, t, w = _stress_on(ub, pb, mesh, "cell", viscosity_kPa_s, x, n_u)
        traction_z = -np.sum(t[1] * w)  # the cell's outward normal is -n of the fluid
        outer = 0.0  # momentum balance: the force on the cell = the stresses on the channel
        for b in OUTER:
            _, t_b, w_b = _stress_on(ub, pb, mesh, b, viscosity_kPa_s, x, n_u)
            outer += float(np.sum(t_b[1] * w_b))
        forces.append((traction_z, on_cell, outer))
    (fq_t, fq_r, fq_b), (fu_t, fu_r, fu_b) = forces
    speed = -fq_r / fu_r
    state = solutions[0] + speed * solutions[1]
    fp = skfem.FacetBasis(mesh, pb.elem, facets=mesh.boundaries["cell"], intorder=6)
    area = 2.0 * np.pi * fp.global_coordinates()[0] * fp.dx
    state[n_u:] -= np.sum(np.asarray(fp.interpolate(state[n_u:])) * area) / np.sum(area)
    X, t, w = _stress_on(ub, pb, mesh, "cell", viscosity_kPa_s, state, n_u)
    return FlowPastCell(
        geometry=geom,
        viscosity_kPa_s=viscosity_kPa_s,
        flow_rate_um3_s=flow_rate_um3_s,
        speed_um_s=float(speed),
        points_um=X,
        traction_kPa=-t,
        weights_um2=w,
        force_traction_nN=(float(fq_t), float(fu_t)),
        force_reaction_nN=(float(fq_r), float(fu_r)),
        force_balance_nN=(float(fq_b), float(fu_b)),
        drag_per_speed_nN_s_um=float(-fu_r),
        n_dofs=K.shape[0],
    )
