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
from scipy.interpolate import CubicSpline

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
            scale = load.scale or ramp
            if load.follower:
                rows, normal = split_normal(rows)
                pressures.append(FollowerPressure("outer_surface", scale, normal, name))
            field = TractionField(rows, axisym)
            tractions.append(SurfaceTraction("outer_surface", field, scale, name))
    return pressures, tractions


class PolarPressure:
    """A pressure [kPa] by polar angle (deg from +y towards +x), a periodic cubic spline
    through the table's rows (its gradient continuous, for Newton's tangent), read at points
    ``x`` (2, ...): the ``where`` of a follower pressure of magnitude ``scale(t)``."""

    def __init__(self, theta_deg: NDArray, pressure_kPa: NDArray) -> None:
        theta = np.append(theta_deg, theta_deg[0] + 360.0)
        self._spline = CubicSpline(
            theta, np.append(pressure_kPa, pressure_kPa[0]), bc_type="periodic"
        )
        self._start = float(theta[0])

    def _at(self, x: NDArray) -> NDArray:
        return (polar_deg(x) - self._start) % 360.0 + self._start

    def __call__(self, x: NDArray) -> NDArray:
        return self._spline(self._at(x))

    def gradient(self, x: NDArray) -> NDArray:
        """``dp/dx`` (2, ...) [kPa/um]: ``dp/dtheta`` times ``grad theta = (180 / pi) (y, -x)
        / r^2`` [deg/um]."""
        r2 = x[0] ** 2 + x[1] ** 2
        return self._spline(self._at(x), 1) * np.degrees(np.stack([x[1], -x[0]]) / r2)


def split_normal(rows: NDArray) -> tuple[NDArray, PolarPressure]:
    """A traction table's rows (theta_deg, tx, ty) [kPa] split into their tangential part
    (rows of the same form) and their normal part as a pressure ``p = -T . N`` by polar
    angle (``N = (sin theta, cos theta)``, the outline's outward normal)."""
    theta = np.radians(rows[:, 0])
    n = np.column_stack([np.sin(theta), np.cos(theta)])
    p = -np.einsum("ij,ij->i", rows[:, 1:3], n)
    return np.column_stack([rows[:, 0], rows[:, 1:3] + p[:, None] * n]), PolarPressure(
        rows[:, 0], p
    )


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
