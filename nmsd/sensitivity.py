"""Forward (direct) sensitivities of the backward-Euler press: exact df/dp of the force output.

Each converged step n of :mod:`nmsd.integrator` solves (um, nN, s)

    R(x_n, x_{n-1}, v_{n-1}; p) = M (x_n - x_{n-1} - dt v_{n-1})/dt^2 + F^d + F^k - F^c = 0,
    v_n = (x_n - x_{n-1})/dt.

Differentiating with respect to a constant p (``S_n = dx_n/dp``, ``V_n = dv_n/dp``):

    K_n S_n = -(dR/dp + dR/dx_{n-1} S_{n-1} + dR/dv_{n-1} V_{n-1}),
    V_n = (S_n - S_{n-1})/dt,    S_0 = V_0 = 0,

with ``K_n = dR/dx_n`` the exact tangent at the converged x_n (refactored there: the chord
Newton of the stepper may end on an older LU). Held DOFs have S = 0. The terms:

- ``dR/dp``. R is linear in k1, k2, d0, d1 (the continuation above dl_c too, since
  ``A = k1 dl_c + k2 dl_c^3`` and ``B = k1 + 3 k2 dl_c^2`` are), so each column is the
  residual with that constant 1 and the others 0, without mass and contact. Link e with
  strain ``e = l/l0 - 1``, unit vector n (second node to first) and ZP factor z:
  ``dR_a/dk1 = z e n``; ``dR_a/dk2 = z e^3 n`` (|e| <= dl_c) or
  ``z sgn(e) (dl_c^3 + 3 dl_c^2 (|e| - dl_c)) n``; ``dR_b = -dR_a``. Nodal damping:
  ``dR_i/dd0 = v_i``, ``dR_i/dd1 = |u_i| v_i``; link dashpots:
  ``dR_a/dd0 = (n.w) n``, ``dR_a/dd1 = |l - l0| (n.w) n`` with ``w`` the rate of the link
  vector. Area term (kappa = area_stiffness k1/h): ``dR/dk1 += (area_stiffness/h) (A/A0 - 1)
  dA/dx``. The critical strain enters only above it: ``dR_a/d dl_c = z sgn(e) 6 k2 dl_c
  (|e| - dl_c) n`` (A' = B cancels the -B of the shifted ramp).
- History. R is affine in (x_{n-1}, v_{n-1}): inertia gives ``-M/dt^2`` and ``-M/dt``;
  nodal damping ``-(d0 + d1 |u_i|)/dt``; a link dashpot ``f^d = c n.(d - d_old)/dt`` gives
  ``dR_a/dd_old = -(c/dt) n n^T`` (d = x_a - x_b, the damping coefficient c is evaluated at
  x_n).
- Pipette. The contact force of node i depends on ``x_i - m`` (m the mouth); its tangent is
  ``C_i = kappa n_f n_f^T`` on the active face (sharp wedge). Moving the pipette start back
  by ``g`` um along its direction a (``gap_um`` of :meth:`nmsd.press.PressSetup.with_gap`)
  gives ``dR_i/dg = C_i a``. The force output ``f_n = a . sum_i F^c_i`` has

      df_n/dp = -a . sum_i C_i (S_i + [p = gap] a).

Step halvings: every substep is a backward-Euler step of its own dt, and the sensitivities
are carried through it in the same way. Symmetric branch (:mod:`nmsd.symmetry`): the
constants keep the mirror symmetry, so S is symmetric too and is solved like the step, on
the half lattice: ``(K P)_kept S_h = rhs_kept``, ``S = P S_h``.

Cost per step: one extra assembly with tangent, one band LU and one ``dgbtrs`` with six
right-hand sides (a press costs about 1.5 presses).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy.linalg.lapack import dgbtrf, dgbtrs

from nmsd.assembly import cell_area, link_geometry
from oocyte_fe.errors import InputError

NAMES = ("k1", "k2", "d0", "d1", "dl_c", "gap_um")
"""Constants whose force sensitivities a press returns, in this column order."""


@njit(cache=True)
def parameter_columns(
    x,
    x_old,
    nodes,
    edges,
    rest_length,
    link_factor,
    k2,
    dl_c,
    link_damping,
    dt,
    cells,
    rest_area,
    area_per_k1,
    held_dof,
    out,
):
    """Fill ``out`` (2n, 5) with dR/dp for p = k1, k2, d0, d1, dl_c at the step (x_old -> x).

    ``area_per_k1`` is kappa/k1 = area_stiffness/h (nN/um per nN), 0 without the area term.
    Held DOFs get zero rows.
    """
    n = nodes.shape[0]
    inv_dt = 1.0 / dt
    out[:, :] = 0.0
    if not link_damping:
        for i in range(n):
            vx = (x[i, 0] - x_old[i, 0]) * inv_dt
            vy = (x[i, 1] - x_old[i, 1]) * inv_dt
            ux = x[i, 0] - nodes[i, 0]
            uy = x[i, 1] - nodes[i, 1]
            un = np.sqrt(ux * ux + uy * uy)
            out[2 * i, 2] += vx
            out[2 * i + 1, 2] += vy
            out[2 * i, 3] += un * vx
            out[2 * i + 1, 3] += un * vy
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        l0 = rest_length[e]
        dx, dy, length, nx, ny, strain = link_geometry(x, a, b, l0)
        z = link_factor[e]
        g1 = z * strain
        if abs(strain) <= dl_c:
            g2 = z * strain**3
            gc = 0.0
        else:
            sg = np.sign(strain)
            g2 = z * sg * (dl_c**3 + 3.0 * dl_c**2 * (abs(strain) - dl_c))
            gc = z * sg * 6.0 * k2 * dl_c * (abs(strain) - dl_c)
        cols = (0, 1, 4)
        vals = (g1, g2, gc)
        for k in range(3):
            c = cols[k]
            out[2 * a, c] += vals[k] * nx
            out[2 * a + 1, c] += vals[k] * ny
            out[2 * b, c] -= vals[k] * nx
            out[2 * b + 1, c] -= vals[k] * ny
        if link_damping:
            wx = (dx - (x_old[a, 0] - x_old[b, 0])) * inv_dt
            wy = (dy - (x_old[a, 1] - x_old[b, 1])) * inv_dt
            rate = nx * wx + ny * wy
            stretch = abs(length - l0)
            out[2 * a, 2] += rate * nx
            out[2 * a + 1, 2] += rate * ny
            out[2 * b, 2] -= rate * nx
            out[2 * b + 1, 2] -= rate * ny
            out[2 * a, 3] += stretch * rate * nx
            out[2 * a + 1, 3] += stretch * rate * ny
            out[2 * b, 3] -= stretch * rate * nx
            out[2 * b + 1, 3] -= stretch * rate * ny
    if area_per_k1 > 0.0:
        gx = np.empty(4)
        gy = np.empty(4)
        idx = np.empty(4, dtype=np.int64)
        for c in range(cells.shape[0]):
            m, area = cell_area(x, cells, c, idx, gx, gy)
            p = area_per_k1 * (area / rest_area[c] - 1.0)
            for k in range(m):
                out[2 * idx[k], 0] += p * gx[k]
                out[2 * idx[k] + 1, 0] += p * gy[k]
    for k in range(2 * n):
        if held_dof[k]:
            out[k, :] = 0.0


@njit(cache=True)
def history_term(
    x, nodes, edges, rest_length, d0, d1, link_damping, mass, dt, s_old, sv_old, held_dof, out
):
    """Fill ``out`` (2n, P) with ``dR/dx_old S_old + dR/dv_old V_old`` (S, V as (2n, P)).

    Inertia ``-M (S_old/dt + V_old)/dt``; nodal damping ``-(d0 + d1 |u|) S_old/dt``; link
    dashpots ``-(c/dt) n n^T (S_old_a - S_old_b)`` on node a and its negative on b, with
    ``c = d0 + d1 |l - l0|`` at x. Held DOFs get zero rows.
    """
    n = nodes.shape[0]
    n_p = s_old.shape[1]
    inv_dt = 1.0 / dt
    for k in range(2 * n):
        for q in range(n_p):
            out[k, q] = -mass * inv_dt * (s_old[k, q] * inv_dt + sv_old[k, q])
    if not link_damping:
        for i in range(n):
            ux = x[i, 0] - nodes[i, 0]
            uy = x[i, 1] - nodes[i, 1]
            c = (d0 + d1 * np.sqrt(ux * ux + uy * uy)) * inv_dt
            for q in range(n_p):
                out[2 * i, q] -= c * s_old[2 * i, q]
                out[2 * i + 1, q] -= c * s_old[2 * i + 1, q]
    else:
        for e in range(edges.shape[0]):
            a = edges[e, 0]
            b = edges[e, 1]
            _, _, length, nx, ny, _ = link_geometry(x, a, b, rest_length[e])
            c = (d0 + d1 * abs(length - rest_length[e])) * inv_dt
            for q in range(n_p):
                proj = c * (
                    nx * (s_old[2 * a, q] - s_old[2 * b, q])
                    + ny * (s_old[2 * a + 1, q] - s_old[2 * b + 1, q])
                )
                out[2 * a, q] -= proj * nx
                out[2 * a + 1, q] -= proj * ny
                out[2 * b, q] += proj * nx
                out[2 * b + 1, q] += proj * ny
    for k in range(2 * n):
        if held_dof[k]:
            out[k, :] = 0.0


class PressSensitivity:
    """Carries ``S = dx/dp`` and ``V = dv/dp`` (2n, 6) through the steps of one press.

    Columns follow :data:`NAMES`. After each converged step call :meth:`update`; it returns
    the sensitivities (6,) of that step's force along the pipette motion, nN per unit of p.
    """

    def __init__(self, stepper) -> None:
        params = stepper.params
        pipette = stepper.pipette
        self.stepper = stepper
        n_dof = stepper.n_dof
        self.s = np.zeros((n_dof, len(NAMES)))
        self.v = np.zeros((n_dof, len(NAMES)))
        self._columns = np.zeros((n_dof, 5))
        self._history = np.zeros((n_dof, len(NAMES)))
        self._direction = np.asarray(pipette.direction, dtype=float)
        if params.area_stiffness > 0:
            self._area_per_k1 = params.area_stiffness / float(stepper.lattice.rest_length.min())
        else:
            self._area_per_k1 = 0.0
        self.factorizations = 0
        red = stepper.reduction
        if red is not None:  # symmetric branch: the half-lattice system of nmsd.symmetry
            self._ab_h = np.zeros((3 * red.band + 1, red.n_dof), order="F")
            self._res_h = np.zeros(red.n_dof)
            self._res_full = np.zeros(n_dof)
            self._kept_nodes = np.flatnonzero(red.kept_row >= 0)
            self._kept_rows = red.kept_row[self._kept_nodes]
            self._mirrored_nodes = np.flatnonzero(red.kept_row < 0)

    def contact_tangents(self, contact: np.ndarray) -> np.ndarray:
        """Contact tangents ``C_i = kappa n n^T`` (n, 2, 2) nN/um from the contact forces.

        A node in contact carries ``F_i = -kappa g n`` with ``g < 0``, so ``n = F_i/|F_i|``
        (the face normal of the sharp wedge, as :meth:`nmsd.pipette.Pipette.gap` gives it);
        nodes without force get zero blocks.
        """
        size = np.sqrt(contact[:, 0] ** 2 + contact[:, 1] ** 2)
        touching = size > 0.0
        n = np.zeros_like(contact)
        n[touching] = contact[touching] / size[touching, None]
        return self.stepper.pipette.contact_stiffness * n[:, :, None] * n[:, None, :]

    def _factor(self, ab: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """Band LU of the tangent ``ab`` (kept intact), or of its half-lattice fold
        ``(K P)_kept`` on the symmetric branch; returns LU, pivots, half bandwidth."""
        st = self.stepper
        red = st.reduction
        if red is None:
            lu, piv, info = dgbtrf(ab, st.band, st.band)  # a copy: ab is kept
            band = st.band
        else:
            st.fold(ab, self._res_full, self._ab_h, self._res_h, True)
            lu, piv, info = dgbtrf(self._ab_h, red.band, red.band, overwrite_ab=1)
            band = red.band
        if info != 0:
            raise InputError("sensitivities", "tangent", "a non-singular tangent", got=info)
        self.factorizations += 1
        return lu, piv, band

    def _solve(self, lu: np.ndarray, piv: np.ndarray, band: int, rhs: np.ndarray) -> np.ndarray:
        """S (2n, P) from ``K S = rhs``; on the symmetric branch the kept rows are solved with
        ``(K P)_kept`` and S is mirrored (``S_k = reflect(S_pair)``, fixed DOFs 0)."""
        red = self.stepper.reduction
        if red is None:
            s, info = dgbtrs(lu, band, band, rhs, piv)
        else:
            n_p = rhs.shape[1]
            rhs_h = np.zeros((red.n_dof // 2, 2, n_p))
            rhs_h[self._kept_rows] = rhs.reshape(-1, 2, n_p)[self._kept_nodes]
            rhs_h = rhs_h.reshape(red.n_dof, n_p)
            rhs_h[red.fixed] = 0.0
            s_h, info = dgbtrs(lu, band, band, rhs_h, piv)
            s = np.empty((len(red.kept_row), 2, n_p))
            s[self._kept_nodes] = s_h.reshape(-1, 2, n_p)[self._kept_rows]
            pairs = red.mirror.pairs[self._mirrored_nodes]
            s[self._mirrored_nodes, 0] = s[pairs, 0]
            s[self._mirrored_nodes, 1] = -s[pairs, 1]
            s = s.reshape(-1, n_p)
        if info != 0:
            raise InputError("sensitivities", "tangent", "a solvable band system", got=info)
        return s

    def update(
        self, x_old: np.ndarray, v_old: np.ndarray, x: np.ndarray, advance: float, dt: float
    ) -> np.ndarray:
        """Advance S, V over the converged step ``x_old -> x`` (dt s, mouth at ``advance`` um).

        Returns df/dp (6,) of the step's force along the pipette direction.
        """
        st = self.stepper
        p = st.params
        _, ab, contact, _ = st.residual(x, x_old, v_old, advance, dt, with_tangent=True)
        lu, piv, band = self._factor(ab)
        parameter_columns(
            x,
            x_old,
            st.lattice.nodes,
            st._edges,
            st._rest,
            st.link_factor,
            p.k2,
            p.dl_c,
            p.damping == "link",
            dt,
            st._cells,
            st._cell_area,
            self._area_per_k1,
            st.held_dof,
            self._columns,
        )
        history_term(
            x,
            st.lattice.nodes,
            st._edges,
            st._rest,
            p.d0,
            p.d1,
            p.damping == "link",
            p.node_mass,
            dt,
            self.s,
            self.v,
            st.held_dof,
            self._history,
        )
        tangents = self.contact_tangents(contact)
        a = self._direction
        rhs = -self._history
        rhs[:, :5] -= self._columns
        gap_column = (tangents @ a).ravel()  # dR_i/dg = C_i a
        gap_column[st.held_dof] = 0.0
        rhs[:, 5] -= gap_column
        s_new = self._solve(lu, piv, band, rhs)
        self.v = (s_new - self.s) / dt
        self.s = s_new
        # df/dp = -a . sum_i C_i (S_i + [gap] a) = -sum_i w_i . (S_i + [gap] a), w_i = C_i a
        dforce = -(gap_column @ s_new)
        dforce[5] -= gap_column.reshape(-1, 2).sum(axis=0) @ a
        return dforce
