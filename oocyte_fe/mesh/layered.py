"""The layered oocyte: a cytoplasm of radius ``Rc`` inside a zona pellucida (ZP) shell of
thickness ``t`` (seed 001, Section 2.3 and Table 1: Rc = 75 um, t = 15 um).

Two forms, coordinates in um:

* ``axisymmetric``: the half-section ``r >= 0`` of the sphere in the r-z plane, x = r the
  radial coordinate and y = z the axis; boundaries ``outer_surface`` (r^2 + z^2 = (Rc+t)^2),
  ``interface`` (r^2 + z^2 = Rc^2, interior facets) and ``axis`` (r = 0, both layers).
* ``plane_strain``: the full disc in the x-y plane; boundaries ``outer_surface`` and
  ``interface``. The centre is a mesh node (handy to pin rigid-body motion).

Subdomains ``cytoplasm`` and ``zona``. The layers share the nodes of the interface (bonded,
Table 1). The centre sits at ``(0, centre_offset_um)``. An optional finer size
``refine_size_um`` applies within ``refine_depth_um`` of the outer-surface arc whose polar
angle ``theta`` (from the +y axis, i.e. +z, towards +x) lies in ``refine_polar_deg``; in
plane strain the window is mirrored about the y axis. Points of the surface are
``(R sin theta, z0 + R cos theta)``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal

import gmsh
import numpy as np
import skfem

from oocyte_fe.errors import InputError
from oocyte_fe.mesh import validate
from oocyte_fe.mesh.cache import cached_mesh
from oocyte_fe.mesh.gmsh_session import add_physical, distance_to_curves, refine_near

SIGNIFICANT = 7
"""Significant digits of the lengths and angles gmsh is given (:func:`drawn`)."""
SUBDOMAINS = ("cytoplasm", "zona")
BOUNDARIES = {
    "axisymmetric": ("outer_surface", "interface", "axis"),
    "plane_strain": ("outer_surface", "interface"),
}


@dataclass(frozen=True)
class LayeredOocyte:
    """Geometry and mesh parameters of the layered oocyte (lengths in um)."""

    cytoplasm_radius_um: float = 75.0
    zona_thickness_um: float = 15.0
    form: Literal["axisymmetric", "plane_strain"] = "axisymmetric"
    size_um: float = 5.0
    refine_polar_deg: tuple[float, float] | None = None
    refine_size_um: float | None = None
    refine_depth_um: float | None = None
    order: int = 1
    centre_offset_um: float = 0.0
    refine_windows_deg: tuple[tuple[float, float], ...] = ()

    """``refine_windows_deg``: further polar windows refined like ``refine_polar_deg`` (needs
    ``refine_size_um``), e.g. both poles of a cell between plates. ``zona_thickness_um = 0``
    is a homogeneous cell: subdomain ``cytoplasm`` only, no ``interface``."""

    def __post_init__(self) -> None:
        src = "LayeredOocyte"
        validate.positive(src, "cytoplasm_radius_um", self.cytoplasm_radius_um)
        if not self.zona_thickness_um >= 0:  # NaN refused too
            raise InputError(src, "zona_thickness_um", ">= 0 um", self.zona_thickness_um)
        validate.positive(src, "size_um", self.size_um)
        validate.one_of(src, "form", self.form, tuple(BOUNDARIES))
        validate.element_order(src, self.order)
        if self.size_um > self.cytoplasm_radius_um / 2:
            raise InputError(
                src,
                "size_um",
                f"<= cytoplasm_radius_um / 2 = {self.cytoplasm_radius_um / 2:g}",
                self.size_um,
            )
        if not np.isfinite(self.centre_offset_um):
            raise InputError(src, "centre_offset_um", "a finite number", self.centre_offset_um)
        if (self.refine_polar_deg is None) != (self.refine_size_um is None):
            raise InputError(
                src,
                "refine_polar_deg/refine_size_um",
                "both given or both omitted",
                (self.refine_polar_deg, self.refine_size_um),
            )
        if self.refine_polar_deg is not None:
            lo, hi = self.refine_polar_deg
            if not 0.0 <= lo < hi <= 180.0:
                raise InputError(
                    src,
                    "refine_polar_deg",
                    "(lo, hi) with 0 <= lo < hi <= 180 deg",
                    self.refine_polar_deg,
                )
            validate.positive(src, "refine_size_um", self.refine_size_um)
            if self.refine_size_um > self.size_um:
                raise InputError(
                    src, "refine_size_um", f"<= size_um = {self.size_um:g}", self.refine_size_um
                )
        for lo, hi in self.refine_windows_deg:
            if not 0.0 <= lo < hi <= 180.0 or self.refine_size_um is None:
                raise InputError(
                    src,
                    "refine_windows_deg",
                    "(lo, hi) windows with 0 <= lo < hi <= 180 deg and refine_size_um",
                    self.refine_windows_deg,
                )
        if self.refine_depth_um is not None:
            validate.positive(src, "refine_depth_um", self.refine_depth_um)

    @property
    def outer_radius_um(self) -> float:
        """Outer radius of the ZP, ``Rc + t`` (um)."""
        return self.cytoplasm_radius_um + self.zona_thickness_um


def _windows(geom: LayeredOocyte) -> list[tuple[float, float]]:
    first = [geom.refine_polar_deg] if geom.refine_polar_deg is not None else []
    return first + list(geom.refine_windows_deg)


def _angles(geom: LayeredOocyte) -> np.ndarray:
    """Polar angles (deg) of the points splitting each circle into arcs of <= 90 deg."""
    full = 180.0 if geom.form == "axisymmetric" else 360.0
    angles = list(np.arange(0.0, full + 1e-9, 90.0))
    for lo, hi in _windows(geom):
        angles += [lo, hi] if geom.form == "axisymmetric" else [lo, hi, 360 - lo, 360 - hi]
    angles = np.unique(np.round(angles, 9))
    return angles if geom.form == "axisymmetric" else angles[angles < 360.0]


def _build(geom: LayeredOocyte) -> float:
    """Add the layered geometry and groups to the current gmsh model; return the size."""
    geo = gmsh.model.geo
    z0 = geom.centre_offset_um
    angles = _angles(geom)
    rad = np.radians(angles)
    centre = geo.addPoint(0.0, z0, 0.0)

    def circle(radius: float) -> tuple[list[int], list[int]]:
        pts = [geo.addPoint(radius * np.sin(a), z0 + radius * np.cos(a), 0.0) for a in rad]
        n = len(pts) - 1 if geom.form == "axisymmetric" else len(pts)
        # arc k runs counter-clockwise, from angle k+1 back to angle k
        arcs = [geo.addCircleArc(pts[(k + 1) % len(pts)], centre, pts[k]) for k in range(n)]
        return pts, arcs

    layered = geom.zona_thickness_um > 0.0  # else a homogeneous cell: one region, no interface
    if layered:
        p_in, c_in = circle(geom.cytoplasm_radius_um)
    p_out, c_out = circle(geom.outer_radius_um)
    if not layered:
        p_in, c_in = p_out, c_out
    axis: list[int] = []
    if geom.form == "axisymmetric":
        if layered:
            top = geo.addLine(p_out[0], p_in[0])
        upper = geo.addLine(p_in[0], centre)
        lower = geo.addLine(centre, p_in[-1])
        axis = [upper, lower]
        if layered:
            bottom = geo.addLine(p_in[-1], p_out[-1])
            axis = [top, upper, lower, bottom]
        cyto_loop = geo.addCurveLoop([upper, lower, *reversed(c_in)])
        if layered:
            zona_loop = geo.addCurveLoop([top, *(-c for c in c_in), bottom, *reversed(c_out)])
        cyto = geo.addPlaneSurface([cyto_loop])
        if layered:
            zona = geo.addPlaneSurface([zona_loop])
    else:
        cyto_loop = geo.addCurveLoop(list(reversed(c_in)))
        if layered:
            zona_loop = geo.addCurveLoop(list(reversed(c_out)))
        cyto = geo.addPlaneSurface([cyto_loop])
        if layered:
            zona = geo.addPlaneSurface([zona_loop, cyto_loop])
    geo.synchronize()
    if geom.form == "plane_strain":
        gmsh.model.mesh.embed(0, [centre], 2, cyto)

    add_physical(2, [cyto], "cytoplasm")
    if layered:
        add_physical(2, [zona], "zona")
    add_physical(1, c_out, "outer_surface")
    if layered:
        add_physical(1, c_in, "interface")
    if axis:
        add_physical(1, axis, "axis")

    if _windows(geom):
        bounds = angles if geom.form == "axisymmetric" else np.append(angles, 360.0)
        mids = 0.5 * (bounds[:-1] + bounds[1:])
        folded = np.minimum(mids, 360.0 - mids)
        window = [
            c
            for c, m in zip(c_out, folded, strict=True)
            if any(lo <= m <= hi for lo, hi in _windows(geom))
        ]
        depth = geom.refine_depth_um or geom.zona_thickness_um
        refine_near(distance_to_curves(window), geom.size_um, geom.refine_size_um, depth)
    return geom.size_um


def _significant(value: object) -> object:
    if isinstance(value, float):
        return float(f"{value:.{SIGNIFICANT}g}")
    if isinstance(value, tuple):
        return tuple(_significant(v) for v in value)
    return value


def drawn(geom: LayeredOocyte) -> LayeredOocyte:
    """The parameters gmsh meshes: every length and angle of ``geom`` rounded to
    :data:`SIGNIFICANT` significant digits (a relative change of 5e-7 at most).

    gmsh's mesh is not continuous in its inputs: a radius or a size changed by a relative 1e-9
    gives another mesh (nodes renumbered and moved by up to half an element), so a figure that
    depends on the mesh at the level of its discretisation error (a small difference of two
    displacements, say) moved with the round-off of an input. Rounded, such inputs draw the
    same mesh; what another mesh does is the subject of a mesh study, not of round-off."""
    changed = {f.name: _significant(getattr(geom, f.name)) for f in dataclasses.fields(geom)}
    return dataclasses.replace(geom, **changed)


def layered_oocyte_mesh(geom: LayeredOocyte) -> skfem.Mesh:
    """The mesh of ``geom`` (``MeshTri1``, or ``MeshTri2`` with curved edges for order 2),
    with subdomains ``cytoplasm``, ``zona`` and boundaries ``outer_surface``, ``interface``
    (and ``axis`` in the axisymmetric form); built with gmsh once, then read from the cache.
    The mesh is drawn for :func:`drawn` (``geom`` rounded to 7 significant digits)."""
    geom = drawn(geom)
    return cached_mesh(geom, geom.order, lambda: _build(geom))
