"""Fully developed generalized-Newtonian flow in a straight duct, by finite elements (scikit-fem).

The axial velocity u (um/s) on the cross-section solves, with G = -dp/dx (kPa/um)::

    -div( eta(|grad u|) grad u ) = G   in the section,    u = 0 on the wall,

weakly: ``R(u; v) = int eta(gamma) grad u . grad v - G v = 0`` with ``gamma = |grad u|`` (1/s).
In a circular pipe the axisymmetric form integrates over ``r dr`` on 0 <= r <= R (the symmetry
condition at r = 0 is natural). Newton's method with the consistent tangent::

    K(u; du, v) = int eta grad du . grad v
                    + (eta'(gamma) / gamma) (grad u . grad du)(grad u . grad v)

and a backtracking line search on the residual norm; ``eta'/gamma`` comes from
:meth:`Rheology.viscosity_slope`. The start is the Newtonian solution with the zero-shear
viscosity; strongly shear-thinning cases are reached by continuation in G (``steps``).
Quadratic Lagrange elements (P2); flow rate ``Q = int u dA`` (um^3/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from skfem import (
    Basis,
    BilinearForm,
    ElementLineP2,
    ElementTriP2,
    Functional,
    LinearForm,
    Mesh,
    MeshLine,
    MeshTri,
    condense,
    solve,
)
from skfem.helpers import dot, grad

from oocyte_fe.checks import number, positive
from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.microchannel.viscosity import Rheology

MAX_CELLS = 400
"""Most cells on the short side of a duct mesh (bounded work)."""


def rectangle_mesh(width: float, height: float, cells: int) -> MeshTri:
    """Triangles on [0, width] x [0, height] with ``cells`` divisions along the shorter side."""
    width = positive("rectangle_mesh", "width", width)
    height = positive("rectangle_mesh", "height", height)
    cells = number("rectangle_mesh", "cells", cells, ge=1, le=MAX_CELLS, integer=True)
    if max(width, height) / min(width, height) * cells > 50 * MAX_CELLS:
        raise InputError("rectangle_mesh", "width/height", "an aspect ratio of at most 50")
    short = min(width, height)
    nx = max(1, round(cells * width / short))
    ny = max(1, round(cells * height / short))
    return MeshTri.init_tensor(np.linspace(0.0, width, nx + 1), np.linspace(0.0, height, ny + 1))


def radial_mesh(radius: float, cells: int) -> MeshLine:
    """The radius 0 <= r <= R in ``cells`` equal segments (axisymmetric pipe section)."""
    radius = positive("radial_mesh", "radius", radius)
    cells = number("radial_mesh", "cells", cells, ge=1, le=100 * MAX_CELLS, integer=True)
    return MeshLine(np.linspace(0.0, radius, cells + 1))


def _weight(w) -> np.ndarray:
    """Area element: r for the axisymmetric section, 1 for a plane section."""
    return w.x[0] if w.axisymmetric else 1.0 + 0.0 * w.x[0]


@LinearForm
def residual_form(v, w):
    return (w.eta * dot(grad(w.u), grad(v)) - w.gradient * v) * _weight(w)


@BilinearForm
def tangent_form(du, v, w):
    gu = grad(w.u)
    return (
        w.eta * dot(grad(du), grad(v)) + w.slope * dot(gu, grad(du)) * dot(gu, grad(v))
    ) * _weight(w)


@Functional
def flow_rate_form(w):
    return w.u * _weight(w)


@dataclass(frozen=True)
class DuctFlow:
    """FE solution: nodal velocity ``u`` (um/s) on ``basis``, flow rate (um^3/s), convergence."""

    basis: Basis
    u: np.ndarray
    flow_rate: float
    area: float
    axisymmetric: bool
    converged: bool
    iterations: int
    residual_norms: tuple[float, ...]

    @property
    def mesh(self) -> Mesh:
        return self.basis.mesh

    @property
    def mean_velocity(self) -> float:
        return self.flow_rate / self.area

    @property
    def dofs(self) -> int:
        return int(self.u.size)


class _Problem:
    """Assembly of residual and tangent for one mesh, rheology and wall."""

    def __init__(self, mesh: Mesh, rheology: Rheology, axisymmetric: bool, wall: np.ndarray):
        element = ElementLineP2() if isinstance(mesh, MeshLine) else ElementTriP2()
        self.basis = Basis(mesh, element)
        self.rheology = rheology
        self.axisymmetric = axisymmetric
        self.wall = wall

    def fields(self, u: np.ndarray) -> dict:
        uh = self.basis.interpolate(u)
        gamma = np.sqrt(np.sum(uh.grad**2, axis=0))
        return {
            "u": uh,
            "eta": self.rheology.viscosity(gamma),
            "axisymmetric": self.axisymmetric,
        }

    def residual(self, u: np.ndarray, gradient: float) -> np.ndarray:
        r = residual_form.assemble(self.basis, gradient=gradient, **self.fields(u))
        r[self.wall] = 0.0
        return r

    def tangent(self, u: np.ndarray):
        f = self.fields(u)
        gamma = np.sqrt(np.sum(f["u"].grad ** 2, axis=0))
        return tangent_form.assemble(self.basis, slope=self.rheology.viscosity_slope(gamma), **f)

    def newtonian(self, gradient: float, viscosity: float) -> np.ndarray:
        n = self.basis.N
        zero = np.zeros(n)
        f = self.fields(zero)
        f["eta"] = np.full_like(f["eta"], viscosity)
        K = tangent_form.assemble(self.basis, slope=np.zeros_like(f["eta"]), **f)
        b = residual_form.assemble(self.basis, gradient=gradient, **f)
        return solve(*condense(K, -b, D=self.wall))

    def newton(
        self, u: np.ndarray, gradient: float, rtol: float, xtol: float, max_iter: int
    ) -> tuple[np.ndarray, bool, list[float]]:
        r = self.residual(u, gradient)
        scale = np.linalg.norm(
            residual_form.assemble(
                self.basis, gradient=gradient, **{**self.fields(np.zeros_like(u)), "eta": 0.0}
            )
        )
        norms = [float(np.linalg.norm(r))]
        for _ in range(max_iter):
            if norms[-1] <= rtol * scale:
                return u, True, norms
            du = solve(*condense(self.tangent(u), -r, D=self.wall))
            if np.linalg.norm(du) <= xtol * np.linalg.norm(u):
                return u, True, norms  # at round-off: the update no longer changes u
            step = 1.0
            while step > 1e-6:
                trial = u + step * du
                r_trial = self.residual(trial, gradient)
                if np.linalg.norm(r_trial) < (1.0 - 1e-4 * step) * norms[-1]:
                    break
                step *= 0.5
            u, r = trial, r_trial
            norms.append(float(np.linalg.norm(r)))
        return u, norms[-1] <= rtol * scale, norms


def solve_duct_flow(
    mesh: Mesh,
    rheology: Rheology,
    pressure_gradient: float,
    *,
    axisymmetric: bool = False,
    steps: int = 1,
    rtol: float = 1e-10,
    xtol: float = 1e-12,
    max_iter: int = 60,
) -> DuctFlow:
    """Fully developed flow on a plane section (MeshTri, u = 0 on its whole boundary) or, with
    ``axisymmetric=True``, on the radius of a pipe (MeshLine, u = 0 at r = R).

    ``steps`` > 1 ramps G geometrically from ``G / 10^(steps-1)`` (continuation). Newton stops
    when the residual is below ``rtol`` times the load ``|int G v|`` or the update below
    ``xtol`` times the solution (round-off). Raises :class:`SolverError` otherwise.
    """
    where = "solve_duct_flow"
    if not isinstance(mesh, (MeshLine, MeshTri)):  # skfem constructors, not types
        raise InputError(where, "mesh", "a MeshTri (rectangle_mesh) or MeshLine (radial_mesh)")
    if axisymmetric != isinstance(mesh, MeshLine):
        raise InputError(
            where, "axisymmetric", "True with a MeshLine radius, False with a MeshTri section"
        )
    pressure_gradient = positive(where, "pressure_gradient", pressure_gradient)
    steps = number(where, "steps", steps, ge=1, le=50, integer=True)
    rtol = number(where, "rtol", rtol, gt=0, lt=1)
    xtol = number(where, "xtol", xtol, gt=0, lt=1)
    max_iter = number(where, "max_iter", max_iter, ge=1, le=10_000, integer=True)
    if axisymmetric:
        radius = float(mesh.p.max())
        basis0 = Basis(mesh, ElementLineP2())
        wall = basis0.get_dofs(lambda x: np.isclose(x[0], radius)).all()
        area = math.pi * radius**2
    else:
        basis0 = Basis(mesh, ElementTriP2())
        wall = basis0.get_dofs().all()
        area = float(Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis0))
    problem = _Problem(mesh, rheology, axisymmetric, wall)
    gradients = pressure_gradient * np.logspace(-(steps - 1), 0, steps)
    eta0 = float(rheology.viscosity(1e-12))
    u = problem.newtonian(gradients[0], eta0)
    all_norms: list[float] = []
    converged = False
    for g in gradients:
        u, converged, norms = problem.newton(u, g, rtol, xtol, max_iter)
        all_norms += norms
        if not converged:
            raise SolverError(
                f"duct flow: Newton stopped at G = {g:.4g} kPa/um with residual "
                f"{norms[-1]:.3g} after {len(norms) - 1} iterations; increase steps"
            )
    q = float(
        flow_rate_form.assemble(
            problem.basis, u=problem.basis.interpolate(u), axisymmetric=axisymmetric
        )
    )
    if axisymmetric:
        q *= 2.0 * math.pi
    return DuctFlow(
        problem.basis, u, q, area, axisymmetric, converged, len(all_norms) - 1, tuple(all_norms)
    )
