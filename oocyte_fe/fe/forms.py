"""Weak forms of the mixed u-p total-Lagrangian problem (scikit-fem forms).

With ``dV = 2 pi R dA`` (axisymmetric, ``axisym = 1``) or ``dA`` per unit thickness (plane
strain, ``axisym = 0``), ``du`` the trial and ``v`` the test displacement, ``q`` the test pressure::

    r_u = int P : Grad v dV                 K_uu = int Grad v : A : Grad du dV
    r_p = int q (J - 1 - p / kappa) dV      K_up = int (J F^-T : Grad v) dp dV
                                            K_pp = -int q dp / kappa dV

Quadrature-point fields (``P5``, ``A5``, ``JFinvT5``, ``Jm1``) come in through ``w``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from skfem import BilinearForm, LinearForm

from oocyte_fe.fe.kinematics import grad5


def volume_measure(w) -> NDArray:
    """``2 pi R`` (axisymmetric) or 1 (plane strain) at the quadrature points."""
    return np.where(w.axisym > 0, 2.0 * np.pi * w.x[0], 1.0)


def _grad5(v, w) -> NDArray:
    return grad5(v, v.grad, w.x[0] if w.axisym > 0 else None)


@LinearForm
def internal_force(v, w):
    return np.einsum("a...,a...->...", w.P5, _grad5(v, w)) * volume_measure(w)


@BilinearForm
def stiffness_uu(du, v, w):
    return np.einsum("a...,ab...,b...->...", _grad5(v, w), w.A5, _grad5(du, w)) * volume_measure(w)


@BilinearForm
def coupling_up(dp, v, w):
    """Rows: displacement test ``v``; columns: pressure trial ``dp``."""
    return np.einsum("a...,a...->...", w.JFinvT5, _grad5(v, w)) * dp * volume_measure(w)


@LinearForm
def volume_constraint(q, w):
    return (w.Jm1 - w.p * w.inv_kappa) * q * volume_measure(w)


@BilinearForm
def compliance_pp(dp, q, w):
    return -w.inv_kappa * dp * q * volume_measure(w)


@LinearForm
def measure(v, w):
    """``int v dV``: with ``v = 1`` the (axisymmetric) volume or area."""
    return v * volume_measure(w)
