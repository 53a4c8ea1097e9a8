"""Deformation gradient of a 2D (plane-strain or axisymmetric) body embedded in 3D.

Coordinates ``(X1, X2)`` are ``(x, y)`` in plane strain and ``(R, Z)`` in axisymmetry (``R`` the
distance from the axis, ``X1 >= 0``). Only five components of ``F`` (3x3) are non-zero::

    F = [[F11, F12, 0], [F21, F22, 0], [0, 0, F33]],
    F33 = 1 (plane strain) or 1 + u_R / R (axisymmetric hoop stretch r / R).

Tensors are carried as their five *active* components ``(11, 12, 21, 22, 33)``; a fourth-order
tangent ``dP/dF`` is then a 5x5 matrix. Arrays have trailing quadrature axes ``(..., nel, nqp)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

ACTIVE_I = np.array([0, 0, 1, 1, 2])
ACTIVE_J = np.array([0, 1, 0, 1, 2])
IDENTITY5 = np.array([1.0, 0.0, 0.0, 1.0, 1.0])


def grad5(value: NDArray, grad: NDArray, radius: NDArray | None) -> NDArray:
    """Active components of ``Grad u`` (3x3) from a 2-vector field and its 2x2 gradient.

    ``radius`` is the reference radius ``R`` at the quadrature points (axisymmetric), or
    ``None`` (plane strain): the 33 component is then ``u_R / R`` or zero.
    """
    hoop = value[0] / radius if radius is not None else np.zeros_like(value[0])
    return np.stack([grad[0, 0], grad[0, 1], grad[1, 0], grad[1, 1], hoop])


def full3(t5: NDArray) -> NDArray:
    """The 3x3 tensor (..., nel, nqp) with the five active components ``t5`` filled in."""
    out = np.zeros((3, 3) + t5.shape[1:])
    out[ACTIVE_I, ACTIVE_J] = t5
    return out


@dataclass(frozen=True)
class Kinematics:
    """``F``, its inverse, ``J = det F`` and ``I1 = F : F`` at quadrature points."""

    F: NDArray  # (3, 3, nel, nqp)
    Finv: NDArray  # (3, 3, nel, nqp)
    J: NDArray  # (nel, nqp)
    I1: NDArray  # (nel, nqp)
    small: bool = False  # small-strain kinematics (see from_grad5)

    @classmethod
    def from_grad5(cls, gu5: NDArray, small: bool = False) -> Kinematics:
        """The kinematics of ``Grad u`` (active components). With ``small`` the linearised
        ones of small-strain elasticity: ``F = I + Grad u`` is kept (the strain is read from
        it), but ``F^-1 = I`` and ``J = 1 + tr(Grad u)``, so that the pressure works on the
        linearised volume change and no geometric stiffness arises."""
        F5 = IDENTITY5[:, None, None] + gu5
        F = full3(F5)
        if small:
            eye = np.broadcast_to(np.eye(3)[:, :, None, None], F.shape).copy()
            J = 1.0 + gu5[0] + gu5[3] + gu5[4]
            return cls(F=F, Finv=eye, J=J, I1=np.einsum("ij...,ij...->...", F, F), small=True)
        det2 = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
        Finv = np.zeros_like(F)
        # a collapsed element gives inf/nan here; the solver detects J <= 0 or non-finite J
        with np.errstate(divide="ignore", invalid="ignore"):
            Finv[0, 0] = F[1, 1] / det2
            Finv[1, 1] = F[0, 0] / det2
            Finv[0, 1] = -F[0, 1] / det2
            Finv[1, 0] = -F[1, 0] / det2
            Finv[2, 2] = 1.0 / F[2, 2]
        return cls(F=F, Finv=Finv, J=det2 * F[2, 2], I1=np.einsum("ij...,ij...->...", F, F))

    @property
    def FinvT(self) -> NDArray:
        return np.swapaxes(self.Finv, 0, 1)


def active(t33: NDArray) -> NDArray:
    """The five active components of a 3x3 tensor field."""
    return t33[ACTIVE_I, ACTIVE_J]


def outer5(a: NDArray, b: NDArray) -> NDArray:
    """``M[p, q] = a[i, J] b[k, L]`` with ``p = (i, J)``, ``q = (k, L)`` active (5x5)."""
    return active(a)[:, None] * active(b)[None, :]


def cross5(x: NDArray) -> NDArray:
    """``M[p, q] = x[L, i] x[J, k]`` with ``p = (i, J)``, ``q = (k, L)`` active (5x5).

    With ``x = F^-1`` this is the derivative pattern of ``F^-T``: ``dFinv[J,i]/dF[k,L]``.
    """
    return x[ACTIVE_J[None, :], ACTIVE_I[:, None]] * x[ACTIVE_J[:, None], ACTIVE_I[None, :]]
