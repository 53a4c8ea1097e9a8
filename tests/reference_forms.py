"""scikit-fem weak forms of the facet blocks: the reference for the vectorised assembly.

Follower pressure stiffness ``-d f / d u = p (da cof(F) N + a cof(dF) N) . v`` and the contact
traction and stiffness of :mod:`oocyte_fe.fe.contact`, written as plain scikit-fem forms.
"""

from __future__ import annotations

import numpy as np
from skfem import BilinearForm, LinearForm


def _cof_n(Fg, N):
    return np.stack([Fg[1, 1] * N[0] - Fg[1, 0] * N[1], -Fg[0, 1] * N[0] + Fg[0, 0] * N[1]])


def _current_radius(w):
    return np.where(w.axisym > 0, 2.0 * np.pi * (w.x[0] + w.u[0]), 1.0)


def _reference_radius(w):
    return np.where(w.axisym > 0, 2.0 * np.pi * w.x[0], 1.0)


@LinearForm
def pressure_force(v, w):
    Fg = np.eye(2)[:, :, None, None] + w.u.grad
    return -w.pn * _current_radius(w) * np.einsum("i...,i...->...", _cof_n(Fg, w.n), v)


@BilinearForm
def pressure_stiffness(du, v, w):
    Fg = np.eye(2)[:, :, None, None] + w.u.grad
    da = np.where(w.axisym > 0, 2.0 * np.pi * du[0], 0.0)
    term = da * _cof_n(Fg, w.n) + _current_radius(w) * _cof_n(du.grad, w.n)
    return w.pn * np.einsum("i...,i...->...", term, v)


@LinearForm
def contact_traction(v, w):
    return np.einsum("i...,i...->...", w.tr, v) * _reference_radius(w)


@BilinearForm
def contact_stiffness(du, v, w):
    vn = np.einsum("i...,i...->...", w.n_c, v)
    vt = np.einsum("i...,i...->...", w.t_c, v)
    dn = np.einsum("i...,i...->...", w.n_c, du)
    dt = np.einsum("i...,i...->...", w.t_c, du)
    return (
        w.k_nn * vn * dn + w.k_tt * vt * dt + w.k_tn * vt * dn + w.k_nt * vn * dt
    ) * _reference_radius(w)
