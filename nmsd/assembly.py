"""Residual and band-stored tangent of the backward-Euler step of eq 1, compiled with numba.

One pass over the nodes (inertia, nodal damping, pipette contact) and one over the links
(springs of eqs 2-5, and Voigt dampers in the link reading of eq 6) fills the residual

    R(x+) = M (v+ - v)/dt + F^d(x+, v+) + F^k(x+) - F^ext(x+),   v+ = (x+ - x)/dt

and, on request, its exact tangent dR/dx+ in LAPACK ``gbtrf`` band storage
(``ab[2 b + i - j, j] = K[i, j]``, b the half bandwidth). The same laws in numpy, for reading
and for the tests, are :func:`nmsd.spring.link_force`, :func:`nmsd.damping.nodal_damping` and
:func:`nmsd.damping.link_damping`, :meth:`nmsd.pipette.Pipette.gap`.

Damping readings (``link_damping``):

- nodal (eq 6 as printed): ``F_i^d = (d0 + d1 |u_i|) v_i`` on every node, ``u_i = r_i - r0_i``;
- link (Fig. 3, a Voigt element per link): on each link a dashpot along it,
  ``f^d = (d0 + d1 |l - l0|) dl/dt``, acting as ``+f^d n`` on its first node and ``-f^d n``
  on its second (n the unit vector from the second node to the first), in parallel with the
  spring.

Optional ZP ring (:mod:`nmsd.zona`): ``link_factor[e]`` scales the spring force and its slope
of link e (k1 and k2 together; 1 everywhere is the paper's lattice, bit for bit).

Optional area term (:mod:`nmsd.area`, off when ``area_kappa`` is 0): each cell (3 or 4
corners, -1 pads) adds ``p dA/dx`` with ``p = kappa (A/A0 - 1)`` to the residual and
``kappa/A0 dA/dx (x) dA/dx + p d2A/dx2`` to the tangent. A cell's corners lie in two
neighbouring grid rows and are pairwise linked, so the band of the links holds them.

Held DOFs get an identity row and a zero residual (they do not move). Units: um, nN, s.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _add_block(ab, band, n_dof, i, j, b00, b01, b10, b11):
    """Add the 2x2 block (node i rows, node j columns) into band storage."""
    r = 2 * i
    c = 2 * j
    base = 2 * band
    ab[base + r - c, c] += b00
    ab[base + r - c - 1, c + 1] += b01
    ab[base + r + 1 - c, c] += b10
    ab[base + r - c, c + 1] += b11


@njit(cache=True, inline="always")
def link_geometry(x, a, b, l0):
    """Link a-b at positions x: ``dx, dy`` (um, a minus b), length l (um), unit vector
    ``n = (dx, dy)/l`` and strain ``l/l0 - 1``."""
    dx = x[a, 0] - x[b, 0]
    dy = x[a, 1] - x[b, 1]
    length = np.sqrt(dx * dx + dy * dy)
    return dx, dy, length, dx / length, dy / length, length / l0 - 1.0


@njit(cache=True, inline="always")
def cell_area(x, cells, c, idx, gx, gy):
    """Shoelace area (um^2) of cell c (3 or 4 corners, -1 padded) and its gradient: fills
    ``idx[k]`` with the corner nodes and ``gx[k], gy[k]`` with dA/dx, dA/dy of corner k;
    returns (number of corners, area)."""
    m = 4 if cells[c, 3] >= 0 else 3
    area = 0.0
    for k in range(m):
        i = cells[c, k]
        j = cells[c, (k + 1) % m]
        h = cells[c, (k + m - 1) % m]
        idx[k] = i
        area += 0.5 * (x[i, 0] * x[j, 1] - x[j, 0] * x[i, 1])
        gx[k] = 0.5 * (x[j, 1] - x[h, 1])
        gy[k] = 0.5 * (x[h, 0] - x[j, 0])
    return m, area


@njit(cache=True)
def assemble(
    x,
    x_old,
    v_old,
    nodes,
    edges,
    rest_length,
    link_factor,
    k1,
    k2,
    dl_c,
    d0,
    d1,
    link_damping,
    mass,
    dt,
    normals,
    offsets,
    mouth,
    kappa,
    cells,
    rest_area,
    area_kappa,
    held_dof,
    band,
    res,
    ab,
    contact,
    with_tangent,
):
    """Fill ``res`` (2n,), ``contact`` (n, 2) and, if ``with_tangent``, ``ab`` in place.

    Returns the largest absolute residual over the free DOFs (nN).
    """
    n = nodes.shape[0]
    n_dof = 2 * n
    inv_dt = 1.0 / dt
    res[:] = 0.0
    contact[:, :] = 0.0
    if with_tangent:
        for j in range(ab.shape[1]):  # column by column: ab is Fortran-ordered (a slice
            for k in range(ab.shape[0]):  # assignment is ~20x slower here)
                ab[k, j] = 0.0
    diag0 = mass * inv_dt * inv_dt
    for i in range(n):
        vx = (x[i, 0] - x_old[i, 0]) * inv_dt
        vy = (x[i, 1] - x_old[i, 1]) * inv_dt
        rx = mass * (vx - v_old[i, 0]) * inv_dt
        ry = mass * (vy - v_old[i, 1]) * inv_dt
        b00 = diag0
        b01 = 0.0
        b10 = 0.0
        b11 = diag0
        if not link_damping:
            ux = x[i, 0] - nodes[i, 0]
            uy = x[i, 1] - nodes[i, 1]
            un = np.sqrt(ux * ux + uy * uy)
            c = d0 + d1 * un
            rx += c * vx
            ry += c * vy
            b00 += c * inv_dt
            b11 += c * inv_dt
            if un > 0.0:
                s = d1 / un
                b00 += s * vx * ux
                b01 += s * vx * uy
                b10 += s * vy * ux
                b11 += s * vy * uy
        # pipette contact: nearest face of the three half-planes
        gap = -np.inf
        nx = 0.0
        ny = 0.0
        for f in range(3):
            g = (x[i, 0] - mouth[0]) * normals[f, 0] + (x[i, 1] - mouth[1]) * normals[f, 1]
            g -= offsets[f]
            if g > gap:
                gap = g
                nx = normals[f, 0]
                ny = normals[f, 1]
        if gap < 0.0:
            fx = -kappa * gap * nx
            fy = -kappa * gap * ny
            contact[i, 0] = fx
            contact[i, 1] = fy
            rx -= fx
            ry -= fy
            b00 += kappa * nx * nx
            b01 += kappa * nx * ny
            b10 += kappa * ny * nx
            b11 += kappa * ny * ny
        res[2 * i] += rx
        res[2 * i + 1] += ry
        if with_tangent:
            _add_block(ab, band, n_dof, i, i, b00, b01, b10, b11)
    a_lin = k1 * dl_c + k2 * dl_c**3
    b_lin = k1 + 3.0 * k2 * dl_c**2
    for e in range(edges.shape[0]):
        a = edges[e, 0]
        b = edges[e, 1]
        l0 = rest_length[e]
        dx, dy, length, nx, ny, strain = link_geometry(x, a, b, l0)
        if abs(strain) <= dl_c:
            f = k1 * strain + k2 * strain**3
            df = k1 + 3.0 * k2 * strain**2
        else:
            f = np.sign(strain) * (a_lin + b_lin * (abs(strain) - dl_c))
            df = b_lin
        f *= link_factor[e]
        df *= link_factor[e]
        g = f / length
        t = df / l0 - g
        t00 = t * nx * nx + g
        t01 = t * nx * ny
        t10 = t01
        t11 = t * ny * ny + g
        ftot = f
        if link_damping:
            wx = (dx - (x_old[a, 0] - x_old[b, 0])) * inv_dt
            wy = (dy - (x_old[a, 1] - x_old[b, 1])) * inv_dt
            rate = nx * wx + ny * wy
            stretch = length - l0
            c = d0 + d1 * abs(stretch)
            fd = c * rate
            ftot += fd
            # d(rate)/dd = P w / l + n / dt, P = I - n n^T; dc/dd = d1 sgn(l - l0) n
            pw = wx * (1.0 - nx * nx) - wy * nx * ny
            qw = -wx * nx * ny + wy * (1.0 - ny * ny)
            sg = d1 * np.sign(stretch) * rate
            gx = sg * nx + c * (pw / length + nx * inv_dt)
            gy = sg * ny + c * (qw / length + ny * inv_dt)
            h = fd / length
            t00 += nx * gx + h * (1.0 - nx * nx)
            t01 += nx * gy - h * nx * ny
            t10 += ny * gx - h * nx * ny
            t11 += ny * gy + h * (1.0 - ny * ny)
        res[2 * a] += ftot * nx
        res[2 * a + 1] += ftot * ny
        res[2 * b] -= ftot * nx
        res[2 * b + 1] -= ftot * ny
        if with_tangent:
            _add_block(ab, band, n_dof, a, a, t00, t01, t10, t11)
            _add_block(ab, band, n_dof, b, b, t00, t01, t10, t11)
            _add_block(ab, band, n_dof, a, b, -t00, -t01, -t10, -t11)
            _add_block(ab, band, n_dof, b, a, -t00, -t01, -t10, -t11)
    if area_kappa > 0.0:
        gx = np.empty(4)
        gy = np.empty(4)
        idx = np.empty(4, dtype=np.int64)
        for c in range(cells.shape[0]):
            m, area = cell_area(x, cells, c, idx, gx, gy)
            a0 = rest_area[c]
            p = area_kappa * (area / a0 - 1.0)
            for k in range(m):
                res[2 * idx[k]] += p * gx[k]
                res[2 * idx[k] + 1] += p * gy[k]
            if with_tangent:
                w = area_kappa / a0
                for k in range(m):
                    for q in range(m):
                        # d2A/(dx_k dy_q) = (d_q,k+1 - d_q,k-1)/2; d2A/(dy_k dx_q) its mirror
                        hxy = 0.0
                        hyx = 0.0
                        if q == (k + 1) % m:
                            hxy += 0.5
                            hyx -= 0.5
                        if q == (k + m - 1) % m:
                            hxy -= 0.5
                            hyx += 0.5
                        _add_block(
                            ab,
                            band,
                            n_dof,
                            idx[k],
                            idx[q],
                            w * gx[k] * gx[q],
                            w * gx[k] * gy[q] + p * hxy,
                            w * gy[k] * gx[q] + p * hyx,
                            w * gy[k] * gy[q],
                        )
    worst = 0.0
    for k in range(n_dof):
        if held_dof[k]:
            res[k] = 0.0
            if with_tangent:
                for j in range(max(0, k - band), min(n_dof, k + band + 1)):
                    ab[2 * band + k - j, j] = 0.0
                ab[2 * band, k] = 1.0
        elif abs(res[k]) > worst:
            worst = abs(res[k])
    return worst
