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
move along the axis (their across-axis DOF is fixed). :class:`Reduction` holds the maps;
:func:`nmsd.assembly.assemble` fills the kept system's band tangent directly (its bandwidth
is the full one and it has about half the rows, so a band LU costs about half).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from nmsd.errors import NmsdInputError
from nmsd.lattice import Lattice
from nmsd.pipette import Pipette


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
    themselves within ``tol_um``; otherwise :class:`NmsdInputError`."""
    a = np.asarray(pipette.direction, dtype=float)
    point = np.asarray(pipette.start, dtype=float)
    mirror = Mirror(point, a, np.zeros(0, dtype=np.int64))
    images = point + mirror.reflect(lattice.nodes - point)
    distance = np.linalg.norm(images[:, None, :] - lattice.nodes[None, :, :], axis=2)
    pairs = np.argmin(distance, axis=1)
    worst = float(distance[np.arange(len(pairs)), pairs].max())
    held = np.asarray(held, dtype=bool)
    if worst > tol_um or not np.array_equal(held, held[pairs]):
        raise NmsdInputError(
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
    def system(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(row_of, col_of, flip_y)`` of :func:`nmsd.assembly.assemble`."""
        return self.kept_row, self.node_map, self.mirrored

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
    mirror: Mirror, edges: np.ndarray, held: np.ndarray, cells: np.ndarray | None = None
) -> Reduction:
    """The half-lattice system of ``mirror`` (pipette axis along x): kept nodes are those on
    the axis and, of each mirror pair, the one with the smaller index. ``cells`` (optional,
    -1 padded) widen the band like links do."""
    if abs(mirror.direction[1]) > 1e-12:
        raise NmsdInputError(
            "symmetric press", "direction", "a pipette axis along x for the half-lattice solve"
        )
    n = len(mirror.pairs)
    index = np.arange(n)
    kept = mirror.pairs >= index
    kept_row = np.full(n, -1, dtype=np.int64)
    kept_row[kept] = np.arange(int(kept.sum()))
    mirrored = ~kept
    node_map = np.where(kept, kept_row, kept_row[mirror.pairs])
    fixed = np.zeros((int(kept.sum()), 2), dtype=bool)
    fixed[kept_row[kept & np.asarray(held, dtype=bool)]] = True
    fixed[kept_row[kept & (mirror.pairs == index)], 1] = True  # on the axis: along it only
    spread = int(np.abs(node_map[edges[:, 0]] - node_map[edges[:, 1]]).max())
    for row in [] if cells is None else cells:
        spread = max(spread, int(np.ptp(node_map[row[row >= 0]])))
    return Reduction(mirror, node_map, kept_row, mirrored, fixed.ravel(), int(2 * spread + 1))
