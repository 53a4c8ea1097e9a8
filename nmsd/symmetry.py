"""Mirror symmetry of the press about the pipette axis, and the symmetric branch.

The Table II press is mirror-symmetric: the lattice (:func:`nmsd.lattice.circular_lattice`),
the pipette on its axis and the held rim nodes map onto themselves under the reflection
``S`` across the pipette axis. The symmetric motion is a solution, but a soft lattice
compressed between the pipette and the holder buckles sideways off it: an antisymmetric
mode grows from round-off (1e-13 um to 4 um within 10 um of advance, docs/nmsd.md,
"Sideways buckling"), so which way and when it buckles is set by round-off and by the time
step, and the press force then varies by ~10 %. Following the symmetric branch makes the
press deterministic: after every converged step the state is projected onto the symmetric
motions,

    x <- (x + S x[mirror]) / 2,    v <- (v + S v[mirror]) / 2,

``mirror[i]`` the node at the reflection of node i. For a state that is symmetric up to
round-off this moves nothing but the round-off.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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

    def project(self, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (n, 2) projected onto the symmetric motions."""
        xs = self.point + self.reflect(x[self.pairs] - self.point)
        return 0.5 * (x + xs), 0.5 * (v + self.reflect(v[self.pairs]))


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
