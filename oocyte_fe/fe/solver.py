"""Quasi-static incremental solution: Newton with a consistent tangent and step cutbacks.

Each step solves ``r(x) = f_int(x) - f_ext(x) = 0`` for ``x = [u | p]`` by Newton's method with
the exact tangent of :mod:`~oocyte_fe.fe.forms`, :mod:`~oocyte_fe.fe.contact` and
:mod:`~oocyte_fe.fe.loads`; prescribed displacements enter as the first increment. The sparse
system is saddle-point (indefinite at ``nu = 0.5``) and unsymmetric (friction, follower
pressure), so it is solved with SuperLU and threshold partial pivoting on a nested-dissection
order (:mod:`~oocyte_fe.fe.linear`), which handles both; Cholesky or symmetric solvers would
not.

A step converges when ``|r_u| <= rtol * max(|f_int|, |f_ext|, f_floor)`` and
``|r_p| <= rtol * V``, with the floor ``f_floor = 1e-6 E_max L^2`` (``2 pi`` more in
axisymmetry) so that a step with vanishing forces (rigid motion) is judged sensibly.
A step that fails (iteration limit, NaN, an inverted element, a diverging residual) is halved, up to
``max_cutbacks`` times, then :class:`~oocyte_fe.errors.SolverError` names the time, the
residual and the cause. Every iteration's residual is logged, so quadratic convergence is
visible in the log.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from skfem import LinearForm, asm, condense

from oocyte_fe.errors import InadmissibleState, InputError, SolverError
from oocyte_fe.fe import contact as ct
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.forms import (
    compliance_pp,
    volume_constraint,
)
from oocyte_fe.fe.kinematics import Kinematics
from oocyte_fe.fe.linear import SparseLU
from oocyte_fe.fe.loads import (
    BodyForce,
    FollowerPressure,
    PinnedPoint,
    Prescribed,
    ReactionControl,
    SurfaceTraction,
    TorqueRelief,
)
from oocyte_fe.fe.material import ViscousHistory, response, update_history
from oocyte_fe.fe.pattern import SparsityPattern
from oocyte_fe.fe.self_contact import Pairs, SelfContact, SurfacePolyline
from oocyte_fe.fe.self_contact import forces as self_contact_forces
from oocyte_fe.fe.vectorized import FacetOperators, RegionOperators
from oocyte_fe.progress import report

LOG = logging.getLogger("oocyte_fe.fe")


@dataclass(frozen=True)
class NewtonSettings:
    """Iteration limits and tolerances (dimensionless)."""

    max_iterations: int = 20
    rtol: float = 1e-8
    max_cutbacks: int = 8
    divergence: float = 1e4  # residual growth over its first value that counts as divergence
    # halvings of a Newton step that would raise the residual (0: off). Off by default: on the
    # frictional pipette passage a plain Newton step with cutbacks got through where the
    # line search crept along at a linear rate
    line_search: int = 0
    # start each step from the last step's increment scaled to dt (a linear extrapolation in
    # time) instead of the last state; prescribed values are then already (nearly) in place
    predictor: bool = True
    # a step that fails from the predictor is taken once more from the last state before it is
    # halved (at a hold the predictor carries the cell on where the tool no longer goes)
    retry_from_last_state: bool = True


@dataclass(frozen=True)
class StepLog:
    """One accepted step: end time, size, Newton residual history, cutbacks spent on it."""

    t: float
    dt: float
    residuals: tuple[float, ...]
    cutbacks: int

    @property
    def iterations(self) -> int:
        return len(self.residuals) - 1


@dataclass
class Frame:
    """The solution at an output time."""

    t: float
    x: NDArray
    volume: float
    obstacle_forces: dict[str, NDArray]  # force on each obstacle [nN] (axisym: ring sums)
    contact_pressure: dict[str, NDArray]  # (nf, nq) at the boundary's quadrature points


@dataclass
class SolveResult:
    """All output frames and the step log of a solve."""

    frames: list[Frame] = field(default_factory=list)
    steps: list[StepLog] = field(default_factory=list)

    @property
    def times(self) -> NDArray:
        return np.array([f.t for f in self.frames])

    @property
    def cutbacks(self) -> int:
        return sum(s.cutbacks for s in self.steps)


class _StepFailed(Exception):
    def __init__(self, cause: str, residual: float) -> None:
        super().__init__(cause)
        self.cause, self.residual = cause, residual


def dead_load_vector(body: Body, load: SurfaceTraction | BodyForce) -> NDArray:
    """The force vector [nN] of a dead load on ``body`` at ``scale = 1``."""
    axisym = bool(body.axisym)
    if isinstance(load, SurfaceTraction):
        ops = FacetOperators.of(body.facet_basis(load.boundary))
        T = np.asarray(load.traction(ops.X), dtype=float)
        if T.shape != ops.X.shape or not np.all(np.isfinite(T)):
            raise InputError(load.name, "traction", "finite tractions (2, ...) at every point")
        return ops.dead_traction_force(T, axisym)

    def form(v, w):
        b = load.force(np.asarray(w.x))
        measure = 2.0 * np.pi * w.x[0] if axisym else 1.0
        return (b[0] * v[0] + b[1] * v[1]) * measure

    return asm(LinearForm(form), body.ubasis)


def _one(_t: float) -> float:
    return 1.0


class Problem:
    """A body with its boundary conditions, pressures and contacts; ``solve`` runs the steps."""

    def __init__(
        self,
        body: Body,
        prescribed: Sequence[Prescribed | PinnedPoint] = (),
        pressures: Sequence[FollowerPressure] = (),
        contacts: Sequence[ct.Contact] = (),
        log: logging.Logger | None = None,
        control: ReactionControl | None = None,
        dead_loads: Sequence[SurfaceTraction | BodyForce] = (),
        torque_relief: TorqueRelief | None = None,
        self_contact: SelfContact | None = None,
    ) -> None:
        self.body = body
        self.self_contact = self_contact
        self._self_line = (
            None
            if self_contact is None
            else SurfacePolyline.of(
                body.ubasis, body.facets(self_contact.boundary), bool(body.axisym)
            )
        )
        self.prescribed = list(prescribed)
        self.pressures = [(pl, body.facet_basis(pl.boundary)) for pl in pressures]
        self.contacts = [(c, body.facet_basis(c.boundary, c.quadrature_order)) for c in contacts]
        self.log = log or LOG
        self._pattern = SparsityPattern((body.n_dofs, body.n_dofs))
        self._fixed = [
            (
                body.point_dofs(b.point, b.component)
                if isinstance(b, PinnedPoint)
                else body.boundary_dofs(b.boundary, b.component),
                b,
            )
            for b in prescribed
        ]
        self.control = control
        self._linear = SparseLU()
        self.control_value = 0.0  # the controlled pressure [kPa] at the current state
        self._control_value = 0.0  # within a step (Newton iterate)
        if control is not None:
            names = [pl.name for pl, _ in self.pressures]
            if control.load not in names:
                raise InputError(
                    "ReactionControl", "load", f"a pressure load's name ({names})", control.load
                )
            self._control_load = names.index(control.load)
            self._control_dofs = body.boundary_dofs(control.boundary, control.component)
            if not any(
                isinstance(b, Prescribed)
                and b.boundary == control.boundary
                and b.component == control.component
                for b in prescribed
            ):
                raise InputError(
                    "ReactionControl",
                    "boundary",
                    "a prescribed boundary component (its reaction is controlled)",
                    (control.boundary, control.component),
                )
        fixed = [d for d, _ in self._fixed] + [body.unused_pressure_dofs]
        self.fixed_dofs = np.unique(np.concatenate(fixed)).astype(int)
        self.x = np.zeros(body.n_dofs)
        self.t = 0.0
        self._increment: tuple[NDArray, float] | None = None  # last accepted (dx, dt)
        # force scale floor: a strain of 1e-6 over the body, E_max L^2 1e-6 [nN]; keeps the
        # relative residual meaningful when the forces vanish (rigid motion, unloaded steps)
        size = float(np.ptp(body.mesh.p, axis=1).max())
        e_max = max(r.material.E_kPa for r in body.regions)
        self.force_floor = 1e-6 * e_max * size**2 * (2.0 * np.pi if body.axisym else 1.0)
        self._quad = [
            (np.asarray(r.ubasis.global_coordinates())[0], r.ubasis.dx) for r in body.regions
        ]
        self._pressure_ops = [FacetOperators.of(fb) for _, fb in self.pressures]
        self.dead_loads = [(load, dead_load_vector(body, load)) for load in dead_loads]
        self._torque = None if torque_relief is None else self._torque_mode(torque_relief)
        self._shift = None  # the unit body forces along x and y: the translation relief
        if torque_relief is not None and torque_relief.translation:
            unit = np.eye(2)
            self._shift = [
                dead_load_vector(body, BodyForce(lambda X, e=e: e[:, None, None] + 0.0 * X, _one))
                for e in unit
            ]
        self._split = body.ubasis.split_indices()  # the x and y displacement dofs
        self._contact_ops = [FacetOperators.of(fb) for _, fb in self.contacts]
        self._ops = [
            RegionOperators.of(r.ubasis, r.pbasis, bool(body.axisym)) for r in body.regions
        ]
        self.histories = [
            ViscousHistory.zeros(len(r.material.prony.g), r.ubasis.dx.shape) for r in body.regions
        ]
        self._masks = [self._mask(k, self.x) for k in range(len(self.pressures))]
        self.applied_masks = list(self._masks)
        self.contact_states = []
        for c, fb in self.contacts:
            X = np.asarray(fb.global_coordinates())
            gap, _ = c.obstacle.distance(X - np.asarray(c.motion(0.0))[:, None, None])
            tol = 1e-6 * float(np.ptp(body.mesh.p))
            if np.any(gap < -tol):
                raise InputError(
                    c.name,
                    "obstacle",
                    f"no initial overlap with boundary {c.boundary!r} (penetration "
                    f"{-gap.min():.3g} um at t = 0)",
                )
            self.contact_states.append(ct.ContactState(np.zeros_like(X), np.zeros(gap.shape), 0.0))

    def _torque_mode(self, relief: TorqueRelief) -> NDArray:
        """The load vector of the unit rotation mode about the reference centroid."""
        body = self.body
        if body.axisym:
            raise InputError(relief.name, "symmetry", "a plane-strain body (no turning about z)")
        weights = [(np.asarray(r.ubasis.global_coordinates()), r.ubasis.dx) for r in body.regions]
        area = sum(float(np.sum(dx)) for _, dx in weights)
        xc, yc = (sum(float(np.sum(X[d] * dx)) for X, dx in weights) / area for d in range(2))
        mode = BodyForce(lambda X: np.stack([-(X[1] - yc), X[0] - xc]), lambda _t: 1.0)
        return dead_load_vector(body, mode)

    def _moment(self, x: NDArray, f: NDArray) -> float:
        """``sum_i (x_i f_iy - y_i f_ix)`` [nN um] of nodal forces ``f`` at the nodes of ``x``."""
        sx, sy = self._split
        X = self.body.ubasis.doflocs
        return float(np.sum((X[0, sx] + x[sx]) * f[sy] - (X[1, sy] + x[sy]) * f[sx]))

    # --- assembly ----------------------------------------------------------------------------

    def dead_load_force(self, name: str, t: float) -> NDArray:
        """Resultant (x, y) [nN] of the dead load ``name`` on the body at time ``t``
        (axisymmetric: the ring sum, x is 0 by symmetry)."""
        for load, vec in self.dead_loads:
            if load.name == name:
                total = np.array([vec[d].sum() for d in self._split])
                return load.scale(t) * total * ([0.0, 1.0] if self.body.axisym else 1.0)
        raise KeyError(name)

    def _mask(self, k: int, x: NDArray) -> NDArray | None:
        """``where`` of pressure load ``k`` at its quadrature points in the configuration ``x``."""
        load, ops = self.pressures[k][0], self._pressure_ops[k]
        if load.where is None:
            return None
        current = ops.X + ops.interpolate(self.body.displacement(x))[0]
        return np.asarray(load.where(current), dtype=float)

    def _mask_gradient(self, k: int, x: NDArray, t: float) -> NDArray | None:
        """The gradient [kPa/um] at the current quadrature points of pressure load ``k``
        whose ``where`` varies smoothly with position and gives its ``gradient`` (a
        :class:`~oocyte_fe.fe.loads.FollowerPressure` of a flow's normal traction); None for
        masks (held from the step's start, or a window's 0 / 1)."""
        load, ops = self.pressures[k][0], self._pressure_ops[k]
        gradient = getattr(load.where, "gradient", None)
        if gradient is None or load.lagged:
            return None
        current = ops.X + ops.interpolate(self.body.displacement(x))[0]
        return self._load_value(k, t) * np.asarray(gradient(current), dtype=float)

    def _contact_eval(self, k: int, x: NDArray, t: float) -> ct.ContactEval:
        """Contact ``k`` at its quadrature points for the state ``x`` at time ``t``."""
        ops = self._contact_ops[k]
        u_q = ops.interpolate(self.body.displacement(x))[0]
        return ct.evaluate(self.contacts[k][0], ops.X, u_q, self.contact_states[k], t)

    def pressure_mask(self, k: int, x: NDArray | None = None) -> NDArray | None:
        """Mask of pressure load ``k`` for the step in progress: held from the step start if
        ``lagged``, else evaluated at ``x`` (default: the current state). After a step,
        ``applied_masks[k]`` is the mask that step was solved with."""
        if self.pressures[k][0].lagged:
            return self._masks[k]
        return self._mask(k, self.x if x is None else x)

    def region_kinematics(self, x: NDArray, k: int) -> tuple[Kinematics, NDArray]:
        """Kinematics and pressure [kPa] at the quadrature points of region ``k`` for ``x``."""
        ops, region = self._ops[k], self.body.regions[k]
        u = self.body.displacement(x)
        gu5 = np.einsum("iaeq,ie->aeq", ops.B, u[ops.dofs])
        p = self.body.pressure(x, region)
        pq = np.einsum("keq,ke->eq", ops.p_values, p[ops.p_dofs])
        return Kinematics.from_grad5(gu5, self.body.small_strain), pq

    def assemble(self, x: NDArray, t: float, dt: float):
        """Residual ``r`` and tangent ``K`` at ``x`` for the step ending at ``t``."""
        r, tangent, f_scale = self.residual(x, t, dt)
        return r, tangent(), f_scale

    def residual(self, x: NDArray, t: float, dt: float):
        """Residual ``r`` at ``x`` for the step ending at ``t``, a function that builds the
        tangent ``K`` there (Newton builds it only when it takes another step: the evaluation
        that converges, or a rejected line-search trial, does not), and the force scale."""
        body = self.body
        a = body.axisym
        r = np.zeros(body.n_dofs)
        deferred = []  # (k, A5, JFinvT5) of each region: the tangent's material parts
        blocks_uu = []  # the loads' and contacts' blocks (cheap: made here)
        f_int_norm2 = 0.0
        f_ext = np.zeros(body.n_u)
        for k, region in enumerate(body.regions):
            kin, pq = self.region_kinematics(x, k)
            inverted = not kin.small and np.any(kin.J <= 0)  # the linear solid cannot invert
            if inverted or not np.all(np.isfinite(kin.J)):
                raise _StepFailed(f"inverted element in region {region.name!r}", np.inf)
            res = response(kin, pq, region.material, self.histories[k], dt)
            ops = self._ops[k]
            fi = ops.internal_force(res.P5)
            f_int_norm2 += float(fi @ fi)
            r[: body.n_u] += fi
            deferred.append((k, res.A5, res.JFinvT5))
            inv_k = region.material.inv_kappa
            o, n_p = region.p_offset, region.pbasis.N
            r[o : o + n_p] = asm(
                volume_constraint, region.pbasis, Jm1=kin.J - 1.0, p=pq, inv_kappa=inv_k, axisym=a
            )
        u = body.displacement(x)
        for k, ops in enumerate(self._pressure_ops):
            pn = np.full(ops.dS.shape, self._load_value(k, t))
            mask = self.pressure_mask(k, x)
            if mask is not None:
                pn = pn * mask
            fe, Kp = ops.pressure(u, pn, bool(a), self._mask_gradient(k, x, t))
            f_ext += fe
            blocks_uu.append(Kp)
        for k, ops in enumerate(self._contact_ops):
            fc, Kc = ops.contact(self._contact_eval(k, x, t), bool(a))
            f_ext += fc
            blocks_uu.append(Kc)
        if self._self_line is not None:
            fs, Ks, _ = self_contact_forces(self._self_line, u, self.self_contact, body.n_u)
            f_ext += fs
            blocks_uu.append(Ks)
        for load, vec in self.dead_loads:
            f_ext += load.scale(t) * vec
        low_rank = []  # the reliefs' K += g w^T
        stiff = None  # the loads' and contacts' -df/du, for the reliefs' tangents
        if self._shift is not None:  # the resultant at x, balanced
            stiff = sp.csr_matrix(sum(blocks_uu)) if blocks_uu else None
            for d, g in zip(self._split, self._shift, strict=True):
                f_ext -= (f_ext[d].sum() / g[d].sum()) * g
                if stiff is not None:  # d(-F_d g / G_d)/du = g (sum_d rows of K_loads) / G_d
                    w = np.zeros(body.n_dofs)
                    w[: body.n_u] = -np.asarray(stiff[d].sum(axis=0)).ravel() / g[d].sum()
                    low_rank.append((np.concatenate([g, np.zeros(body.n_dofs - body.n_u)]), w))
        if self._torque is not None:
            g = self._torque
            m_g = self._moment(x, g)
            c = -self._moment(x, f_ext) / m_g
            # d(-c g)/du = g (grad M_f + c grad M_g) / M_g, grad M_f = (f_y, -f_x) per node
            w = np.zeros(body.n_dofs)
            sx, sy = self._split
            w[sx] = (f_ext[sy] + c * g[sy]) / m_g
            w[sy] = -(f_ext[sx] + c * g[sx]) / m_g
            if self._shift is not None and stiff is not None:  # the follower loads' df/du
                X = body.ubasis.doflocs
                xs, ys = X[0, sx] + x[sx], X[1, sy] + x[sy]  # each node's current position
                w[: body.n_u] -= (stiff[sy].T @ xs - stiff[sx].T @ ys) / m_g
            low_rank.append((np.concatenate([g, np.zeros(body.n_dofs - body.n_u)]), w))
            f_ext += c * g
        r[: body.n_u] -= f_ext

        def tangent() -> sp.csc_matrix:
            rows, cols, vals = [], [], []
            uu = list(blocks_uu)
            for k, A5, JFinvT5 in deferred:
                region, ops = body.regions[k], self._ops[k]
                uu.insert(k, ops.stiffness(A5))
                o = region.p_offset
                up_rows, up_cols, up_vals = ops.coupling(JFinvT5)
                rows += [up_rows, up_cols + o]
                cols += [up_cols + o, up_rows]
                vals += [up_vals, up_vals]
                inv_k = region.material.inv_kappa
                if inv_k > 0:
                    Kpp = asm(compliance_pp, region.pbasis, inv_kappa=inv_k, axisym=a).tocoo()
                    rows.append(Kpp.row + o)
                    cols.append(Kpp.col + o)
                    vals.append(Kpp.data)
            for block in uu:
                rows.append(block.row)
                cols.append(block.col)
                vals.append(block.data)
            return self._pattern.csc(
                np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
            )

        # the reliefs' K += G W^T (columns g, w), or None
        tangent.low_rank = (
            tuple(np.column_stack(c) for c in zip(*low_rank, strict=True)) if low_rank else None
        )
        return r, tangent, max(np.sqrt(f_int_norm2), float(np.linalg.norm(f_ext)))

    def self_contact_pairs(self, x: NDArray | None = None) -> Pairs | None:
        """The boundary's node-segment pairs within the self-contact's range at ``x``
        (default: the current state); None without self-contact."""
        if self._self_line is None:
            return None
        u = self.body.displacement(self.x if x is None else x)
        return self_contact_forces(self._self_line, u, self.self_contact, self.body.n_u)[2]

    def _load_value(self, k: int, t: float) -> float:
        """Pressure [kPa] of load ``k``: the controlled unknown or the load's ``pressure(t)``."""
        if self.control is not None and k == self._control_load:
            return self._control_value
        return float(self.pressures[k][0].pressure(t))

    def unit_load(self, k: int, x: NDArray) -> NDArray:
        """External force vector of pressure load ``k`` at 1 kPa (mask included) at ``x``."""
        ops = self._pressure_ops[k]
        pn = np.ones(ops.dS.shape)
        mask = self.pressure_mask(k, x)
        if mask is not None:
            pn = pn * mask
        return ops.pressure_force(self.body.displacement(x), pn, bool(self.body.axisym))

    def _control_active(self, x: NDArray) -> bool:
        """A control acts while its load reaches the body (a mask that is not all zero)."""
        if self.control is None:
            return False
        mask = self.pressure_mask(self._control_load, x)
        return mask is None or bool(np.any(mask > 0))

    def reaction(self, r: NDArray) -> float:
        """Net reaction [nN] on the controlled boundary component for the residual ``r``."""
        return float(r[self._control_dofs].sum())

    # --- one step ----------------------------------------------------------------------------

    def _targets(self, t: float) -> NDArray:
        target = self.x.copy()
        for dofs, bc in self._fixed:
            target[dofs] = bc.value(t)
        target[self.body.unused_pressure_dofs] = 0.0
        return target

    def _newton(self, t: float, dt: float, settings: NewtonSettings) -> tuple[NDArray, list[float]]:
        x = self.x.copy()
        predicted = settings.predictor and self._increment is not None
        if predicted:
            x += (dt / self._increment[1]) * self._increment[0]
        D = self.fixed_dofs
        free = np.setdiff1d(np.arange(self.body.n_dofs), D)
        n_u = self.body.n_u
        free_u, free_p = free[free < n_u], free[free >= n_u]
        volume = self.volume(self.x)
        target = self._targets(t)

        def evaluate(xx: NDArray) -> tuple[NDArray, object, float, float, float]:
            r, K, f_scale = self.residual(xx, t, dt)  # K: builds the tangent when called
            ru, rp = np.linalg.norm(r[free_u]), np.linalg.norm(r[free_p])
            if self._control_active(xx):  # the reaction's mismatch counts as a force residual
                ru = float(np.hypot(ru, self.reaction(r) - self.control.target_nN))
            res = max(ru / max(f_scale, self.force_floor), rp / volume) if (ru or rp) else 0.0
            return r, K, float(res), float(ru), float(rp)

        history: list[float] = []
        self._control_value = self.control_value
        try:
            r, K, res, ru, rp = evaluate(x)
        except _StepFailed:  # the extrapolation inverted an element: start from the last state
            if not predicted:
                raise
            x = self.x.copy()
            r, K, res, ru, rp = evaluate(x)
        for it in range(settings.max_iterations + 1):
            history.append(res)
            self.log.info(
                "  t=%.6g it=%d residual=%.3e (|r_u|=%.3e nN, |r_p|=%.3e um3)", t, it, res, ru, rp
            )
            if not np.isfinite(res):
                raise _StepFailed("residual is not finite", res)
            pending = bool(np.any(target[D] != x[D]))
            if res <= settings.rtol and not pending:
                return x, history
            if it >= 3 and res > settings.divergence * max(history[1], settings.rtol):
                raise _StepFailed("residual diverging", res)
            if it == settings.max_iterations:
                break
            dx = np.zeros_like(x)
            dx[D] = target[D] - x[D]
            low_rank = K.low_rank
            K = K()
            A, b, _, I = condense(K, -r, x=dx, D=D)
            try:
                lu = self._linear.factorize(A)
                if low_rank is None:
                    dx[I] = lu.solve(b)
                else:  # (K_II + G_I W_I^T) dx_I = b - G_I W_D^T dx_D, by Woodbury
                    G, W = low_rank
                    y = lu.solve(b - G[I] @ (W[D].T @ dx[D]))
                    Z = np.column_stack([lu.solve(G[I, j]) for j in range(G.shape[1])])
                    small = np.eye(G.shape[1]) + W[I].T @ Z
                    dx[I] = y - Z @ np.linalg.solve(small, W[I].T @ y)
            except RuntimeError as exc:
                raise _StepFailed(f"singular tangent ({exc})", res) from None
            if self.control is not None:  # (a line search scales dx, not this increment)
                self._control_value += self._control_increment(x, dx, r, K, lu, I)
            x, r, K, res, ru, rp = self._line_search(x, dx, res, pending, evaluate, settings)
        raise _StepFailed(f"no convergence in {settings.max_iterations} iterations", history[-1])

    def _step(self, t: float, dt: float, settings: NewtonSettings) -> tuple[NDArray, list[float]]:
        """Newton from the predictor; if that fails, once more from the last state at the same
        ``dt``. The predictor assumes the loading goes on at the last step's rate: at a hold or
        a reversal of a tool it starts the cell where the tool no longer goes, and halving the
        step does not bring it back (an AFM ramp-and-hold stopped at the hold's first step)."""
        try:
            return self._newton(t, dt, settings)
        except _StepFailed as fail:
            if not (
                settings.retry_from_last_state
                and settings.predictor
                and self._increment is not None
            ):
                raise
            self.log.info(
                "step to t=%.6g failed from the predictor (%s): from the last state", t, fail.cause
            )
            return self._newton(t, dt, replace(settings, predictor=False))

    def _control_increment(self, x, dx, r, K, lu, free) -> float:
        """Pressure increment of the bordered system (see :class:`ReactionControl`); ``dx``
        is updated in place with the response to it."""
        g = self.unit_load(self._control_load, x)
        g_full = np.zeros_like(x)
        g_full[: self.body.n_u] = g
        c = self._control_dofs
        s = np.asarray(K[c].sum(axis=0)).ravel()
        v = lu.solve(g_full[free])
        den = float(s[free] @ v) - float(g_full[c].sum())
        scale = float(np.abs(s[free]) @ np.abs(v)) + float(np.abs(g_full[c]).sum())
        if abs(den) <= 1e-12 * max(scale, 1e-300):
            return 0.0  # the load has no resultant on the controlled component: hold it
        reaction_new = self.reaction(r) + float(s @ dx)
        dp = (self.control.target_nN - reaction_new) / den
        dx[free] += dp * v
        return dp

    def _line_search(
        self,
        x: NDArray,
        dx: NDArray,
        res: float,
        pending: bool,
        evaluate: Callable[[NDArray], tuple],
        settings: NewtonSettings,
    ) -> tuple:
        """Backtracking on the residual: the full Newton step unless it raises the residual
        (or inverts an element); then halve it, at most ``settings.line_search`` times."""
        alpha = 1.0
        for attempt in range(settings.line_search + 1):
            last = attempt == settings.line_search
            x_try = x + alpha * dx
            try:
                r, K, res_try, ru, rp = evaluate(x_try)
            except _StepFailed:
                if last:
                    raise
                alpha /= 2.0
                continue
            if pending or res_try < res or last:
                if alpha < 1.0:
                    self.log.info("  line search: step scaled by %g", alpha)
                return x_try, r, K, res_try, ru, rp
            alpha /= 2.0
        raise AssertionError("unreachable")

    def _accept(self, x: NDArray, t: float, dt: float) -> None:
        self._increment = (x - self.x, dt)
        for k, region in enumerate(self.body.regions):
            if region.material.prony.g:
                kin, pq = self.region_kinematics(x, k)
                res = response(kin, pq, region.material, self.histories[k], dt)
                self.histories[k] = update_history(self.histories[k], region.material, res.S0, dt)
        u = self.body.displacement(x)
        for k, ops in enumerate(self._contact_ops):
            ev = self._contact_eval(k, x, t)
            self.contact_states[k] = ct.ContactState(ops.interpolate(u)[0], ev.slip, t)
        self.applied_masks = [self.pressure_mask(k, x) for k in range(len(self.pressures))]
        self.x, self.t = x, t
        self.control_value = self._control_value
        self._masks = [self._mask(k, x) for k in range(len(self.pressures))]

    # --- outputs -----------------------------------------------------------------------------

    def volume(self, x: NDArray) -> float:
        """Current volume ``int J dV`` [um^3] (axisymmetric) or area [um^2] (plane strain)."""
        total = 0.0
        for k, _region in enumerate(self.body.regions):
            kin, _ = self.region_kinematics(x, k)
            R, dx = self._quad[k]
            measure = 2.0 * np.pi * R if self.body.axisym else 1.0
            total += float(np.sum(kin.J * dx * measure))
        return total

    def frame(self) -> Frame:
        """The current state as an output frame."""
        forces, pressures = {}, {}
        for k, (c, fb) in enumerate(self.contacts):
            ev = self._contact_eval(k, self.x, self.t)
            forces[c.name] = -ct.resultant(ev, fb, self.body.axisym)
            pressures[c.name] = ev.pressure
        return Frame(self.t, self.x.copy(), self.volume(self.x), forces, pressures)

    def solve(
        self,
        times: Sequence[float],
        settings: NewtonSettings | None = None,
        on_frame: Callable[[Frame], None] | None = None,
        max_dt: float | None = None,
        admissible: Callable[[Frame], str] | None = None,
    ) -> SolveResult:
        """Advance through the output ``times`` [s] (increasing, > current time).

        Each output interval is one step (at most ``max_dt``); a failed step is halved and
        retried, never below ``dt_nominal / 2^max_cutbacks`` (so a stuck interval fails in
        bounded time); after three easy steps the step grows back. ``admissible(frame)``, if
        given, says what is wrong with a converged output frame ("" if nothing): a frame that
        is not a state of the body (a surface through itself) ends the solve with
        :class:`~oocyte_fe.errors.InadmissibleState`, the frames before it kept.
        """
        settings = settings or NewtonSettings()
        times = [float(t) for t in times]
        if any(b <= a for a, b in zip([self.t, *times], times, strict=False)):
            raise InputError("solve", "times", f"increasing output times after t = {self.t:g}")
        result = SolveResult()
        for i_out, t_out in enumerate(times):
            dt_nominal = min(t_out - self.t, max_dt or np.inf)
            dt, easy = dt_nominal, 0
            while self.t < t_out - 1e-12 * max(1.0, abs(t_out)):
                cutbacks = 0
                while True:
                    step = min(dt, t_out - self.t)
                    t_new = self.t + step
                    try:
                        x, hist = self._step(t_new, step, settings)
                        break
                    except _StepFailed as fail:
                        cutbacks += 1
                        self.log.warning(
                            "step to t=%.6g (dt=%.3g) failed: %s; cutback %d",
                            t_new,
                            step,
                            fail.cause,
                            cutbacks,
                        )
                        smallest = dt_nominal / 2.0**settings.max_cutbacks
                        if cutbacks > settings.max_cutbacks or step / 2.0 < smallest * 0.999:
                            raise SolverError(
                                f"no convergence at t = {t_new:.6g} s (dt = {step:.3g} s) after "
                                f"{settings.max_cutbacks} cutbacks: {fail.cause}, residual "
                                f"{fail.residual:.3e}",
                                result,
                            ) from None
                        dt = step / 2.0
                self._accept(x, t_new, step)
                result.steps.append(StepLog(t_new, step, tuple(hist), cutbacks))
                easy = easy + 1 if len(hist) <= 6 and cutbacks == 0 else 0
                if easy >= 3 and dt < dt_nominal:
                    dt, easy = min(2.0 * dt, dt_nominal), 0
            frame = self.frame()
            wrong = admissible(frame) if admissible is not None else ""
            if wrong:
                raise InadmissibleState(f"{wrong} at t = {frame.t:.6g} s", result)
            result.frames.append(frame)
            if on_frame is not None:
                on_frame(frame)
            report(i_out + 1, len(times), "FE steps")
        return result
