"""Rigid tools of an experiment as FE obstacles, motions, held regions and suction masks.

Each tool is built in the frame of the ``top`` side (the cell's centre at the origin, the tool
above the pole ``(0, R)``, advancing along -y) and turned to its side by a rotation, which keeps
a polyline's solid on its left. The advance ``w(t)`` [um] moves the tool along its approach
direction ``d`` (towards the centre): ``motion(t) = w(t) d``.

Shapes (lengths um, angles deg), in the top frame with the clearance ``g`` (``gap_um``):

* plate: the line ``y = R + g``, solid above;
* sphere of radius ``Rp``: centre ``(0, R + g + Rp)``;
* cone of half angle ``alpha``: apex ``(0, R + g)``, flanks opening upwards;
* straight pipette, inner radius ``a``, wall ``w``, mouth fillet ``f``: the glass is the ring
  ``a <= r <= a + w`` above the mouth plane ``y_m``, its inner corner rounded with radius
  ``f``; ``y_m = sqrt((R + f)^2 - (a + f)^2) - f + g``, so that at ``g = 0`` the rounded corner
  touches the sphere (tangent); the surface inside the bore and ahead of the mouth is sucked;
* necked pipette (axisymmetric, its axis along +y): a bore, a cosine taper and a neck
  (:mod:`oocyte_fe.neck.pipette`), the cell ``clearance_um`` from the taper; its suction acts
  ahead of the seal the cell makes with the wall (:func:`oocyte_fe.neck.suction.seal_mask`);
* wedge pipette (plane strain): a flat tip of width ``b`` at ``(0, R + g)``, flanks at the
  included angle, its two mouth edges rounded with ``edge_radius_um`` (polyline arcs);
* a pipette's ``fixed`` seal: the outer-surface facets under its end face are held along its
  axis (Theret's rigid annular punch); the rest of the glass acts by contact;
* holding pipette: no obstacle; the outer-surface facets within ``half_width`` of its axis on
  its side are fixed (bonded), picked among the ``outer_surface`` facets only, so that no facet
  of the symmetry axis or the interior can be caught, however wide the window.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from oocyte_fe.experiment.description import (
    Cone,
    HoldingPipette,
    NeckedPipette,
    Plate,
    Sphere,
    StraightPipette,
    WedgePipette,
    neck_geometry,
)
from oocyte_fe.fe.obstacles import Circle, Obstacle, Polyline, wedge_tip
from oocyte_fe.neck import pipette as neck

ROTATION = {
    "top": ((1.0, 0.0), (0.0, 1.0)),
    "right": ((0.0, 1.0), (-1.0, 0.0)),  # -90 deg
    "bottom": ((-1.0, 0.0), (0.0, -1.0)),
    "left": ((0.0, -1.0), (1.0, 0.0)),  # +90 deg
}
"""Rotation taking the top frame to each side, exact (no cos(90 deg) = 6e-17 round-off)."""
ARC_SEGMENTS = 8
"""Segments of a polyline quarter circle (a pipette's rounded mouth corner)."""


def rotation(side: str) -> NDArray:
    """The 2x2 rotation from the top frame to ``side``."""
    return np.array(ROTATION[side])


def approach(side: str) -> NDArray:
    """Unit vector along which a tool on ``side`` advances (towards the centre)."""
    return rotation(side) @ np.array([0.0, -1.0])


def _turned(points: list[tuple[float, float]], side: str, name: str) -> Polyline:
    q = np.asarray(points, dtype=float) @ rotation(side).T
    return Polyline(tuple((float(x), float(y)) for x, y in q), name=name)


def mouth_height(tool: StraightPipette, radius_um: float) -> float:
    """``y_m`` of the mouth plane in the top frame (the rounded corner touches at gap 0)."""
    a, f = tool.inner_radius_um, tool.mouth_fillet_um
    return float(np.sqrt((radius_um + f) ** 2 - (a + f) ** 2) - f + tool.gap_um)


def pipette_profile(tool: StraightPipette, radius_um: float) -> list[tuple[float, float]]:
    """The glass's boundary in the top frame, down the bore, round the mouth, up the outside."""
    a, w, f, top = tool.inner_radius_um, tool.wall_um, tool.mouth_fillet_um, tool.length_um
    ym = mouth_height(tool, radius_um)
    pts = [(a, ym + top)]
    if f > 0:
        angles = np.linspace(np.pi, 1.5 * np.pi, ARC_SEGMENTS + 1)
        pts += [(a + f + f * np.cos(t), ym + f + f * np.sin(t)) for t in angles]
    else:
        pts.append((a, ym))
    pts += [(a + w, ym), (a + w, ym + top)]
    return [(float(x), float(y)) for x, y in pts]


def cone_profile(
    half_angle_deg: float, tip_radius_um: float, length_um: float, y0: float
) -> list[tuple[float, float]]:
    """Right half of a cone with its apex at ``(0, y0)``, blunted by a sphere of radius
    ``rho`` tangent to the flanks (centre ``(0, y0 + rho)``, tangent at ``r = rho cos(alpha)``)
    when ``tip_radius_um > 0``; the flank runs ``length_um`` beyond it."""
    a, rho = np.deg2rad(half_angle_deg), tip_radius_um
    if rho > 0:
        phis = np.linspace(-0.5 * np.pi, -a, ARC_SEGMENTS + 1)
        pts = [(rho * np.cos(p), y0 + rho + rho * np.sin(p)) for p in phis]
        pts[0] = (0.0, y0)
    else:
        pts = [(0.0, y0)]
    x, y = pts[-1]
    pts.append((x + length_um * np.sin(a), y + length_um * np.cos(a)))
    return [(float(px), float(py)) for px, py in pts]


def obstacle(tool: object, name: str, radius_um: float, axisym: bool) -> Obstacle | None:
    """The rigid obstacle of a tool at t = 0 (``None`` for a holding pipette)."""
    R = radius_um
    if isinstance(tool, HoldingPipette):
        return None
    y0 = R + tool.gap_um
    if isinstance(tool, Plate):  # wider than the cell on both sides, whatever the side
        return _turned([(-2.0 * R, y0), (2.0 * R, y0)], tool.side, name)
    if isinstance(tool, Sphere):
        centre = rotation(tool.side) @ np.array([0.0, y0 + tool.radius_um])
        return Circle((float(centre[0]), float(centre[1])), tool.radius_um, name=name)
    if isinstance(tool, Cone):
        right = cone_profile(tool.half_angle_deg, tool.tip_radius_um, tool.length_um, y0)
        left = [(-x, y) for x, y in reversed(right) if x > 0.0]
        return _turned(right if axisym else left + right, tool.side, name)
    if isinstance(tool, StraightPipette):
        return _turned(pipette_profile(tool, R), tool.side, name)
    if isinstance(tool, NeckedPipette):
        return necked_pipette(tool, R).obstacle()
    if isinstance(tool, WedgePipette):
        wedge = wedge_tip(
            (0.0, y0),
            (0.0, -1.0),
            tool.width_um,
            tool.tip_angle_deg,
            tool.length_um,
            tool.edge_radius_um,
        )
        return _turned(list(wedge.points), tool.side, name)
    raise TypeError(f"unknown tool {type(tool).__name__}")


def motion(tool: object) -> Callable[[float], tuple[float, float]]:
    """Rigid translation ``w(t) d`` [um] of a tool (still without a displacement path); for a
    holding pipette, the displacement of the surface it holds."""
    d = approach(tool.side)
    path = getattr(tool, "displacement_um", None)

    def move(t: float) -> tuple[float, float]:
        w = 0.0 if path is None else path(t)
        return (float(w * d[0]), float(w * d[1]))

    return move


def held_facets(tool: HoldingPipette, midpoints: NDArray, radius_um: float) -> NDArray:
    """Mask of outer-surface facets (midpoints (2, nf)) held by a holding pipette: within
    ``half_width_um`` of its axis, or beyond the cap plane ``R cos(cap_deg)`` (less 1e-9 R)."""
    local = rotation(tool.side).T @ midpoints  # back to the top frame: the pipette above
    if tool.cap_deg is not None:
        return local[1] > radius_um * np.cos(np.deg2rad(tool.cap_deg)) - 1e-9 * radius_um
    return (np.abs(local[0]) <= tool.half_width_um) & (local[1] > 0.0)


def necked_pipette(tool: NeckedPipette, radius_um: float) -> neck.NeckedPipette:
    """The necked pipette placed ``clearance_um`` from a cell of ``radius_um`` at the origin."""
    return neck_geometry(tool).touching(radius_um, tool.clearance_um)


def sealed_facets(tool: StraightPipette, midpoints: NDArray) -> NDArray:
    """Mask of outer-surface facets under a pipette's end face (``a + f <= r <= a + w``)."""
    local = rotation(tool.side).T @ midpoints
    r = np.abs(local[0])
    inner = tool.inner_radius_um + tool.mouth_fillet_um
    return (r >= inner) & (r <= tool.inner_radius_um + tool.wall_um) & (local[1] > 0.0)


@dataclass(frozen=True)
class SuctionMask:
    """Points of the current surface inside a pipette's bore and ahead of its mouth plane."""

    tool: StraightPipette
    radius_um: float

    def __call__(self, x: NDArray) -> NDArray:
        local = np.einsum("ij,j...->i...", rotation(self.tool.side).T, x)
        ym = mouth_height(self.tool, self.radius_um)
        return (np.abs(local[0]) < self.tool.inner_radius_um) & (local[1] > ym)
