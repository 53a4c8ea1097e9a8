"""Vectorised assembly of the displacement blocks: all element matrices in one ``einsum``.

scikit-fem's ``BilinearForm`` calls the form once per pair of basis functions (144 pairs for a
vector P2 triangle), which made the tangent stiffness the largest cost of a Newton iteration.
In the total-Lagrangian setting the reference gradients of the basis functions never change,
so they are stacked once per region as ``B[i, a, e, q]`` (basis function ``i``, active
component ``a`` of ``Grad v`` (see :mod:`~oocyte_fe.fe.kinematics`), element ``e``, quadrature
point ``q``) together with ``dV = w_q |det J| (2 pi R)``; then (same forms as
:mod:`~oocyte_fe.fe.forms`)::

    f_i   = sum_eq B[i,a] P5[a] dV                      (internal force)
    K_ij  = sum_eq B[i,a] A5[a,b] B[j,b] dV             (stiffness_uu)
    G_ik  = sum_eq B[i,a] (J F^-T)5[a] N_k dV           (coupling_up, N_k the P1 pressure basis)

are one ``einsum`` each and a scatter into global dofs; the stiffness, the costliest, is a
batched matrix product ``Bq^T (A5 dV) Bq`` per element and quadrature point (``Bq`` =
``B[:, :, e, q]``, kept in that layout), 3.4 times faster than the two ``einsum`` it replaced.
Results equal scikit-fem's assembly of the same forms to rounding (tested).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from skfem import Basis

from oocyte_fe.fe.kinematics import grad5


@dataclass(frozen=True)
class RegionOperators:
    """Stacked reference gradients of a vector basis (and the values of its pressure basis)."""

    B: NDArray  # (nb, 5, nel, nq)
    dV: NDArray  # (nel, nq)
    dofs: NDArray  # (nb, nel) global displacement dofs
    n_u: int
    p_values: NDArray  # (np, nel, nq) pressure basis values
    p_dofs: NDArray  # (np, nel) local pressure dofs
    Bq: NDArray  # (nel, nq, nb, 5): B laid out for batched matrix products

    @classmethod
    def of(cls, ubasis: Basis, pbasis: Basis, axisym: bool) -> RegionOperators:
        radius = np.asarray(ubasis.global_coordinates())[0] if axisym else None
        B = np.stack(
            [grad5(np.asarray(phi[0]), phi[0].grad, radius) for phi in ubasis.basis]
        )  # (nb, 5, nel, nq)
        dV = ubasis.dx * (2.0 * np.pi * radius if axisym else 1.0)
        p_values = np.stack([np.asarray(phi[0]) for phi in pbasis.basis])
        Bq = np.ascontiguousarray(B.transpose(2, 3, 0, 1))
        return cls(B, dV, ubasis.element_dofs, ubasis.N, p_values, pbasis.element_dofs, Bq)

    def internal_force(self, P5: NDArray) -> NDArray:
        """``f_i = int P : Grad v_i dV`` over the region, length ``n_u`` [nN]."""
        fe = np.einsum("iaeq,aeq->ie", self.B, P5 * self.dV)
        return np.bincount(self.dofs.ravel(), fe.ravel(), minlength=self.n_u)

    def stiffness(self, A5: NDArray) -> sp.coo_matrix:
        """``K_ij = int Grad v_i : A : Grad v_j dV`` (``n_u`` x ``n_u``) [nN/um]."""
        weighted = (A5 * self.dV).transpose(2, 3, 0, 1)  # (nel, nq, 5, 5)
        Ke = (self.Bq @ weighted @ self.Bq.transpose(0, 1, 3, 2)).sum(axis=1)  # (nel, nb, nb)
        nb, nel = self.dofs.shape
        rows = np.broadcast_to(self.dofs.T[:, :, None], (nel, nb, nb))
        cols = np.broadcast_to(self.dofs.T[:, None, :], (nel, nb, nb))
        return sp.coo_matrix((Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.n_u, self.n_u))

    def coupling(self, JFinvT5: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """``G_ik = int (J F^-T : Grad v_i) N_k dV``: (u dof rows, local p dof cols, values)."""
        Ge = np.einsum("iaeq,aeq,keq->ike", self.B, JFinvT5 * self.dV, self.p_values)
        nb, n_p, nel = Ge.shape
        rows = np.broadcast_to(self.dofs[:, None, :], (nb, n_p, nel))
        cols = np.broadcast_to(self.p_dofs[None, :, :], (nb, n_p, nel))
        return rows.ravel(), cols.ravel(), Ge.ravel()


def _cof_n(G: NDArray, N: NDArray) -> NDArray:
    """``cof(G) N`` in the section plane, ``cof(G) = [[G22, -G21], [-G12, G11]]``."""
    return np.stack([G[1, 1] * N[0] - G[1, 0] * N[1], -G[0, 1] * N[0] + G[0, 0] * N[1]])


@dataclass(frozen=True)
class FacetOperators:
    """Stacked basis values and gradients of a vector basis on a boundary's facets.

    Assembles (per reference arc length ``dS``, ``a = 2 pi r`` current or ``A = 2 pi R``
    reference radius factor in axisymmetry, 1 in plane strain)::

        follower pressure   f_i = -p a cof(F) N . v_i dS
                            K_ij = p (da_j cof(F) N + a cof(Grad v_j) N) . v_i dS
        contact traction    f_i = t . v_i A dS
                            K_ij = (k_nn v_i.n v_j.n + k_tt v_i.t v_j.t + k_tn v_i.t v_j.n
                                    + k_nt v_i.n v_j.t) A dS

    (the forms of :mod:`~oocyte_fe.fe.loads` and :mod:`~oocyte_fe.fe.contact`).
    """

    phi: NDArray  # (nb, 2, nf, nq)
    dphi: NDArray  # (nb, 2, 2, nf, nq)
    X: NDArray  # (2, nf, nq) reference coordinates
    N: NDArray  # (2, nf, nq) reference outward normal
    dS: NDArray  # (nf, nq)
    dofs: NDArray  # (nb, nf)
    n_u: int

    @classmethod
    def of(cls, fb) -> FacetOperators:
        phi = np.stack([np.asarray(b[0]) for b in fb.basis])
        dphi = np.stack([b[0].grad for b in fb.basis])
        X = np.asarray(fb.global_coordinates())
        return cls(phi, dphi, X, np.asarray(fb.normals), fb.dx, fb.element_dofs, fb.N)

    def interpolate(self, u: NDArray) -> tuple[NDArray, NDArray]:
        """Value (2, nf, nq) and gradient (2, 2, nf, nq) of the field ``u`` [um]."""
        ue = u[self.dofs]
        return (
            np.einsum("icfq,if->cfq", self.phi, ue),
            np.einsum("icdfq,if->cdfq", self.dphi, ue),
        )

    def _vector(self, T: NDArray) -> NDArray:
        fe = np.einsum("icfq,cfq->if", self.phi, T * self.dS)
        return np.bincount(self.dofs.ravel(), fe.ravel(), minlength=self.n_u)

    def _matrix(self, Ke: NDArray) -> sp.coo_matrix:
        nb, _, nf = Ke.shape
        rows = np.broadcast_to(self.dofs[:, None, :], (nb, nb, nf))
        cols = np.broadcast_to(self.dofs[None, :, :], (nb, nb, nf))
        return sp.coo_matrix((Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.n_u, self.n_u))

    def _pressure_terms(self, u: NDArray, axisym: bool) -> tuple[NDArray, NDArray]:
        value, grad = self.interpolate(u)
        cofN = _cof_n(np.eye(2)[:, :, None, None] + grad, self.N)
        a = 2.0 * np.pi * (self.X[0] + value[0]) if axisym else np.ones_like(self.dS)
        return cofN, a

    def pressure_force(self, u: NDArray, pn: NDArray, axisym: bool) -> NDArray:
        """External force [nN] of the follower pressure ``pn`` (nf, nq) [kPa] at ``u``."""
        cofN, a = self._pressure_terms(u, axisym)
        return self._vector(-pn * a * cofN)

    def pressure(
        self, u: NDArray, pn: NDArray, axisym: bool, grad_pn: NDArray | None = None
    ) -> tuple[NDArray, sp.coo_matrix]:
        """External force of the follower pressure ``pn`` (nf, nq) [kPa] and ``-d f / d u``;
        ``grad_pn`` (2, nf, nq) [kPa/um]: the gradient of a pressure that depends on the
        current position, whose term ``(grad p . v_j) a cof(F) N . v_i dS`` joins ``K``."""
        cofN, a = self._pressure_terms(u, axisym)
        f = self._vector(-pn * a * cofN)
        # T_j = da_j cof(F) N + a cof(Grad v_j) N  (nb, 2, nf, nq)
        T = a * _cof_n(np.moveaxis(self.dphi, 0, 2), self.N)  # (2, nb, nf, nq)
        T = np.moveaxis(T, 1, 0)
        if axisym:
            T = T + 2.0 * np.pi * self.phi[:, 0][:, None] * cofN[None]
        Ke = np.einsum("icfq,jcfq->ijf", self.phi, T * (pn * self.dS))
        if grad_pn is not None:
            vn = np.einsum("icfq,cfq->ifq", self.phi, cofN * (a * self.dS))
            vg = np.einsum("icfq,cfq->ifq", self.phi, grad_pn)
            Ke = Ke + np.einsum("ifq,jfq->ijf", vn, vg)
        return f, self._matrix(Ke)

    def dead_traction_force(self, T: NDArray, axisym: bool) -> NDArray:
        """External force [nN] of the nominal traction ``T`` (2, nf, nq) [kPa], per reference
        area (a dead load: no stiffness)."""
        A = 2.0 * np.pi * self.X[0] if axisym else np.ones_like(self.dS)
        return self._vector(T * A)

    def contact(self, ev, axisym: bool) -> tuple[NDArray, sp.coo_matrix]:
        """Contact tractions ``ev`` (:class:`~oocyte_fe.fe.contact.ContactEval`) as an external
        force vector and its stiffness ``-d f / d u``."""
        A = 2.0 * np.pi * self.X[0] if axisym else np.ones_like(self.dS)
        f = self._vector(ev.traction * A)
        vn = np.einsum("icfq,cfq->ifq", self.phi, ev.normal)
        vt = np.einsum("icfq,cfq->ifq", self.phi, ev.tangent)
        w = A * self.dS
        Ke = (
            np.einsum("ifq,jfq->ijf", vn, vn * (ev.k_nn * w))
            + np.einsum("ifq,jfq->ijf", vt, vt * (ev.k_tt * w))
            + np.einsum("ifq,jfq->ijf", vt, vn * (ev.k_tn * w))
            + np.einsum("ifq,jfq->ijf", vn, vt * (ev.k_nt * w))
        )
        return f, self._matrix(Ke)
