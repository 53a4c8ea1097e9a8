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

are one ``einsum`` each and a scatter into global dofs. Results equal scikit-fem's assembly
of the same forms to rounding (tested).
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

    @classmethod
    def of(cls, ubasis: Basis, pbasis: Basis, axisym: bool) -> RegionOperators:
        radius = np.asarray(ubasis.global_coordinates())[0] if axisym else None
        B = np.stack(
            [grad5(np.asarray(phi[0]), phi[0].grad, radius) for phi in ubasis.basis]
        )  # (nb, 5, nel, nq)
        dV = ubasis.dx * (2.0 * np.pi * radius if axisym else 1.0)
        p_values = np.stack([np.asarray(phi[0]) for phi in pbasis.basis])
        return cls(B, dV, ubasis.element_dofs, ubasis.N, p_values, pbasis.element_dofs)

    def internal_force(self, P5: NDArray) -> NDArray:
        """``f_i = int P : Grad v_i dV`` over the region, length ``n_u`` [nN]."""
        fe = np.einsum("iaeq,aeq->ie", self.B, P5 * self.dV)
        return np.bincount(self.dofs.ravel(), fe.ravel(), minlength=self.n_u)

    def stiffness(self, A5: NDArray) -> sp.coo_matrix:
        """``K_ij = int Grad v_i : A : Grad v_j dV`` (``n_u`` x ``n_u``) [nN/um]."""
        C = np.einsum("abeq,jbeq->ajeq", A5 * self.dV, self.B)
        Ke = np.einsum("iaeq,ajeq->ije", self.B, C)
        nb = self.dofs.shape[0]
        rows = np.broadcast_to(self.dofs[:, None, :], (nb, nb, self.dofs.shape[1]))
        cols = np.broadcast_to(self.dofs[None, :, :], (nb, nb, self.dofs.shape[1]))
        return sp.coo_matrix((Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.n_u, self.n_u))

    def coupling(self, JFinvT5: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """``G_ik = int (J F^-T : Grad v_i) N_k dV``: (u dof rows, local p dof cols, values)."""
        Ge = np.einsum("iaeq,aeq,keq->ike", self.B, JFinvT5 * self.dV, self.p_values)
        nb, n_p, nel = Ge.shape
        rows = np.broadcast_to(self.dofs[:, None, :], (nb, n_p, nel))
        cols = np.broadcast_to(self.p_dofs[None, :, :], (nb, n_p, nel))
        return rows.ravel(), cols.ravel(), Ge.ravel()
