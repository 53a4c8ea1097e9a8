"""Damping of eq 6, seed 000, in two readings: per node (as printed) or per link (Fig. 3).

Nodal (eq 6 as printed; a drag on each node against the surrounding medium):

    F_i^d = (d0 + d1 |r_i - r0_i|) v_i

r, r0 (um): current and rest position of the node; v (um/s) its velocity.

Link (Fig. 3 and issue 6: "linked to up to 8 neighbours by a Voigt element"; a dashpot in
parallel with each spring, acting on the rate of change of the link length):

    f^d = (d0 + d1 |l - l0|) dl/dt,   dl/dt = n . (v_a - v_b),   n = (r_a - r_b) / l

on node a ``+f^d n``, on node b ``-f^d n``. ``|r - r0|`` of eq 6 is read for a link as its
elongation ``|l - l0|`` (um), the only length a two-node Voigt element knows (the relative
displacement of its ends would add rigid rotation, which a dashpot does not resist). The
link dashpot resists no rigid motion: the lattice is then not tied to the medium.

Both: d0 in nN s/um, d1 in nN s/um^2, forces in nN. The compiled residual and tangent are
in :mod:`nmsd.assembly`; these numpy versions are the readable reference.
"""

from __future__ import annotations

import numpy as np

READINGS = ("nodal", "link")


def nodal_damping(
    displacement: np.ndarray, velocity: np.ndarray, d0: float, d1: float
) -> tuple[np.ndarray, np.ndarray]:
    """Damping force (n, 2) in nN and the coefficient d0 + d1 |u| (n,) in nN s/um."""
    coefficient = d0 + d1 * np.linalg.norm(displacement, axis=1)
    return coefficient[:, None] * velocity, coefficient


def link_damping(
    positions: np.ndarray,
    velocities: np.ndarray,
    edges: np.ndarray,
    rest_length: np.ndarray,
    d0: float,
    d1: float,
) -> np.ndarray:
    """Nodal forces (n, 2) in nN of the Voigt dashpots on the links (m, 2) of a lattice."""
    d = positions[edges[:, 0]] - positions[edges[:, 1]]
    length = np.linalg.norm(d, axis=1)
    n = d / length[:, None]
    rate = np.sum(n * (velocities[edges[:, 0]] - velocities[edges[:, 1]]), axis=1)
    f = ((d0 + d1 * np.abs(length - rest_length)) * rate)[:, None] * n
    force = np.zeros_like(positions)
    np.add.at(force, edges[:, 0], f)
    np.add.at(force, edges[:, 1], -f)
    return force
