"""Mirror symmetry of the press about the pipette axis, and the symmetric branch.

The Table II press is mirror-symmetric: the lattice (:func:`nmsd.lattice.circular_lattice`),
the pipette on its axis and the held rim nodes map onto themselves under the reflection
``S`` across the pipette axis. The symmetric motion is a solution, but a soft lattice
compressed between the pipette and the holder buckles sideways off it: an antisymmetric
mode grows from round-off (1e-13 um to 4 um within 10 um of advance, docs/nmsd.md,
"Sideways buckling"), so which way and when it buckles is set by round-off and by the time
step, and the press force then varies by ~10 %. Following the symmetric branch makes the
press deterministic.

Half-lattice solve. On the symmetric branch the unknowns are the nodes on one side of the
axis (and on it): with ``P`` the map from those to all nodes (``x_k = S x_pairs[k]`` for the
mirrored nodes, S the reflection), Newton solves ``(K P)_kept dx_h = -R_kept`` on the kept
rows only (R is mirror-equivariant, so the other rows are their reflections). The axis nodes
move along the axis (their across-axis DOF is fixed). :func:`fold` turns the full band
tangent into the kept system; its bandwidth is the full one and it has about half the rows,
so a band LU costs about half. :class:`Reduction` holds the maps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import reverse_cuthill_mckee

from nmsd.lattice import Lattice
from nmsd.pipette import Pipette
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class Mirror:
    """Reflection across the line through ``point`` along ``direction`` (um), node pairing."""

    point: np.ndarray
    direction: np.ndarray
    pairs: np.ndarray

    def reflect(self, vectors: np.ndarray) -> np.ndarray:
        """Reflected vectors (n, 2) (no translation)."""
        a = self.direction
        along = vectors @ a
        return 2.0 * along[:, None] * a - vectors


def mirror_of(lattice: Lattice, pipette: Pipette, held: np.ndarray, tol_um: float = 1e-6) -> Mirror:
    """The reflection across the pipette axis, if it maps lattice and held nodes onto
    themselves within ``tol_um``; otherwise :class:`InputError`."""
    a = np.asarray(pipette.direction, dtype=float)
    point = np.asarray(pipette.start, dtype=float)
    mirror = Mirror(point, a, np.zeros(0, dtype=np.int64))
    images = point + mirror.reflect(lattice.nodes - point)
    distance = np.linalg.norm(images[:, None, :] - lattice.nodes[None, :, :], axis=2)
    pairs = np.argmin(distance, axis=1)
    worst = float(distance[np.arange(len(pairs)), pairs].max())
    held = np.asarray(held, dtype=bool)
    if worst > tol_um or not np.array_equal(held, held[pairs]):
        raise InputError(
            "symmetric press",
            "symmetric",
            "a lattice, pipette axis and held nodes symmetric about the axis "
            f"(largest node mismatch {worst:.3g} um, held nodes "
            f"{'symmetric' if np.array_equal(held, held[pairs]) else 'not symmetric'}); "
            "set symmetric = false",
        )
    return Mirror(point, a, pairs)


@dataclass(frozen=True)
class Reduction:
    """Maps of the half-lattice system of a press along the x axis (see module docstring).

    ``node_map[k]``: reduced index of node k's representative (itself if kept, else its
    mirror image); ``kept_row[k]``: reduced index of node k if kept, else -1; ``mirrored[k]``:
    node k is the image of a kept node; ``fixed``: reduced DOFs held (holder, and the
    across-axis DOF of axis nodes); ``band``: half bandwidth (DOFs) of the kept system.
    """

    mirror: Mirror
    node_map: np.ndarray
    kept_row: np.ndarray
    mirrored: np.ndarray
    fixed: np.ndarray
    band: int

    @property
    def n_dof(self) -> int:
        """Number of DOFs of the kept system."""
        return len(self.fixed)

    def expand(self, x: np.ndarray, dx: np.ndarray) -> None:
        """Add the kept update ``dx`` (2 n_kept,) to ``x`` (n, 2) in place and mirror it."""
        _expand(x, dx, self.kept_row, self.mirror.pairs, float(self.mirror.point[1]))


@njit(cache=True)
def _expand(x, dx, kept_row, pairs, y_axis):
    """x[kept] += dx; every other node is the image of its pair across y = y_axis."""
    for k in range(x.shape[0]):
        r = kept_row[k]
        if r >= 0:
            x[k, 0] += dx[2 * r]
            x[k, 1] += dx[2 * r + 1]
    for k in range(x.shape[0]):
        if kept_row[k] < 0:
            x[k, 0] = x[pairs[k], 0]
            x[k, 1] = 2.0 * y_axis - x[pairs[k], 1]


def reduction_of(
    mirror: Mirror,
    nodes: np.ndarray,
    edges: np.ndarray,
    held: np.ndarray,
    cells: np.ndarray | None = None,
) -> Reduction:
    """The half-lattice system of ``mirror`` (pipette axis along x): kept nodes are those on
    the axis and, of each mirror pair, the one with the smaller index; ``cells`` (optional,
    -1 padded) widen the band like links do.

    The kept nodes are numbered for the narrowest band among three orderings: the lattice's
    own, across-axis columns (sorted by x, then y; the half disc is about half as tall as it
    is wide) and reverse Cuthill-McKee (:func:`scipy.sparse.csgraph.reverse_cuthill_mckee`).
    A band LU costs ~ n b^2: for the 231-node lattice the columns give a half bandwidth of 21
    DOFs against 37 for the rows.
    """
    if abs(mirror.direction[1]) > 1e-12:
        raise InputError(
            "symmetric press", "direction", "a pipette axis along x for the half-lattice solve"
        )
    n = len(mirror.pairs)
    index = np.arange(n)
    kept = mirror.pairs >= index
    mirrored = ~kept
    corners = [] if cells is None else [c[c >= 0] for c in cells]
    candidates = [index[kept], index[kept][np.lexsort((nodes[kept, 1], nodes[kept, 0]))]]
    # reverse Cuthill-McKee on the kept graph (links folded onto their kept images)
    image = np.where(kept, index, mirror.pairs)
    local = np.full(n, -1, dtype=np.int64)
    local[kept] = np.arange(int(kept.sum()))
    pairs = local[image[edges]]
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(int(kept.sum()),) * 2
    ).tocsr()
    candidates.append(index[kept][reverse_cuthill_mckee(graph + graph.T, symmetric_mode=True)])
    best = None
    for order in candidates:
        kept_row = np.full(n, -1, dtype=np.int64)
        kept_row[order] = np.arange(len(order))
        node_map = kept_row[image]
        spread = int(np.abs(node_map[edges[:, 0]] - node_map[edges[:, 1]]).max())
        for c in corners:
            spread = max(spread, int(np.ptp(node_map[c])))
        if best is None or spread < best[0]:
            best = (spread, kept_row, node_map)
    spread, kept_row, node_map = best
    fixed = np.zeros((int(kept.sum()), 2), dtype=bool)
    fixed[kept_row[kept & np.asarray(held, dtype=bool)]] = True
    fixed[kept_row[kept & (mirror.pairs == index)], 1] = True  # on the axis: along it only
    return Reduction(mirror, node_map, kept_row, mirrored, fixed.ravel(), int(2 * spread + 1))


def fold_map(
    red: Reduction, n_nodes: int, edges: np.ndarray, band: int, cells: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Where each structurally non-zero tangent entry of a kept row goes in the kept system.

    Entries couple a node with itself, the two ends of a link and (area term) the corners of
    a cell. Returns ``(src_row, src_col, dst_row, dst_col, sign)``: band-storage positions
    in the full tangent (half bandwidth ``band``) and in the kept one (``red.band``), and the
    sign of the reflection (-1 for the y column of a mirrored node).
    """
    pairs = [np.column_stack([np.arange(n_nodes)] * 2), edges, edges[:, ::-1]]
    for cell in [] if cells is None else cells:
        c = cell[cell >= 0]
        pairs.append(np.array([(i, j) for i in c for j in c if i != j]))
    blocks = np.unique(np.vstack(pairs), axis=0)
    blocks = blocks[red.kept_row[blocks[:, 0]] >= 0]
    out = []
    for ri in range(2):
        for ci in range(2):
            i = 2 * blocks[:, 0] + ri
            j = 2 * blocks[:, 1] + ci
            row = 2 * red.kept_row[blocks[:, 0]] + ri
            col = 2 * red.node_map[blocks[:, 1]] + ci
            sign = np.where(red.mirrored[blocks[:, 1]] & (ci == 1), -1.0, 1.0)
            out.append((2 * band + i - j, j, 2 * red.band + row - col, col, sign))
    return tuple(np.concatenate(parts) for parts in zip(*out, strict=True))


