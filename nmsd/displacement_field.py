"""Displacement field of a press, for cross-checking the plane-strain FE model (issue 9).

Runs the press and returns, at each requested pipette advance, the nodal displacements
``u = x - X`` (um) and the displacement at arbitrary interior points of the rest
configuration (linear in the Delaunay triangles of the rest lattice).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from nmsd.material_point import locate
from nmsd.parameters import NmsdParameters
from nmsd.press import PressResult, PressSetup


@dataclass(frozen=True, eq=False)
class DisplacementField:
    """Nodal (n, 2) and point (p, 2) displacements in um, keyed by pipette advance in um."""

    reference_nodes: np.ndarray
    nodal: dict[float, np.ndarray]
    at_points: dict[float, np.ndarray]
    press: PressResult


def press_displacements(
    setup: PressSetup,
    params: NmsdParameters,
    advances_um: Sequence[float],
    points_um: np.ndarray | None = None,
) -> DisplacementField:
    """Press up to the largest advance; displacement fields at each advance (um)."""
    advances = sorted(float(a) for a in advances_um)
    press = setup.run(params, record_um=advances, travel_um=max(advances))
    ref = setup.lattice.nodes
    nodal = {a: press.snapshots[a] - ref for a in advances}
    at_points: dict[float, np.ndarray] = {}
    if points_um is not None:
        carried = locate(setup.lattice, points_um)
        at_points = {
            a: carried.positions(press.snapshots[a]) - carried.positions(ref) for a in advances
        }
    return DisplacementField(ref, nodal, at_points, press)
