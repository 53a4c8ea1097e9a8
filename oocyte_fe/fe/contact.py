"""Penalty contact with Coulomb friction against a rigid moving obstacle.

Evaluated at the quadrature points of a named boundary, in the current position
``x = X + u - d(t)`` relative to the obstacle's rigid translation ``d(t)`` [um]::

    g = gap(x),  lambda = eps_N <-g>                       normal pressure [kPa]
    s_trial = s_n + ((u - u_n) - (d - d_n)) . tau           elastic tangential slip [um]
    q_trial = -eps_T s_trial
    q = q_trial                      if |q_trial| <= mu lambda   (stick)
    q = -mu lambda sign(s_trial)     otherwise                   (slip)
    traction on the body t = lambda n + q tau,   tau = (-n_2, n_1)

with the consistent (unsymmetric in slip) tangent, including the turning of ``n`` and ``tau``
with the contact point on a curved obstacle (``dn/dx = kappa tau tau^T``,
``dtau/dx = -kappa n tau^T``, :mod:`~oocyte_fe.fe.obstacles`): ``-lambda kappa`` on
``tau tau^T`` and ``q kappa`` on ``n tau^T``. Left out: the turning of ``tau`` in the slip
increment (a term proportional to the increment). With ``smooth_friction`` the return
mapping is replaced by its smooth counterpart

    q = -mu lambda tanh(z),   z = eps_T s_trial / (mu lambda)

(stick ``q ~ -eps_T s`` for ``|z| << 1``, sliding ``q -> -mu lambda sign(s)`` for
``|z| >> 1``, within 0.5 % of it beyond ``|z| = 3``, i.e. beyond an elastic slip of
``3 mu lambda / eps_T``; the stored slip keeps ``|z| <= 5``, so a point sliding in small steps
stays within 1e-4 of ``mu lambda`` and a converged state re-evaluates to the same traction
unless capped): the tangent is continuous, so Newton does not cycle when many points sit on
the stick/slip boundary at once (a body sliding as a whole).
Tractions are per reference area (times ``2 pi R`` in axisymmetry). Penalties [kPa/um] default
to ``penalty_factor * E_max / h`` (see :class:`Contact`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from skfem import FacetBasis

from oocyte_fe.fe.obstacles import Linearised, Obstacle

SLIP_CAP = 5.0  # stored |z| of the smooth friction law: 1 - tanh(5) = 9e-5


def _still(_t: float) -> tuple[float, float]:
    return (0.0, 0.0)


@dataclass(frozen=True)
class ContactLaw:
    """The penalty contact law, chosen in one place: the normal law and the friction law.

    ``penalty`` (normal) and ``tangential_penalty`` in kPa/um; ``friction`` the Coulomb
    coefficient ``mu`` (0.2 in the seed paper's Table 1). Normal law: ``lambda = eps <-g>``,
    or with ``smoothing_um = delta > 0`` the C1 law ``lambda = eps pen^2 / (2 delta)`` for a
    penetration ``pen < delta``, then ``eps (pen - delta/2)`` (a point that touches lightly
    no longer switches the tangent on and off between iterations: contact chatter at
    corners). Friction law: the exact Coulomb return mapping, or with ``smooth_friction`` its
    tanh-regularised counterpart (module docstring).
    """

    penalty: float
    friction: float = 0.0
    tangential_penalty: float | None = None
    smoothing_um: float = 0.0
    smooth_friction: bool = False

    @property
    def eps_t(self) -> float:
        return self.penalty if self.tangential_penalty is None else self.tangential_penalty

    def normal(self, pen: NDArray) -> tuple[NDArray, NDArray]:
        """Normal pressure ``lambda`` [kPa] and ``d lambda / d pen`` [kPa/um] at penetrations
        ``pen`` [um] (negative: open)."""
        closed = pen > 0.0
        delta = self.smoothing_um
        if delta > 0.0:  # C1 law: quadratic over the first delta of penetration, then linear
            lam = self.penalty * np.where(
                pen >= delta, pen - delta / 2.0, np.where(closed, pen**2 / (2.0 * delta), 0.0)
            )
            return lam, self.penalty * np.clip(pen / delta, 0.0, 1.0)
        return self.penalty * np.where(closed, pen, 0.0), np.where(closed, self.penalty, 0.0)

    def tangential(
        self, s_trial: NDArray, lam: NDArray, dlam: NDArray, closed: NDArray
    ) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Shear ``q`` [kPa], ``k_tt = -dq/ds``, ``k_tn = -dq/d pen`` and the slip to store,
        at trial slips ``s_trial`` [um] under the pressures ``lam``."""
        limit = self.friction * lam
        if self.smooth_friction:
            return _smooth_return(s_trial, limit, self.eps_t, self.friction, dlam)
        q_trial = -self.eps_t * s_trial
        stick = closed & (limit > 0.0) & (np.abs(q_trial) <= limit)  # mu = 0: never sticks
        slip = closed & ~stick
        sgn = np.sign(s_trial)
        q = np.where(stick, q_trial, np.where(slip, -limit * sgn, 0.0))
        s_new = np.where(stick, s_trial, np.where(slip, limit * sgn / self.eps_t, 0.0))
        k_tt = np.where(stick, self.eps_t, 0.0)
        k_tn = np.where(slip, -self.friction * dlam * sgn, 0.0)
        return q, k_tt, k_tn, s_new


@dataclass(frozen=True)
class Contact:
    """Contact of the boundary ``boundary`` with a rigid ``obstacle`` moving by ``motion(t)``,
    under the contact ``law``, evaluated at the Gauss points of order ``quadrature_order`` on
    each facet (default: the body's order). Penalty contact acts only at those points: a sharp
    obstacle corner that presses between two of them is not resisted there, and the facet folds
    round it (the wedge pipette's mouth corners, docs/fe.md, Limits)."""

    boundary: str
    obstacle: Obstacle
    law: ContactLaw
    motion: Callable[[float], tuple[float, float]] = _still
    name: str = "contact"
    quadrature_order: int | None = None


@dataclass
class ContactState:
    """Converged state at the boundary's quadrature points."""

    u: NDArray  # (2, nf, nq) displacement at the last converged step
    slip: NDArray  # (nf, nq) elastic tangential slip s_n
    t: float


@dataclass(frozen=True)
class ContactEval:
    """Contact quantities at the quadrature points for the current iterate."""

    gap: NDArray
    normal: NDArray
    tangent: NDArray
    pressure: NDArray  # lambda [kPa]
    shear: NDArray  # q [kPa]
    slip: NDArray  # s (elastic tangential slip), to store when converged
    # -d traction / du = k_nn n n^T + k_tt tau tau^T + k_tn tau n^T + k_nt n tau^T  [kPa/um]
    k_nn: NDArray
    k_tt: NDArray  # stick stiffness minus lambda kappa (the turning of n)
    k_tn: NDArray
    k_nt: NDArray  # q kappa (the turning of tau)

    @property
    def traction(self) -> NDArray:
        return self.pressure * self.normal + self.shear * self.tangent


def evaluate(
    contact: Contact, X: NDArray, u_q: NDArray, state: ContactState, t: float
) -> ContactEval:
    """Gap, tractions and tangent coefficients at the quadrature points (``u_q`` (2, nf, nq))."""
    d = np.asarray(contact.motion(t), dtype=float)[:, None, None]
    d_n = np.asarray(contact.motion(state.t), dtype=float)[:, None, None]
    if isinstance(contact.obstacle, Linearised):  # small strain: the lateral displacement out
        a = np.asarray(contact.obstacle.axis, dtype=float)[:, None, None]
        x = X + a * np.einsum("i...,i...->...", a, u_q) - d
    else:
        x = X + u_q - d
    gap, n, kappa = contact.obstacle.distance_curvature(x)
    tau = np.stack([-n[1], n[0]])
    pen = -gap
    lam, dlam = contact.law.normal(pen)
    ds = np.einsum("i...,i...->...", (u_q - state.u) - (d - d_n), tau)
    q, k_tt, k_tn, s_new = contact.law.tangential(state.slip + ds, lam, dlam, pen > 0.0)
    return ContactEval(
        gap=gap,
        normal=n,
        tangent=tau,
        pressure=lam,
        shear=q,
        slip=s_new,
        k_nn=dlam,
        k_tt=k_tt - lam * kappa,
        k_tn=k_tn,
        k_nt=q * kappa,
    )


def _smooth_return(
    s_trial: NDArray, limit: NDArray, eps_t: float, mu: float, dlam: NDArray
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """``q = -limit tanh(z)``, ``z = eps_t s / limit`` (``limit = mu lambda``), its derivatives
    ``k_tt = -dq/ds = eps_t (1 - tanh^2 z)`` and ``k_tn = -mu (tanh z - z (1 - tanh^2 z)) dlam``,
    and the slip to store, ``z`` capped at ``SLIP_CAP`` (so that a point sliding in small steps
    keeps ``q`` within ``1 - tanh(SLIP_CAP)`` of ``mu lambda``, and a reversal unwinds a
    bounded slip); zero where the contact is open."""
    on = limit > 0.0
    z = np.divide(eps_t * s_trial, limit, out=np.zeros_like(s_trial), where=on)
    th = np.tanh(z)
    dth = 1.0 - th**2
    q = np.where(on, -limit * th, 0.0)
    k_tt = np.where(on, eps_t * dth, 0.0)
    k_tn = np.where(on, -mu * (th - z * dth) * dlam, 0.0)
    s_new = np.where(on, np.clip(z, -SLIP_CAP, SLIP_CAP) * limit / eps_t, 0.0)
    return q, k_tt, k_tn, s_new


def resultant(ev: ContactEval, fb: FacetBasis, axisym: float) -> NDArray:
    """Total force on the body [nN] (axisymmetric: the axial component is the net force)."""
    X = np.asarray(fb.global_coordinates())
    measure = np.where(axisym > 0, 2.0 * np.pi * X[0], 1.0)
    return np.einsum("ifq,fq->i", ev.traction, fb.dx * measure)
