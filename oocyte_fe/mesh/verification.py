"""Meshes of the verification problems (closed-form solutions), lengths in um.

* Thick sphere / cylinder: the quarter annulus ``a <= sqrt(x^2 + y^2) <= b``, x >= 0,
  y >= 0. Axisymmetric (``spherical_shell_mesh``, x = r, y = z): boundaries ``inner``,
  ``outer``, ``axis`` (r = 0) and ``symmetry`` (z = 0). Plane strain
  (``annulus_quarter_mesh``): ``inner``, ``outer``, ``left`` (x = 0) and ``bottom`` (y = 0).
* Block / half-space: the rectangle [0, w] x [0, h] with boundaries ``left``, ``right``,
  ``bottom``, ``top`` and an optional finer size within ``refine_radius_um`` of a point (for
  Hertz: the indenter tip at the top-left corner, on the axis).

Each mesh has the single subdomain ``body``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import gmsh
import skfem

from oocyte_fe.errors import InputError
from oocyte_fe.mesh import validate
from oocyte_fe.mesh.cache import cached_mesh
from oocyte_fe.mesh.gmsh_session import add_physical, distance_to_point, refine_near


@dataclass(frozen=True)
class QuarterAnnulus:
    """Quarter annulus between radii ``inner_um`` < ``outer_um``, element size ``size_um``."""

    inner_um: float
    outer_um: float
    size_um: float
    order: int = 1
    form: Literal["axisymmetric", "plane_strain"] = "axisymmetric"

    def __post_init__(self) -> None:
        src = "QuarterAnnulus"
        validate.positive(src, "inner_um", self.inner_um)
        validate.positive(src, "outer_um", self.outer_um)
        validate.positive(src, "size_um", self.size_um)
        validate.element_order(src, self.order)
        validate.one_of(src, "form", self.form, ("axisymmetric", "plane_strain"))
        if self.outer_um <= self.inner_um:
            raise InputError(src, "outer_um", f"> inner_um = {self.inner_um:g}", self.outer_um)
        if self.size_um > self.outer_um - self.inner_um:
            raise InputError(
                src, "size_um", "<= the wall thickness outer_um - inner_um", self.size_um
            )


def _build_annulus(geom: QuarterAnnulus) -> float:
    geo = gmsh.model.geo
    a, b = geom.inner_um, geom.outer_um
    centre = geo.addPoint(0.0, 0.0, 0.0)
    pa, pb = geo.addPoint(a, 0.0, 0.0), geo.addPoint(b, 0.0, 0.0)
    qb, qa = geo.addPoint(0.0, b, 0.0), geo.addPoint(0.0, a, 0.0)
    bottom = geo.addLine(pa, pb)
    outer = geo.addCircleArc(pb, centre, qb)
    left = geo.addLine(qb, qa)
    inner = geo.addCircleArc(qa, centre, pa)
    body = geo.addPlaneSurface([geo.addCurveLoop([bottom, outer, left, inner])])
    geo.synchronize()
    axi = geom.form == "axisymmetric"
    add_physical(2, [body], "body")
    add_physical(1, [inner], "inner")
    add_physical(1, [outer], "outer")
    add_physical(1, [left], "axis" if axi else "left")
    add_physical(1, [bottom], "symmetry" if axi else "bottom")
    return geom.size_um


def spherical_shell_mesh(
    inner_um: float, outer_um: float, size_um: float, order: int = 1
) -> skfem.Mesh:
    """Axisymmetric quarter section of a thick sphere (x = r, y = z); boundaries ``inner``,
    ``outer``, ``axis`` (r = 0), ``symmetry`` (z = 0); subdomain ``body``."""
    geom = QuarterAnnulus(inner_um, outer_um, size_um, order, "axisymmetric")
    return cached_mesh(geom, order, lambda: _build_annulus(geom))


def annulus_quarter_mesh(
    inner_um: float, outer_um: float, size_um: float, order: int = 1
) -> skfem.Mesh:
    """Plane-strain quarter of a thick cylinder; boundaries ``inner``, ``outer``, ``left``
    (x = 0), ``bottom`` (y = 0); subdomain ``body``."""
    geom = QuarterAnnulus(inner_um, outer_um, size_um, order, "plane_strain")
    return cached_mesh(geom, order, lambda: _build_annulus(geom))


@dataclass(frozen=True)
class Block:
    """Rectangle [0, width_um] x [0, height_um], optionally refined near ``refine_point``."""

    width_um: float
    height_um: float
    size_um: float
    refine_point: tuple[float, float] | None = None
    refine_size_um: float | None = None
    refine_radius_um: float | None = None
    order: int = 1

    def __post_init__(self) -> None:
        src = "Block"
        validate.positive(src, "width_um", self.width_um)
        validate.positive(src, "height_um", self.height_um)
        validate.positive(src, "size_um", self.size_um)
        validate.element_order(src, self.order)
        if self.size_um > min(self.width_um, self.height_um):
            raise InputError(src, "size_um", "<= min(width_um, height_um)", self.size_um)
        if (self.refine_point is None) != (self.refine_size_um is None):
            raise InputError(
                src,
                "refine_point/refine_size_um",
                "both given or both omitted",
                (self.refine_point, self.refine_size_um),
            )
        if self.refine_point is not None:
            x, y = self.refine_point
            if not (0.0 <= x <= self.width_um and 0.0 <= y <= self.height_um):
                raise InputError(src, "refine_point", "a point of the rectangle", self.refine_point)
            validate.positive(src, "refine_size_um", self.refine_size_um)
            if self.refine_size_um > self.size_um:
                raise InputError(
                    src, "refine_size_um", f"<= size_um = {self.size_um:g}", self.refine_size_um
                )
        if self.refine_radius_um is not None:
            validate.positive(src, "refine_radius_um", self.refine_radius_um)


def _build_block(geom: Block) -> float:
    geo = gmsh.model.geo
    w, h = geom.width_um, geom.height_um
    corners = [geo.addPoint(x, y, 0.0) for x, y in ((0, 0), (w, 0), (w, h), (0, h))]
    bottom, right, top, left = (geo.addLine(corners[k], corners[(k + 1) % 4]) for k in range(4))
    body = geo.addPlaneSurface([geo.addCurveLoop([bottom, right, top, left])])
    geo.synchronize()
    add_physical(2, [body], "body")
    for name, curve in (("left", left), ("right", right), ("bottom", bottom), ("top", top)):
        add_physical(1, [curve], name)
    if geom.refine_point is not None:
        radius = geom.refine_radius_um or 10.0 * geom.refine_size_um
        refine_near(
            distance_to_point(*geom.refine_point), geom.size_um, geom.refine_size_um, radius
        )
    return geom.size_um


def block_mesh(
    width_um: float,
    height_um: float,
    size_um: float,
    refine_point: tuple[float, float] | None = None,
    refine_size_um: float | None = None,
    order: int = 1,
    refine_radius_um: float | None = None,
) -> skfem.Mesh:
    """Rectangle [0, width_um] x [0, height_um] with boundaries ``left``, ``right``,
    ``bottom``, ``top`` and subdomain ``body``; size ``refine_size_um`` within
    ``refine_radius_um`` (default 10 ``refine_size_um``) of ``refine_point``, graded to
    ``size_um``."""
    geom = Block(
        width_um,
        height_um,
        size_um,
        None if refine_point is None else tuple(map(float, refine_point)),
        refine_size_um,
        refine_radius_um,
        order,
    )
    return cached_mesh(geom, order, lambda: _build_block(geom))
