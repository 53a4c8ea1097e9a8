"""Rigid analytic obstacles in the section plane: signed distance ``g(x)`` and normal ``n(x)``.

Every obstacle is a curve of the (x, y) / (R, Z) plane; in axisymmetry it is revolved about the
Z axis (a polyline becomes a pipette wall, a cone or a plate, a circle centred on the axis a
sphere). ``g > 0`` on the free side, ``g < 0`` inside the obstacle; ``n = grad g`` is the unit
normal pointing away from the obstacle. A polyline's solid lies on the *left* of its direction
of travel. Lengths in um.

``distance_curvature`` also returns the curvature ``kappa`` [1/um] of the level set through
``x``: ``dn/dx = kappa t t^T`` with ``t = (-n_2, n_1)`` (the Hessian of ``g``). It is 0 on a
polyline's faces, ``1/g`` where the nearest point is a vertex (``n`` turns about it) and
``1/(g + R)`` for a circle; the contact tangent uses it (:mod:`~oocyte_fe.fe.contact`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class Polyline:
    """Rigid boundary through ``points`` (k, 2), solid on the left of the direction of travel."""

    points: tuple[tuple[float, float], ...]
    name: str = "obstacle"

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise InputError(self.name, "points", "at least two (x, y) points", got=self.points)
        if np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) <= 0):
            raise InputError(self.name, "points", "distinct consecutive points")

    def distance(self, x: NDArray) -> tuple[NDArray, NDArray]:
        """Signed distance ``g`` (...) and unit normal ``n`` (2, ...) at points ``x`` (2, ...)."""
        return self.distance_curvature(x)[:2]

    def distance_curvature(self, x: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """``g``, ``n`` and the level-set curvature ``kappa`` (...) [1/um] at ``x`` (2, ...)."""
        pts = np.asarray(self.points, dtype=float)
        a, b = pts[:-1], pts[1:]  # (s, 2)
        d = b - a
        seg_n = np.stack([d[:, 1], -d[:, 0]], axis=1) / np.linalg.norm(d, axis=1)[:, None]
        xf = x.reshape(2, -1).T  # (m, 2)
        rel = xf[:, None, :] - a[None, :, :]  # (m, s, 2)
        t = np.clip(np.einsum("msk,sk->ms", rel, d) / np.einsum("sk,sk->s", d, d), 0.0, 1.0)
        closest = a[None] + t[..., None] * d[None]
        diff = xf[:, None, :] - closest
        dist = np.linalg.norm(diff, axis=2)
        k = np.argmin(dist, axis=1)
        m = np.arange(len(xf))
        dk, tk, diffk = dist[m, k], t[m, k], diff[m, k]
        # normal: segment normal in a segment's interior; vertex pseudo-normal at its ends
        normal = seg_n[k].copy()
        at_start = (tk <= 0.0) & (k > 0)
        at_end = (tk >= 1.0) & (k < len(d) - 1)
        normal[at_start] = seg_n[k[at_start]] + seg_n[k[at_start] - 1]
        normal[at_end] = seg_n[k[at_end]] + seg_n[k[at_end] + 1]
        sign = np.where(np.einsum("mk,mk->m", diffk, normal) >= 0.0, 1.0, -1.0)
        vertex = (tk <= 0.0) | (tk >= 1.0)
        safe = dk > 1e-12
        n = np.where(
            (vertex & safe)[:, None], sign[:, None] * diffk / np.where(safe, dk, 1)[:, None], normal
        )
        n /= np.linalg.norm(n, axis=1)[:, None]
        g = sign * dk
        kappa = np.where(vertex & safe, 1.0 / np.where(safe, g, 1.0), 0.0)
        shape = x.shape[1:]
        return g.reshape(shape), n.T.reshape(x.shape), kappa.reshape(shape)


@dataclass(frozen=True)
class Circle:
    """Rigid disc (plane strain) or sphere centred on the axis (axisymmetric), radius [um]."""

    center: tuple[float, float]
    radius: float
    name: str = "sphere"

    def __post_init__(self) -> None:
        if self.radius <= 0:
            raise InputError(self.name, "radius", "a positive radius", got=self.radius)

    def distance(self, x: NDArray) -> tuple[NDArray, NDArray]:
        return self.distance_curvature(x)[:2]

    def distance_curvature(self, x: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        rel = x - np.asarray(self.center, dtype=float).reshape((2,) + (1,) * (x.ndim - 1))
        r = np.linalg.norm(rel, axis=0)
        safe = np.where(r > 0, r, 1.0)
        return r - self.radius, rel / safe, np.where(r > 0, 1.0 / safe, 0.0)


@dataclass(frozen=True)
class Linearised:
    """The contact of small-strain theory with a rigid tool advancing along ``axis`` (unit):
    the gap is measured along the axis from the tool's front at the point's lateral position
    ``s = x . e`` (``e`` the axis turned by +90 deg), and the normal is the axis::

        g(x) = x . a - f(s),    n = a,    kappa = 0

    ``f(s)`` the foremost point of ``tool`` along ``a`` on the line of lateral position ``s``
    (``g = +inf`` where the line misses the tool). With the point taken at ``X + (u . a) a``
    (the lateral displacement left out, :func:`~oocyte_fe.fe.contact.evaluate`) this is the
    boundary condition of Sneddon's and Hertz's solutions: ``u . a >= f(X . e) - X . a``, a
    pressure along the axis.
    """

    tool: Polyline | Circle
    axis: tuple[float, float]
    name: str = "tool"

    def __post_init__(self) -> None:
        if not np.isclose(np.hypot(*self.axis), 1.0):
            raise InputError(self.name, "axis", "a unit vector", got=self.axis)

    def front(self, s: NDArray) -> NDArray:
        """``f(s)`` [um]: the tool's foremost coordinate along the axis at lateral ``s``."""
        a = np.asarray(self.axis, dtype=float)
        e = np.array([-a[1], a[0]])
        if isinstance(self.tool, Circle):
            c = np.asarray(self.tool.center, dtype=float)
            h2 = self.tool.radius**2 - (s - c @ e) ** 2
            return np.where(h2 >= 0.0, c @ a + np.sqrt(np.maximum(h2, 0.0)), -np.inf)
        pts = np.asarray(self.tool.points, dtype=float)
        lat, ax = pts @ e, pts @ a
        out = np.full(np.shape(s), -np.inf)
        for s0, s1, t0, t1 in zip(lat[:-1], lat[1:], ax[:-1], ax[1:], strict=True):
            on = (s >= min(s0, s1)) & (s <= max(s0, s1))
            if s1 == s0:  # a segment along the axis: its foremost end
                here = np.full(np.shape(s), max(t0, t1))
            else:
                here = t0 + (s - s0) / (s1 - s0) * (t1 - t0)
            out = np.where(on, np.maximum(out, here), out)
        return out

    def distance(self, x: NDArray) -> tuple[NDArray, NDArray]:
        return self.distance_curvature(x)[:2]

    def distance_curvature(self, x: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        a = np.asarray(self.axis, dtype=float).reshape((2,) + (1,) * (x.ndim - 1))
        e = np.stack([-a[1], a[0]])
        s = np.sum(x * e, axis=0)
        g = np.sum(x * a, axis=0) - self.front(s)
        n = np.broadcast_to(a, x.shape).copy()
        return g, n, np.zeros_like(g)


Obstacle = Polyline | Circle | Linearised


def flat_plate(y: float, x_min: float, x_max: float, below: bool = True) -> Polyline:
    """A plate with its surface at height ``y``: solid below (``below``) or above it."""
    pts = ((x_max, y), (x_min, y)) if below else ((x_min, y), (x_max, y))
    return Polyline(pts, name="plate")


def cone_indenter(apex: tuple[float, float], half_angle_deg: float, length: float) -> Polyline:
    """Axisymmetric cone, apex on the axis pointing down (-Z), solid above its flank."""
    a = np.deg2rad(half_angle_deg)
    top = (apex[0] + length * np.sin(a), apex[1] + length * np.cos(a))
    return Polyline((apex, (float(top[0]), float(top[1]))), name="cone")


def rounded_corners(
    points: list[tuple[float, float]], radius: float, segments_per_quarter: int = 8
) -> list[tuple[float, float]]:
    """The polyline ``points`` with every interior vertex replaced by a circular arc of
    ``radius`` [um] tangent to both of its segments (``ceil(segments_per_quarter * turn /
    90 deg)`` chords, their ends on the arc). A vertex of interior angle ``2 beta`` gives up
    ``radius / tan(beta)`` of each segment; a segment too short for that is refused; a vertex
    where the polyline runs straight on is kept."""
    p = np.asarray(points, dtype=float)
    out = [p[0]]
    cut = np.zeros(len(p))  # length each vertex takes from its segments
    arcs: list[tuple[np.ndarray, ...] | None] = []
    for i in range(1, len(p) - 1):
        u = (p[i - 1] - p[i]) / np.linalg.norm(p[i - 1] - p[i])
        w = (p[i + 1] - p[i]) / np.linalg.norm(p[i + 1] - p[i])
        if u @ w < -1.0 + 1e-12:  # straight on: nothing to round
            arcs.append(None)
            continue
        beta = 0.5 * np.arccos(np.clip(u @ w, -1.0, 1.0))  # half the interior angle
        cut[i] = radius / np.tan(beta)
        bisector = (u + w) / np.linalg.norm(u + w)
        arcs.append((p[i] + u * cut[i], p[i] + w * cut[i], p[i] + bisector * radius / np.sin(beta)))
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    if np.any(cut[:-1] + cut[1:] > seg):
        raise InputError("polyline", "radius", "arcs that fit on the segments", got=radius)
    for vertex, arc in zip(p[1:-1], arcs, strict=True):
        if arc is None:
            out.append(vertex)
            continue
        start, end, c = arc
        a0 = np.arctan2(*(start - c)[::-1])
        turn = (np.arctan2(*(end - c)[::-1]) - a0 + np.pi) % (2.0 * np.pi) - np.pi
        n = max(1, int(np.ceil(segments_per_quarter * abs(turn) / (0.5 * np.pi) - 1e-9)))
        angles = a0 + turn * np.arange(n + 1) / n
        out += list(c + radius * np.stack([np.cos(angles), np.sin(angles)], axis=1))
    out.append(p[-1])
    return [(float(x), float(y)) for x, y in out]


def largest_edge_radius(width: float, angle_deg: float) -> float:
    """The radius [um] beyond which the two rounded mouth edges of :func:`wedge_tip` (mouth
    ``width``, included angle ``angle_deg``) no longer fit the mouth: each edge, of interior
    angle ``90 deg + angle_deg / 2``, takes ``r / tan(45 deg + angle_deg / 4)`` of its half."""
    return float(0.5 * width * np.tan(np.deg2rad(45.0 + 0.25 * angle_deg)))


def wedge_tip(
    tip: tuple[float, float],
    direction: tuple[float, float],
    width: float,
    angle_deg: float,
    length: float,
    edge_radius: float = 0.0,
) -> Polyline:
    """Plane-strain wedge micropipette: flat tip of ``width`` [um] centred at ``tip``, advancing
    along ``direction``, flanks opening at the full ``angle_deg`` behind it; with
    ``edge_radius`` > 0 [um] the two mouth edges are rounded (:func:`rounded_corners`)."""
    d = np.asarray(direction, dtype=float)
    d /= np.linalg.norm(d)
    side = np.array([-d[1], d[0]])
    c = np.asarray(tip, dtype=float)
    half = np.tan(np.deg2rad(angle_deg) / 2.0)
    p1 = c + side * width / 2
    p2 = c - side * width / 2
    b1 = p1 - d * length + side * length * half
    b2 = p2 - d * length - side * length * half
    pts = [(float(p[0]), float(p[1])) for p in (b2, p2, p1, b1)]  # solid on the left
    if edge_radius > 0:
        pts = rounded_corners(pts, edge_radius)
    return Polyline(tuple(pts), name="wedge")


def necked_pipette_wall(profile: list[tuple[float, float]], name: str = "pipette") -> Polyline:
    """Inner wall of an axisymmetric pipette, ``profile`` = [(R, Z), ...] in order of increasing
    Z; the body lives at ``R`` below the wall (inside the bore), the glass outside it."""
    z = [p[1] for p in profile]
    if any(b <= a for a, b in zip(z, z[1:], strict=False)):
        raise InputError(name, "profile", "points with increasing Z")
    # travelling towards -Z, the solid (glass, larger R) is on the left
    return Polyline(tuple((float(r), float(zz)) for r, zz in reversed(profile)), name=name)
