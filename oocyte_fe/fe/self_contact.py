"""Frictionless penalty self-contact of a boundary: a layer that folds onto itself.

The boundary is the polyline through its displacement nodes (P2: vertices and edge
midpoints, in order along each facet) in the current configuration. Each node ``x`` is
checked against every segment ``(a, b)`` of the polyline that does not belong to a facet of
the node; where its projection falls on the segment (``0 <= xi <= 1``) the signed gap

    g = s (e x r) / |e|,   e = b - a,   r = x - a,   xi = (r . e) / |e|^2      [um]

(``s = +-1``: positive on the free side of the segment, fixed from the reference
configuration) enters the energy

    E = sum_pairs  w_x  eps / 2  <g_hat - g>^2,   for  -g_max < g < g_hat       [nN um]

with ``eps`` the penalty [kPa/um], ``g_hat`` the range at which the surfaces start to repel
[um] (they never touch while the contact pressure ``eps (g_hat - g)`` is below
``eps g_hat``), ``w_x`` the node's tributary length in the reference configuration (times
``2 pi R`` in axisymmetry) and ``g_max`` a depth beyond which a node is taken to lie behind
the segment, on the body's other side. The forces ``-dE/dq`` on the node and the segment's
ends sum to zero with zero moment (``E`` depends on relative positions only), and the tangent
is ``d2E/dq2`` of each pair (6 x 6, the Hessian of ``g`` included). The pairs are found anew
at every evaluation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from skfem import Basis

from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class SelfContact:
    """Self-contact of the boundary ``boundary``: penalty ``penalty`` [kPa/um], range
    ``range_um`` [um] (``g_hat``), depth ``depth_um`` [um] (``g_max``)."""

    boundary: str
    penalty: float
    range_um: float
    depth_um: float
    name: str = "self-contact"

    def __post_init__(self) -> None:
        for field, value in (
            ("penalty", self.penalty),
            ("range_um", self.range_um),
            ("depth_um", self.depth_um),
        ):
            if not (np.isfinite(value) and value > 0):
                raise InputError(self.name, field, "a finite number > 0", got=value)


@dataclass(frozen=True)
class SurfacePolyline:
    """The boundary's nodes and segments: ``dofs`` (2, n) displacement dofs of the nodes,
    ``X`` (2, n) their reference positions, ``segments`` (m, 2) node indices, ``side`` (m,)
    the sign ``s``, ``facet`` (m,) and ``node_facets`` (n, 2) the facets of each node (-1:
    none; for the exclusion of a node's own facets), ``weight`` (n,) the tributary measure."""

    dofs: NDArray
    X: NDArray
    segments: NDArray
    side: NDArray
    facet: NDArray
    node_facets: NDArray
    weight: NDArray

    @classmethod
    def of(cls, basis: Basis, facets: NDArray, axisym: bool) -> SurfacePolyline:
        mesh = basis.mesh
        facets = np.asarray(facets, dtype=int)
        ends = mesh.facets[:, facets]  # (2, nf) vertex numbers
        vdofs = basis.nodal_dofs[:, ends.ravel()]  # (2, 2 nf)
        has_mid = basis.facet_dofs.size > 0
        keys = [vdofs[0, : len(facets)], vdofs[0, len(facets) :]]
        mids = basis.facet_dofs[:, facets] if has_mid else None
        # node numbering by the x-dof of each node (unique along the boundary)
        all_x = np.concatenate(keys + ([mids[0]] if has_mid else []))
        unique_x, inverse = np.unique(all_x, return_inverse=True)
        nf = len(facets)
        i0, i1 = inverse[:nf], inverse[nf : 2 * nf]
        if has_mid:
            im = inverse[2 * nf :]
            segments = np.concatenate([np.stack([i0, im], 1), np.stack([im, i1], 1)])
            facet = np.concatenate([np.arange(nf), np.arange(nf)])
        else:
            segments = np.stack([i0, i1], 1)
            facet = np.arange(nf)
        x_to_y = dict(
            zip(
                np.concatenate([vdofs[0], mids[0]] if has_mid else [vdofs[0]]),
                np.concatenate([vdofs[1], mids[1]] if has_mid else [vdofs[1]]),
                strict=True,
            )
        )
        dofs = np.stack([unique_x, [x_to_y[d] for d in unique_x]])
        X = basis.doflocs[:, unique_x]
        # the free side: the segment's left normal against the direction to its element
        element = mesh.f2t[0, facets]
        centre = mesh.p[:, mesh.t[:3, element]].mean(axis=1)  # (2, nf)
        a, b = X[:, segments[:, 0]], X[:, segments[:, 1]]
        e = b - a
        inward = centre[:, facet] - 0.5 * (a + b)
        side = -np.sign(e[0] * inward[1] - e[1] * inward[0])  # e x inward > 0: left is inside
        length = np.linalg.norm(e, axis=0)
        radius = 0.5 * (a[0] + b[0])
        measure = length * (2.0 * np.pi * radius if axisym else 1.0)
        weight = np.zeros(len(unique_x))
        np.add.at(weight, segments[:, 0], 0.5 * measure)
        np.add.at(weight, segments[:, 1], 0.5 * measure)
        node_facets = np.full((len(unique_x), 2), -1)
        for k, (p, q) in enumerate(segments):
            for node in (p, q):  # a vertex on two facets, a midpoint on one
                if facet[k] not in node_facets[node]:
                    node_facets[node, int(node_facets[node, 0] >= 0)] = facet[k]
        return cls(dofs, X, segments, side, facet, node_facets, weight)


@dataclass(frozen=True)
class Pairs:
    """Active node-segment pairs: ``node``, ``segment`` indices, gap ``g`` [um]."""

    node: NDArray
    segment: NDArray
    gap: NDArray


def _perp(v: NDArray) -> NDArray:
    """``(-v_y, v_x)`` of (..., 2) vectors."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def find_pairs(line: SurfacePolyline, x: NDArray, contact: SelfContact) -> Pairs:
    """The node-segment pairs within ``(-g_max, g_hat)`` at current node positions ``x`` (2, n)."""
    a, b = x[:, line.segments[:, 0]], x[:, line.segments[:, 1]]
    e = (b - a).T  # (m, 2)
    length2 = np.einsum("mk,mk->m", e, e)
    reach = np.sqrt(length2.max()) + contact.range_um + contact.depth_um
    lo = np.minimum(a, b) - reach
    hi = np.maximum(a, b) + reach
    near = np.all((x[:, :, None] >= lo[:, None, :]) & (x[:, :, None] <= hi[:, None, :]), axis=0)
    node, seg = np.nonzero(near)
    own = np.any(line.node_facets[node] == line.facet[seg][:, None], axis=1)
    node, seg = node[~own], seg[~own]
    r = x[:, node].T - a[:, seg].T
    es = e[seg]
    xi = np.einsum("mk,mk->m", r, es) / length2[seg]
    g = line.side[seg] * (es[:, 0] * r[:, 1] - es[:, 1] * r[:, 0]) / np.sqrt(length2[seg])
    keep = (xi >= 0.0) & (xi <= 1.0) & (g < contact.range_um) & (g > -contact.depth_um)
    return Pairs(node[keep], seg[keep], g[keep])


def gap_derivatives(
    xn: NDArray, a: NDArray, b: NDArray, side: NDArray
) -> tuple[NDArray, NDArray, NDArray]:
    """Gap ``g``, gradient (k, 6) and Hessian (k, 6, 6) over ``q = (x, a, b)`` of each pair
    (rows of (k, 2) positions), for ``g = s (e x r) / |e|``."""
    e, r = b - a, xn - a
    L = np.linalg.norm(e, axis=1)
    c = e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0]
    # dc/dq: d/dx = perp(e), d/da = -perp(e) + perp(r), d/db = -perp(r)
    pe, pr = _perp(e), _perp(r)
    dc = np.concatenate([pe, -pe + pr, -pr], axis=1)
    # c = e^T M r with M = [[0, 1], [-1, 0]]; e = Te q, r = Tr q
    M = np.array([[0.0, 1.0], [-1.0, 0.0]])
    eye = np.eye(2)
    Te = np.concatenate([0 * eye, -eye, eye], axis=1)  # (2, 6)
    Tr = np.concatenate([eye, -eye, 0 * eye], axis=1)
    Hc = Te.T @ M @ Tr + Tr.T @ M.T @ Te  # constant (6, 6)
    w = 1.0 / L
    dw_e = -e / L[:, None] ** 3  # (k, 2)
    dw = dw_e @ Te  # (k, 6)
    Hw_e = -np.eye(2)[None] / L[:, None, None] ** 3 + 3.0 * np.einsum("ki,kj->kij", e, e) / (
        L[:, None, None] ** 5
    )
    Hw = np.einsum("ai,kab,bj->kij", Te, Hw_e, Te)
    g = c * w
    dg = w[:, None] * dc + c[:, None] * dw
    Hg = (
        w[:, None, None] * Hc[None]
        + np.einsum("ki,kj->kij", dc, dw)
        + np.einsum("ki,kj->kij", dw, dc)
        + c[:, None, None] * Hw
    )
    s = side[:, None]
    return side * g, s * dg, s[:, :, None] * Hg


def forces(
    line: SurfacePolyline, u: NDArray, contact: SelfContact, n_u: int
) -> tuple[NDArray, sp.coo_matrix, Pairs]:
    """The contact forces ``-dE/du`` on the body (n_u,) [nN], the tangent ``d2E/du2`` (COO)
    and the active pairs, at the displacement ``u`` (n_u,)."""
    x = line.X + u[line.dofs]
    pairs = find_pairs(line, x, contact)
    f = np.zeros(n_u)
    if len(pairs.node) == 0:
        return f, sp.coo_matrix((n_u, n_u)), pairs
    ends = line.segments[pairs.segment]
    xn, a, b = x[:, pairs.node].T, x[:, ends[:, 0]].T, x[:, ends[:, 1]].T
    g, dg, Hg = gap_derivatives(xn, a, b, line.side[pairs.segment])
    pen = contact.range_um - g
    kw = contact.penalty * line.weight[pairs.node]
    # E = kw pen^2 / 2: dE/dq = -kw pen dg, d2E/dq2 = kw (dg dg^T - pen Hg)
    grad = -(kw * pen)[:, None] * dg
    hess = kw[:, None, None] * (np.einsum("ki,kj->kij", dg, dg) - pen[:, None, None] * Hg)
    nodes = np.stack([pairs.node, ends[:, 0], ends[:, 1]], axis=1)  # (k, 3)
    q_dofs = np.stack([line.dofs[0][nodes], line.dofs[1][nodes]], axis=2).reshape(-1, 6)
    np.add.at(f, q_dofs.ravel(), -grad.ravel())
    rows = np.repeat(q_dofs, 6, axis=1).ravel()
    cols = np.tile(q_dofs, (1, 6)).ravel()
    K = sp.coo_matrix((hess.ravel(), (rows, cols)), shape=(n_u, n_u))
    return f, K, pairs
