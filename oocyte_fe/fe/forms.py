"""Weak forms of the mixed u-p total-Lagrangian problem (scikit-fem forms).

With ``dV = 2 pi R dA`` (axisymmetric, ``axisym = 1``) or ``dA`` per unit thickness (plane
strain, ``axisym = 0``), ``du`` the trial and ``v`` the test displacement, ``q`` the test pressure::

    r_u = int P : Grad v dV                 K_uu = int Grad v : A : Grad du dV
    r_p = int q (J - 1 - p / kappa) dV      K_up = int (J F^-T : Grad v) dp dV
                                            K_pp = -int q dp / kappa dV

The displacement blocks ``r_u``, ``K_uu``, ``K_up`` are assembled by
:mod:`~oocyte_fe.fe.vectorized` (all element matrices in one ``einsum``); the pressure blocks
below are scikit-fem forms, their quadrature-point fields (``Jm1``, ``p``, ``inv_kappa``) come
in through ``w``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from skfem import BilinearForm, LinearForm


def volume_measure(w) -> NDArray:
    """``2 pi R`` (axisymmetric) or 1 (plane strain) at the quadrature points."""
    return np.where(w.axisym > 0, 2.0 * np.pi * w.x[0], 1.0)


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