@njit(cache=True)
def fold(
    ab,
    res,
    kept_row,
    fixed,
    src_row,
    src_col,
    dst_row,
    dst_col,
    sign,
    ab_h,
    band_h,
    res_h,
    with_tangent,
):
    """Kept-row residual ``res_h`` and, if ``with_tangent``, the tangent ``(K P)_kept`` in
    band storage ``ab_h`` (LAPACK gbtrf layout) from the full ones; ``src_row`` ... ``sign``
    from :func:`fold_map`."""
    for k in range(kept_row.shape[0]):
        r = kept_row[k]
        if r >= 0:
            res_h[2 * r] = res[2 * k]
            res_h[2 * r + 1] = res[2 * k + 1]
    n_h = res_h.shape[0]
    for q in range(n_h):
        if fixed[q]:
            res_h[q] = 0.0
    if not with_tangent:
        return
    for j in range(ab_h.shape[1]):  # column by column (Fortran order)
        for k in range(ab_h.shape[0]):
            ab_h[k, j] = 0.0
    for e in range(src_row.shape[0]):
        ab_h[dst_row[e], dst_col[e]] += sign[e] * ab[src_row[e], src_col[e]]
    for q in range(n_h):
        if fixed[q]:
            for j in range(max(0, q - band_h), min(n_h, q + band_h + 1)):
                ab_h[2 * band_h + q - j, j] = 0.0
            ab_h[2 * band_h, q] = 1.0
