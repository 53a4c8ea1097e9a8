"""The description's surface loads as FE loads, and the supports of a free cell.

See :mod:`oocyte_fe.experiment.loads` for the loads and the inertia relief they get when the
cell is free (``support = "inertia_relief"``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import skfem
from numpy.typing import NDArray

from oocyte_fe.experiment.description import Experiment
from oocyte_fe.experiment.loads import (
    PressureLoad,
    TractionField,
    TractionLoad,
    polar_deg,
    read_traction_table,
)
from oocyte_fe.experiment.paths import PathSpec
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.loads import BodyForce, FollowerPressure, PinnedPoint, SurfaceTraction
from oocyte_fe.fe.solver import dead_load_vector


def rigid_pins(mesh: skfem.Mesh, axisym: bool) -> list[PinnedPoint]:
    """Pins that remove only the rigid motion of a free cell: the vertex nearest the centre
    (both components; axisymmetric: the axial one) and, in plane strain, the y component of
    the vertex nearest (R, 0) (a vertex of the outline on the x axis: the rotation is the one
    that leaves it no tangential motion)."""
    p = mesh.p[:, np.unique(mesh.t[:3])]  # the vertices (a P2 mesh lists its mid-nodes too)
    centre = tuple(p[:, int(np.argmin(np.hypot(*p)))])
    if axisym:
        return [PinnedPoint(centre, 1)]
    across = tuple(p[:, int(np.argmin(np.hypot(p[0] - np.hypot(*p).max(), p[1])))])
    return [PinnedPoint(centre, 0), PinnedPoint(centre, 1), PinnedPoint(across, 1)]


def surface_loads(exp: Experiment) -> tuple[list[FollowerPressure], list[SurfaceTraction]]:
    """The description's loads as FE loads on the outer surface (see :mod:`.loads`)."""
    axisym = exp.cell.symmetry == "axisymmetric"
    pressures, tractions = [], []
    ramp = PathSpec(time_s=[0.0, exp.time.duration_s], value=[0.0, 1.0])
    for name, load in exp.loads.items():
        if isinstance(load, PressureLoad):
            window = load.window_deg
            pressures.append(
                FollowerPressure(
                    "outer_surface",
                    lambda t, path=load.pressure_Pa: 1e-3 * path(t),  # Pa -> kPa
                    where=None if window is None else PolarWindow(*window),
                    name=name,
                )
            )
        elif isinstance(load, TractionLoad):
            rows = read_traction_table(load.table, exp.cell.radius_um, axisym)
            field = TractionField(rows, axisym)
            tractions.append(SurfaceTraction("outer_surface", field, load.scale or ramp, name))
    return pressures, tractions


@dataclass(frozen=True)
class PolarWindow:
    lo: float
    hi: float

    def __call__(self, x: NDArray) -> NDArray:
        theta = polar_deg(x)
        return (theta >= self.lo) & (theta <= self.hi)


def inertia_relief(body: Body, vectors: list[tuple[str, NDArray, Callable]]) -> list[BodyForce]:
    """One body force per load that balances its resultant and moment (about the centre) at
    scale 1 on the reference configuration (see :mod:`.loads`)."""
    axisym = bool(body.axisym)
    X = body.ubasis.doflocs
    split = body.ubasis.split_indices()

    def wrench(f: NDArray) -> NDArray:
        fx, fy = f[split[0]], f[split[1]]
        moment = np.sum(X[0, split[0]] * fy - X[1, split[0]] * fx)
        return np.array([fx.sum(), fy.sum(), moment])

    modes = [lambda x: np.stack([np.zeros_like(x[0]), np.ones_like(x[0])])]
    if not axisym:
        modes = [
            lambda x: np.stack([np.ones_like(x[0]), np.zeros_like(x[0])]),
            *modes,
            lambda x: np.stack([-x[1], x[0]]),
        ]
    one = lambda _t: 1.0  # noqa: E731
    unit = np.array([wrench(dead_load_vector(body, BodyForce(m, one))) for m in modes]).T
    rows = [1] if axisym else [0, 1, 2]
    forces = []
    for name, vec, scale in vectors:
        c = np.linalg.solve(unit[rows], -wrench(vec)[rows])
        forces.append(
            BodyForce(
                lambda x, c=c: sum(ci * m(x) for ci, m in zip(c, modes, strict=True)),
                scale,
                name=f"inertia:{name}",
            )
        )
    return forces
