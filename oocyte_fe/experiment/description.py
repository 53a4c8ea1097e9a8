"""An FE experiment on a layered cell, declared as data (``case.toml`` ``[inputs]``).

One description serves every experiment a micromanipulation lab runs on an oocyte: the cell
(outer diameter, ZP thickness, a material per layer, mesh), the material points to follow, the
rigid tools with their paths or loads, the time path and what to record. Every part is named
once (tools by their table name) and validated where it enters, relations between fields
included (a ZP thicker than the cell's radius, a point outside the cell, a pipette wider than
the cell, a path shorter than the experiment). Units: um, s, kPa; ``_Pa`` fields are
converted to kPa here, at the file boundary.

Coordinates: the cell's centre at the origin; ``axisymmetric`` is the half-section ``x = r >= 0``
about the ``y = z`` axis, ``plane_strain`` the full disc. A tool sits on one ``side`` of the
cell (``top``: above it on +y, moving along -y towards the centre; ``bottom``, ``left``,
``right`` likewise); in axisymmetry only ``top`` and ``bottom`` lie on the axis.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, Discriminator, Field, Tag, model_validator

from afm.material_file import material_constants
from oocyte_fe.errors import InputError
from oocyte_fe.experiment import relations as rel
from oocyte_fe.experiment.loads import Load, TractionLoad, read_traction_table
from oocyte_fe.experiment.paths import PathSpec
from oocyte_fe.fe.material import Material, Prony, read_material_file
from oocyte_fe.fe.obstacles import largest_edge_radius
from oocyte_fe.kinds.data_templates import ZONA_MATERIAL
from oocyte_fe.neck import pipette as neck
from oocyte_fe.runner.schema import CaseInputs, DataFile, Relation, RuleBroken

Side = Literal["top", "bottom", "left", "right"]
Length = Annotated[float, Field(gt=0, le=1e4)]
Friction = Annotated[float, Field(ge=0, le=2)]
MAX_FRAMES = 10_000
"""Most output frames of an experiment (one solver step each)."""
TIME_SLACK = 1e-6
"""A path's last time or a section time up to this fraction of ``time.duration_s`` past it is
taken as ending at the duration (round-off: ``fe_afm_sphere``'s probe path and duration, each
x (1 +- 1e-9), were refused)."""
DISH_HINT = (
    " (a dish or stage the cell rests on, a tool that does not move: a holding_pipette, the "
    "bonded patch of the cell on it, with half_width_um or cap_deg)"
)
"""Said where a plate, sphere or cone has no path or never presses (a user's dish)."""
MAX_TRIANGLES = 2_000_000
"""Most triangles of a cell's estimated mesh (P2: about 8 million unknowns, beyond what the
solver meets on a workstation; the shipped cases and templates estimate below 3000). The
estimate (:meth:`Experiment.estimated_triangles`) read 0.5-1.0 times gmsh's count on the
shipped cases and 0.7-1.0 on fine meshes (uniform: 17 780 against 17 888)."""
TRIANGLES_PER_SQUARE = 2.31
"""Triangles of side ``h`` per ``h^2`` of area (equilateral: ``4 / sqrt(3)``)."""
GRADING = 0.3
"""The size field's growth per um of distance (:data:`oocyte_fe.mesh.gmsh_session.GRADING`)."""
RESOLVE = 10
"""A tool's length: at least the cell's finest element (``refine_size_um``, else
``mesh_size_um``) / RESOLVE; a smaller tool falls within one element, between two surface
nodes (a radius typed in metres, 3e-6, ran to a force of 0)."""
ADVANCE_RESOLVE = 100
"""A path's largest advance into the cell: at least the finest element / ADVANCE_RESOLVE (a
depth typed in metres, 3e-7, ran to a force of 0); looser than a tool's length, since a
small uniform press of a plate is well resolved by elements much larger than it."""
TOOL_LENGTHS = (
    "radius_um",
    "tip_radius_um",
    "length_um",
    "inner_radius_um",
    "wall_um",
    "mouth_fillet_um",
    "edge_radius_um",
    "width_um",
    "bore_diameter_um",
    "neck_diameter_um",
    "taper_length_um",
    "bore_length_um",
    "neck_length_um",
    "half_width_um",
)
"""A tool's lengths that the mesh must resolve (those left at 0 or unset are not checked:
a sharp cone, a pipette without fillet)."""


def _readable_material(path: Path) -> Path:
    try:
        read_material_file(path)
    except InputError as exc:  # pydantic names the case file and the field
        raise ValueError(f"a material file ({exc})") from None
    return path


MaterialFile = Annotated[DataFile, AfterValidator(_readable_material)]
"""A material TOML written by the AFM route (``afm.write_material``): E, nu, Prony terms."""


SHARED_CHECK = {"max_abs": 1e300}
"""The bounds of these fields are the material file's (one check, reported by its message)."""


class PronyTerms(CaseInputs):
    """Normalised relaxation terms ``G(t)/G0 = g_inf + sum g_i exp(-t/tau_i)`` (checked with
    the material they belong to, by :func:`afm.material_file.material_constants`)."""

    g: list[float] = Field(
        description="relaxation fractions g_i in [0, 1), sum(g) < 1",
        json_schema_extra=SHARED_CHECK,
    )
    tau_s: list[float] = Field(
        description="relaxation times in [1e-9, 1e9] s, as many as g",
        json_schema_extra=SHARED_CHECK,
    )


class InlineMaterial(CaseInputs):
    """A neo-Hookean layer with an optional Prony series (the seed's ANSYS model); its
    constants pass the one check of a material file
    (:func:`afm.material_file.material_constants`: E in [1e-6, 1e9] kPa, nu in [0, 0.5],
    tau in [1e-9, 1e9] s), so a number refused in a file is refused here too, in the same
    words."""

    E_kPa: float = Field(
        description="Young's modulus at t = 0, in [1e-6, 1e9] kPa", json_schema_extra=SHARED_CHECK
    )
    nu: float = Field(
        0.5,
        description="Poisson's ratio in [0, 0.5] (0.5: incompressible)",
        json_schema_extra=SHARED_CHECK,
    )
    prony: PronyTerms | None = None

    @model_validator(mode="after")
    def _constants(self) -> InlineMaterial:
        g, tau = (self.prony.g, self.prony.tau_s) if self.prony else ((), ())
        try:
            material_constants("case.toml", self.E_kPa, self.nu, g, tau)
        except InputError as exc:  # reported against the inline field (RuleBroken)
            raise RuleBroken(exc.field.removeprefix("material."), exc.expected, exc.got) from None
        return self


def _material_form(value: object) -> str:
    return "inline" if isinstance(value, dict | InlineMaterial) else "file"


LayerMaterial = Annotated[
    Annotated[MaterialFile, Tag("file")] | Annotated[InlineMaterial, Tag("inline")],
    Discriminator(
        _material_form,
        custom_error_type="material",
        custom_error_message="a material file name or an inline table {E_kPa, nu, prony}",
    ),
]
"""A layer's material: told apart by its form, so that an error names the form given."""


def to_material(spec: LayerMaterial, name: str) -> Material:
    """The FE material of a layer (a material file or inline constants)."""
    if isinstance(spec, InlineMaterial):
        prony = (
            Prony(tuple(spec.prony.g), tuple(spec.prony.tau_s), source=name)
            if spec.prony
            else Prony()
        )
        return Material(spec.E_kPa, spec.nu, prony, name=name, source=name)
    return read_material_file(spec)


def inline_table(material: Material) -> dict:
    """A FE material as the description's inline table (the same floats; the inverse of
    :func:`to_material` for inline layers)."""
    table: dict = {"E_kPa": material.E_kPa, "nu": material.nu}
    if material.prony.g:
        table["prony"] = {"g": list(material.prony.g), "tau_s": list(material.prony.tau_s)}
    return table


class Layers(CaseInputs):
    zona: LayerMaterial | None = Field(
        None, description="the ZP (needed if thicker than 0)", json_schema_extra=ZONA_MATERIAL
    )
    cytoplasm: LayerMaterial = Field(description="the cytoplasm (the whole cell without a ZP)")


class SelfContactSpec(CaseInputs):
    """Frictionless self-contact of the cell's outer surface: a ZP that folds onto itself
    (:mod:`oocyte_fe.fe.self_contact`)."""

    penalty_factor: float = Field(
        20.0, gt=0, le=1e6, description="normal penalty eps_N h / E_max (h: refine size)"
    )
    range_um: float | None = Field(
        None,
        gt=0,
        le=1e3,
        description="distance at which the surface starts to push itself off (default: h / 10)",
        json_schema_extra={"unit": "um"},
    )


class Cell(CaseInputs):
    """The cell: a cytoplasm inside a ZP shell (``zona_thickness_um = 0``: homogeneous)."""

    outer_diameter_um: float = Field(
        ge=1, le=1e4, description="the cell's outer diameter", json_schema_extra={"unit": "um"}
    )
    zona_thickness_um: float = Field(
        0.0,
        ge=0,
        le=1e4,
        description="ZP thickness (0: homogeneous)",
        json_schema_extra={"unit": "um"},
    )
    symmetry: Literal["axisymmetric", "plane_strain"] = Field(
        "axisymmetric", description="axisymmetric (about y) or plane strain"
    )
    dimension: Literal[2] = Field(2, description="2: a section (axisymmetric or plane strain)")
    materials: Layers = Field(description="a material per layer: a file or inline")
    mesh_size_um: float = Field(
        ge=0.01, le=1e3, description="element size", json_schema_extra={"unit": "um"}
    )
    refine_size_um: float | None = Field(
        None,
        ge=0.005,
        le=1e3,
        description="element size near each tool (default: mesh_size)",
        json_schema_extra={"unit": "um"},
    )
    refine_depth_um: float | None = Field(
        None,
        gt=0,
        le=1e4,
        description="depth of the refined zone below the surface",
        json_schema_extra={"unit": "um"},
    )
    curved_edges: bool = Field(
        True,
        description="quadratic elements with curved edges on the surface; false: straight "
        "(scikit-fem cannot invert curved elements much smaller than the cell, e.g. 0.1 um "
        "at an AFM tip on a 1 mm sphere)",
    )
    refine_windows_deg: list[Annotated[list[float], Field(min_length=2, max_length=2)]] | None = (
        Field(
            None,
            description="polar windows (deg from +y) to refine instead of one at each tool, "
            "e.g. [[20, 160]] along the side of a cell that passes through a pipette",
            json_schema_extra={"unit": "deg"},
        )
    )
    refine_half_angle_deg: float = Field(
        20.0,
        gt=0,
        le=90,
        description="polar half-width of the refined window at each tool",
        json_schema_extra={"unit": "deg"},
    )
    points: dict[str, Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(
        default_factory=dict,
        description="material points to follow (x, y), by name",
        json_schema_extra={"unit": "um"},
    )
    self_contact: SelfContactSpec | None = Field(
        None, description="the outer surface in frictionless contact with itself (off: none)"
    )

    rules = (
        Relation("zona_thickness_um", "<", lambda m: 0.5 * m.radius_um, "half the outer radius"),
        Relation(
            "mesh_size_um",
            "<=",
            lambda m: 0.5 * (m.radius_um - m.zona_thickness_um),
            "half the cytoplasm radius",
        ),
        Relation("refine_size_um", "<=", lambda m: m.mesh_size_um, "mesh_size_um"),
        Relation("refine_depth_um", "<", lambda m: m.radius_um, "the cell's radius"),
    )

    @property
    def radius_um(self) -> float:
        return 0.5 * self.outer_diameter_um

    @model_validator(mode="after")
    def _geometry(self) -> Cell:
        r = self.radius_um
        if self.zona_thickness_um > 0 and self.materials.zona is None:
            raise ValueError("materials.zona when zona_thickness_um > 0")
        if self.zona_thickness_um == 0 and self.materials.zona is not None:
            raise RuleBroken(
                "zona_thickness_um",
                "a ZP thickness > 0 with materials.zona (at 0 the cell is all cytoplasm and "
                "the zona material would be ignored; remove it for a homogeneous cell)",
                0.0,
            )
        for lo, hi in self.refine_windows_deg or []:
            if not 0 <= lo < hi <= 180:
                raise ValueError("refine_windows_deg: [lo, hi] with 0 <= lo < hi <= 180")
        for name, (x, y) in self.points.items():
            axisym = self.symmetry == "axisymmetric"
            if np.hypot(x, y) > r * (1 + 1e-9) or (axisym and x < 0):
                raise RuleBroken(
                    "points",
                    f"point {name!r} inside the cell (radius {r:g} um"
                    + (", x >= 0 in axisymmetry)" if axisym else ")"),
                    [x, y],
                )
        return self


class ToolBase(CaseInputs):
    side: Side = "top"
    gap_um: float = Field(0.0, ge=0, le=1e4, description="clearance to the cell at t = 0")
    friction: Friction = 0.0
    penalty_factor: float = Field(
        20.0, gt=0, le=1e6, description="normal penalty eps_N h / E_max (h: refine size)"
    )
    smoothing_um: float = Field(0.0, ge=0, le=10, description="C1 smoothing of the contact law")
    quadrature_order: int | None = Field(
        None,
        ge=2,
        le=40,
        description="Gauss order of the contact's facet quadrature (default: the body's, 4; "
        "a sharp tool corner between quadrature points is not seen)",
    )
    displacement_um: PathSpec | None = Field(
        None, description="advance towards the cell's centre (um) against time (s)"
    )


class Plate(ToolBase):
    type: Literal["plate"]


class Sphere(ToolBase):
    type: Literal["sphere"]
    radius_um: Length


class Cone(ToolBase):
    type: Literal["cone"]
    half_angle_deg: float = Field(gt=1, lt=89)
    length_um: Length = 20.0
    tip_radius_um: float = Field(
        0.0, ge=0, le=100, description="a spherically blunted apex (0: sharp; see docs/fe.md)"
    )

    @property
    def reach_um(self) -> float:
        """Depth of the flank's end below the apex [um]: ``rho (1 - sin alpha) + L cos alpha``
        (the blunting sphere's tangent point, then ``length_um`` along the flank)."""
        a, rho = np.deg2rad(self.half_angle_deg), self.tip_radius_um
        return float(rho * (1.0 - np.sin(a)) + self.length_um * np.cos(a))


class StraightPipette(ToolBase):
    type: Literal["straight_pipette"]
    inner_radius_um: Length
    wall_um: Length
    mouth_fillet_um: float = Field(0.0, ge=0, le=1e3)
    length_um: Length = 50.0
    suction_Pa: PathSpec | None = Field(
        None, description="suction (pressure drop) on the surface inside the bore, Pa"
    )
    seal: Literal["fixed", "contact"] = Field(
        "fixed",
        description="fixed: the surface under the end face held axially (Theret's rigid punch; "
        "it holds the cell); contact: the glass by contact only (hold the cell otherwise)",
    )

    rules = (Relation("mouth_fillet_um", "<", lambda m: m.wall_um, "wall_um"),)


class WedgePipette(ToolBase):
    type: Literal["wedge_pipette"]
    width_um: Length
    tip_angle_deg: float = Field(gt=0, lt=180)
    length_um: Length = 80.0
    edge_radius_um: float = Field(
        0.0,
        ge=0,
        le=1e3,
        description="the mouth's two edges rounded with this radius (0: sharp; see docs/fe.md)",
        json_schema_extra={"unit": "um"},
    )

    rules = (
        Relation(
            "edge_radius_um",
            "<",
            lambda m: largest_edge_radius(m.width_um, m.tip_angle_deg),
            "the largest that fits the mouth, width_um / 2 tan(45 deg + tip_angle_deg / 4)",
        ),
    )


class HoldingPipette(CaseInputs):
    """Holds the outer surface facing it (bonded, or along its axis only): within
    ``half_width_um`` of its axis, or a polar cap of ``cap_deg`` about its pole; it may move
    along its axis by ``displacement_um`` (a rear cap that drives the cell)."""

    type: Literal["holding_pipette"]
    side: Side = "bottom"
    half_width_um: float | None = Field(None, gt=0, le=1e4, json_schema_extra={"unit": "um"})
    cap_deg: float | None = Field(None, gt=0, lt=90, json_schema_extra={"unit": "deg"})
    components: Literal["both", "axial"] = "both"
    displacement_um: PathSpec | None = None

    @model_validator(mode="after")
    def _one_region(self) -> HoldingPipette:
        if (self.half_width_um is None) == (self.cap_deg is None):
            raise ValueError("half_width_um or cap_deg (one of them)")
        return self


class SuctionControl(CaseInputs):
    """The suction as an unknown: the net axial reaction on ``tool`` (a holding pipette with a
    displacement path) equals ``target_nN``; the suction the experiment needs is the answer."""

    tool: str = Field(min_length=1, max_length=100)
    target_nN: float = Field(0.0, ge=-1e9, le=1e9)


class NeckedPipette(ToolBase):
    """A bore narrowing through a cosine taper to a neck (``oocyte_fe.neck.pipette``), its
    axis along +y, the cell ``clearance_um`` from the taper at t = 0."""

    type: Literal["necked_pipette"]
    bore_diameter_um: Length
    neck_diameter_um: Length
    taper_length_um: Length
    bore_length_um: Length = 300.0
    neck_length_um: Length = 500.0
    taper_points: int = Field(41, ge=2, le=10_000)
    clearance_um: float = Field(0.1, ge=0, le=1e3)
    seal_tol_um: float = Field(
        0.5, gt=0, le=100, description="a surface point within this of the wall seals"
    )
    suction_Pa: PathSpec | None = None
    suction_control: SuctionControl | None = None

    rules = (Relation("neck_diameter_um", "<", lambda m: m.bore_diameter_um, "bore_diameter_um"),)

    @model_validator(mode="after")
    def _narrowing(self) -> NeckedPipette:
        if (self.suction_Pa is None) == (self.suction_control is None):
            raise ValueError("suction_Pa or suction_control (one of them)")
        return self


TOOL_TYPES = {
    "plate": Plate,
    "sphere": Sphere,
    "cone": Cone,
    "straight_pipette": StraightPipette,
    "necked_pipette": NeckedPipette,
    "wedge_pipette": WedgePipette,
    "holding_pipette": HoldingPipette,
}


def _tool_type(value: object) -> str | None:
    kind = value.get("type") if isinstance(value, dict) else getattr(value, "type", None)
    return kind if kind in TOOL_TYPES else None


Tool = Annotated[
    Annotated[Plate, Tag("plate")]
    | Annotated[Sphere, Tag("sphere")]
    | Annotated[Cone, Tag("cone")]
    | Annotated[StraightPipette, Tag("straight_pipette")]
    | Annotated[NeckedPipette, Tag("necked_pipette")]
    | Annotated[WedgePipette, Tag("wedge_pipette")]
    | Annotated[HoldingPipette, Tag("holding_pipette")],
    Discriminator(
        _tool_type,
        custom_error_type="tool_type",
        custom_error_message=f"a table with type = one of {', '.join(TOOL_TYPES)}",
    ),
]
"""A tool table, told apart by its ``type`` (an error names the fields of that type only)."""


class TimePath(CaseInputs):
    duration_s: float = Field(
        gt=0, le=1e9, description="duration of the experiment", json_schema_extra={"unit": "s"}
    )
    frames: int = Field(
        gt=0,
        le=MAX_FRAMES,
        description="output frames (one solver step each)",
        json_schema_extra={"unit": "1"},
    )
    max_step_s: float | None = Field(
        None, gt=0, le=1e9, description="largest solver step", json_schema_extra={"unit": "s"}
    )
    rtol: float = Field(
        1e-6,
        gt=0,
        lt=1e-2,
        description="Newton tolerance on the relative residual",
        json_schema_extra={"unit": "1"},
    )
    max_iterations: int = Field(
        25, ge=2, le=200, description="Newton iterations per step", json_schema_extra={"unit": "1"}
    )
    max_cutbacks: int = Field(
        8, ge=0, le=30, description="halvings of a failing step", json_schema_extra={"unit": "1"}
    )
    line_search: int = Field(
        0,
        ge=0,
        le=20,
        description="halvings of a Newton step that would raise the residual or invert an "
        "element (0: the full step)",
        json_schema_extra={"unit": "1"},
    )
    retry_from_last_state: bool = Field(
        True,
        description="take a step that fails from the predictor once more from the last state "
        "before halving it (false: halve at once, as before 2026-12-07)",
    )
    at_path_knots: bool = Field(
        True,
        description="also output a frame at each knot of a tool's path (the end of a ramp, "
        "the start of a hold or a retract) and at each time of record.sections_at_s",
    )


class Record(CaseInputs):
    fields: bool = Field(False, description="VTU/PVD field series and its viewer script")
    sections_at_s: list[Annotated[float, Field(ge=0, le=1e9)]] = Field(
        default_factory=list,
        description="times of the section figures",
        json_schema_extra={"unit": "s"},
    )
    section_window_um: list[float] | None = Field(
        None,
        min_length=4,
        max_length=4,
        description="[x_min, x_max, y_min, y_max] of the section figures (default: the cell)",
        json_schema_extra={"unit": "um"},
    )

    @model_validator(mode="after")
    def _window(self) -> Record:
        w = self.section_window_um
        if w is not None and not (w[0] < w[1] and w[2] < w[3]):
            raise ValueError("section_window_um: [x_min, x_max, y_min, y_max] with min < max")
        return self


class Experiment(CaseInputs):
    """A whole experiment: cell, tools (by name), time path, recorders."""

    description: str = Field("", max_length=2000, description="what the experiment is")
    cell: Cell = Field(description="the cell: size, layers, materials, mesh, points")
    tools: dict[str, Tool] = Field(default_factory=dict, description="the rigid tools, by name")
    loads: dict[str, Load] = Field(
        default_factory=dict, description="pressures and traction tables on the outer surface"
    )
    support: Literal["tools", "inertia_relief"] = Field(
        "tools",
        description="tools: holding pipettes, seals or opposed tools hold the cell; "
        "inertia_relief: a free cell balanced by its rigid-body acceleration (loads only)",
    )
    time: TimePath = Field(description="the time path")
    record: Record = Field(Record(), description="what to record beyond the histories")
    kinematics: Literal["finite_strain", "small_strain"] = Field(
        "finite_strain",
        description="finite_strain: the neo-Hookean solid; small_strain: small-strain "
        "elasticity with the contact of Sneddon's and Hertz's solutions (a pressure along the "
        "tool's axis, the gap measured along it; frictionless plates, spheres and cones)",
    )
    mesh_scale: float = Field(
        1.0,
        ge=0.25,
        le=8,
        description="multiplies every element size (quick runs: 2)",
        json_schema_extra={"unit": "1"},
    )

    @model_validator(mode="after")
    def _relations(self) -> Experiment:
        r = self.cell.radius_um
        axisym = self.cell.symmetry == "axisymmetric"
        if not self.tools and not self.loads:
            raise ValueError("tools or loads: at least one tool or load")
        if not self.loads and not any(
            getattr(t, "suction_control", None) is not None
            or any(
                path is not None and any(path.value)
                for path in (getattr(t, "displacement_um", None), getattr(t, "suction_Pa", None))
            )
            for t in self.tools.values()
        ):
            raise RuleBroken(
                "tools",
                "at least one tool with a path (displacement_um) or a suction (suction_Pa, "
                "suction_control) that is not 0 throughout, or a surface load (loads): "
                "nothing here loads the cell",
                sorted(self.tools),
            )
        self._mesh_size()
        if set(self.tools) & set(self.loads):
            raise ValueError("tools and loads: distinct names")
        for name, load in self.loads.items():
            if isinstance(load, TractionLoad):
                try:
                    read_traction_table(load.table, r, axisym)
                except InputError as exc:
                    raise ValueError(f"loads.{name}.table: {exc}") from None
                if load.follower and axisym:
                    raise ValueError(f"loads.{name}.follower: a plane-strain cell (symmetry)")
            elif load.window_deg is not None:
                rel.window_meets_section(f"loads.{name}.window_deg", load.window_deg, axisym)
        if self.support == "inertia_relief":
            if self.tools or not self.loads:
                raise ValueError("support 'inertia_relief': a free cell with loads, no tools")
            return self._sections()
        if self.kinematics == "small_strain":
            self._small_strain()
        for name, tool in self.tools.items():
            where = f"tools.{name}"
            floor, why = self._floor(RESOLVE, "a smaller tool falls within one element")
            for key in TOOL_LENGTHS:
                value = getattr(tool, key, None)
                if value:
                    rel.resolvable(f"{where}.{key}", value, floor, why)
            if axisym and tool.side not in ("top", "bottom"):
                raise ValueError(f"{where}.side 'top' or 'bottom' (on the axis) in axisymmetry")
            if isinstance(tool, StraightPipette):
                if not axisym:
                    raise ValueError(f"{where}: a straight pipette needs symmetry 'axisymmetric'")
                if tool.inner_radius_um + tool.mouth_fillet_um >= r:
                    raise RuleBroken(
                        f"{where}.inner_radius_um",
                        f"inner_radius_um + mouth_fillet_um below the cell's radius {r:g} um",
                        tool.inner_radius_um + tool.mouth_fillet_um,
                    )
                if (tool.suction_Pa is None) == (tool.displacement_um is None):
                    raise ValueError(f"{where}: suction_Pa or displacement_um (one of them)")
            if isinstance(tool, WedgePipette) and axisym:
                raise ValueError(f"{where}: a wedge pipette needs symmetry 'plane_strain'")
            if isinstance(tool, HoldingPipette) and (tool.half_width_um or 0) >= r:
                raise ValueError(f"{where}.half_width_um < the cell radius {r:g} um")
            if (
                isinstance(tool, HoldingPipette)
                and tool.displacement_um
                and tool.displacement_um.value[0]
            ):
                raise RuleBroken(
                    f"{where}.displacement_um",
                    "a path that is 0 at t = 0 (a holding pipette holds the cell where it is at "
                    "t = 0; its path is the displacement from there)",
                    tool.displacement_um.value,
                )
            if isinstance(tool, NeckedPipette):
                self._necked(name, tool)
            if isinstance(tool, Sphere | Cone | Plate) and tool.displacement_um is None:
                raise ValueError(f"{where}.displacement_um (a path){DISH_HINT}")
            path = tool.displacement_um if isinstance(tool, ToolBase) else None
            if path is not None and max(path.value) - tool.gap_um >= 2 * r:
                raise RuleBroken(
                    f"{where}.displacement_um",
                    f"a travel into the cell (advance less gap_um) below its diameter {2 * r:g} um",
                    max(path.value) - tool.gap_um,
                )
            if path is not None and not isinstance(tool, NeckedPipette):
                floor = self._floor(ADVANCE_RESOLVE, "a smaller advance gives no force")
                rel.presses(self._travel(name), *floor)
            if path is not None and isinstance(tool, NeckedPipette):
                travel = rel.Travel(f"{where}.displacement_um", tool.side, path, tool.clearance_um)
                rel.clear_at_start(travel, "clearance_um")
            elif path is not None and not isinstance(tool, HoldingPipette):
                rel.clear_at_start(self._travel(name))
            if isinstance(tool, Cone) and path is not None:
                _cone_reaches(where, tool, max(path.value) - tool.gap_um)
        pressing = [n for n, t in self.tools.items() if not isinstance(t, NeckedPipette)]
        rel.opposed([self._travel(n) for n in pressing], 2 * r)
        held = any(
            isinstance(t, HoldingPipette) or (isinstance(t, StraightPipette) and t.seal == "fixed")
            for t in self.tools.values()
        )
        if not held:
            self._supported(axisym)
        return self._sections()

    def _floor(self, factor: int, what: str) -> tuple[float, str]:
        """The shortest tool length or advance the mesh resolves (the finest element /
        ``factor``), and why (for messages)."""
        cell = self.cell
        if cell.refine_size_um:
            h, size = cell.refine_size_um, f"refine_size_um = {cell.refine_size_um:g} um"
        else:
            h = cell.mesh_size_um
            size = f"refine_size_um unset: mesh_size_um = {h:g} um"
        return h / factor, f"the cell's finest element, {size}, / {factor}: {what}"

    def estimated_triangles(self) -> float:
        """Triangles of the cell's mesh, estimated: ``2.31`` per ``h^2`` over the section at
        ``mesh_size_um``, over a band ``refine_depth_um`` deep under the refined arcs at
        ``refine_size_um``, and over the graded band where the size rises from one to the
        other (``(1/f - 1/H) / GRADING`` per um of arc); sizes times ``mesh_scale``."""
        return TRIANGLES_PER_SQUARE * sum(self._squares())

    def _squares(self) -> tuple[float, float]:
        """``h^2`` squares of :meth:`estimated_triangles`: the section at ``mesh_size_um``,
        and the refined and graded bands (0 without refinement)."""
        cell, s = self.cell, self.mesh_scale
        r, axisym = cell.radius_um, cell.symmetry == "axisymmetric"
        big = cell.mesh_size_um * s
        fine = (cell.refine_size_um or cell.mesh_size_um) * s
        area = np.pi * r**2 / (2.0 if axisym else 1.0)
        count, refined = area / big**2, 0.0
        if fine < big:
            if cell.refine_windows_deg is not None:
                windows = [tuple(w) for w in cell.refine_windows_deg]
            else:
                half = cell.refine_half_angle_deg
                poles = {"top": 0.0, "bottom": 180.0, "left": 90.0, "right": 90.0}
                windows = [
                    (max(0.0, poles[t.side] - half), min(180.0, poles[t.side] + half))
                    for t in self.tools.values()
                    if not isinstance(t, HoldingPipette | NeckedPipette)
                ]
            span, end = 0.0, -1.0
            for lo, hi in sorted(windows):  # the union of the polar windows, deg
                lo = max(lo, end)
                span += max(0.0, hi - lo)
                end = max(end, hi)
            arc = r * np.deg2rad(span) * (1.0 if axisym else 2.0)
            depth = min(r, cell.refine_depth_um or max(cell.zona_thickness_um, 4 * fine))
            band = min(area, arc * depth)
            refined = band / fine**2 + arc * (1.0 / fine - 1.0 / big) / GRADING
        return count, refined

    def _mesh_size(self) -> None:
        """RuleBroken if the cell's mesh would exceed :data:`MAX_TRIANGLES` (meshing hangs)."""
        coarse, refined = self._squares()
        count = TRIANGLES_PER_SQUARE * (coarse + refined)
        if count > MAX_TRIANGLES:
            cell = self.cell
            key = "refine_size_um" if refined > coarse else "mesh_size_um"
            raise RuleBroken(
                f"cell.{key}",
                f"a mesh of at most {MAX_TRIANGLES:,} triangles (estimated from the section's "
                "area / mesh_size_um^2 and the refined band's area / refine_size_um^2, sizes "
                f"times mesh_scale = {self.mesh_scale:g}): these sizes give about {count:.3g}, "
                "meshing would not end",
                getattr(cell, key),
            )

    def _travel(self, name: str) -> rel.Travel:
        """The tool's advance into the cell (a holding pipette carries its surface: gap 0)."""
        tool = self.tools[name]
        return rel.Travel(
            f"tools.{name}.displacement_um",
            tool.side,
            tool.displacement_um,
            getattr(tool, "gap_um", 0.0),
        )

    def _supported(self, axisym: bool) -> None:
        """Without a hold the cell is held by tools on top and bottom (axisymmetric), those
        with a displacement path pressing it at every time after t = 0."""
        why = "plane strain needs a hold"
        if axisym:
            found = {
                side: [
                    rel.presses_throughout(self._travel(n)) if t.displacement_um else None
                    for n, t in self.tools.items()
                    if t.side == side and isinstance(t, ToolBase)
                ]
                for side in ("top", "bottom")
            }
            if all(None in whys for whys in found.values()):
                return
            missing = [side for side, whys in found.items() if not whys]
            why = (
                f"no tool on the {missing[0]}"
                if missing
                else next(w for whys in found.values() for w in whys if w)
            )
        raise ValueError(
            "tools: a holding_pipette, a pipette with seal 'fixed', or (axisymmetric) "
            "tools on top and bottom that press the cell throughout: the cell needs "
            f"support (a free cell under loads only: support = 'inertia_relief'; {why})"
        )

    def _necked(self, name: str, tool: NeckedPipette) -> None:
        """A necked pipette: axisymmetric on top, a bore that takes the cell, a neck narrower
        than it, a controlling cap, an advance onto the taper within the modelled glass."""
        where = f"tools.{name}"
        if self.cell.symmetry != "axisymmetric" or tool.side != "top":
            raise ValueError(f"{where}: a necked pipette is axisymmetric, side 'top'")
        diameter, clearance = self.cell.outer_diameter_um, tool.clearance_um
        rel.neck_fits(
            diameter, tool.bore_diameter_um, tool.neck_diameter_um, clearance, f"{where}."
        )
        control = tool.suction_control
        driver = self.tools.get(control.tool) if control else None
        if control and not (isinstance(driver, HoldingPipette) and driver.displacement_um):
            holders = [
                n
                for n, t in self.tools.items()
                if isinstance(t, HoldingPipette) and t.displacement_um
            ]
            raise RuleBroken(
                f"{where}.suction_control.tool",
                "the name of a holding pipette with displacement_um in tools"
                + (f" ({', '.join(map(repr, holders))})" if holders else " (there is none)")
                + ("" if driver is None else f"; {control.tool!r} is a {driver.type}"),
                control.tool,
            )
        caps = [
            n
            for n, t in self.tools.items()
            if isinstance(t, HoldingPipette) and t.side == "bottom" and t.displacement_um
        ]
        moving = ([self._travel(name)] if tool.displacement_um else []) + [
            self._travel(n) for n in caps
        ]
        if not moving:
            return
        t = np.unique(np.concatenate([m.times for m in moving]))
        total = PathSpec(time_s=list(t), value=list(sum(m.at(t) + m.gap_um for m in moving)))
        field = moving[-1].field if len(moving) == 1 else " + ".join(m.field for m in moving)
        rel.neck_advance(
            self.cell.radius_um,
            neck_geometry(tool),
            clearance,
            rel.Travel(field, "bottom", total),
        )

    def _small_strain(self) -> None:
        """Small strain: Sneddon's frictionless indenters only (no loads, no pipettes)."""
        if self.loads:
            raise ValueError("kinematics 'small_strain': tools only, no loads")
        for name, tool in self.tools.items():
            if not isinstance(tool, Plate | Sphere | Cone | HoldingPipette):
                raise ValueError(
                    f"tools.{name}: kinematics 'small_strain' takes plates, spheres, cones and "
                    "holding pipettes"
                )
            if getattr(tool, "friction", 0.0):
                raise ValueError(f"tools.{name}.friction: 0 with kinematics 'small_strain'")

    def output_times(self) -> list[float]:
        """The output frames' times [s] after t = 0: ``time.frames`` even steps to the
        duration and, with ``time.at_path_knots``, every knot of a tool's path (displacement,
        suction) and every time of ``record.sections_at_s`` (a ramp's end is then a frame, its
        peak force recorded, and a section drawn at the time asked); a knot within 1e-9 of
        the duration of a frame is that frame."""
        duration = self.time.duration_s
        times = list(np.linspace(duration / self.time.frames, duration, self.time.frames))
        if self.time.at_path_knots:
            for tool in self.tools.values():
                for key in ("displacement_um", "suction_Pa"):
                    path = getattr(tool, key, None)
                    times += list(path.time_s) if path is not None else []
            times += list(self.record.sections_at_s)
        out: list[float] = []
        for t in sorted(t for t in times if 0.0 < t <= duration):
            if not out or t - out[-1] > 1e-9 * duration:
                out.append(float(t))
        return out

    def _sections(self) -> Experiment:
        """Section times and the last time of every path within ``time.duration_s``: the
        driver solves up to the duration, so a path's later values would never be applied. A
        time within a relative :data:`TIME_SLACK` past the duration is its round-off (a path
        and a duration written to end together, one of them off by 1e-9, was refused)."""
        end = self.time.duration_s * (1.0 + TIME_SLACK)
        for t in self.record.sections_at_s:
            if t > end:
                raise ValueError(f"record.sections_at_s within the duration ({t:g} s)")
        if self.record.section_window_um is not None:
            paths = [getattr(t, "displacement_um", None) for t in self.tools.values()]
            reach = max([max(abs(v) for v in p.value) for p in paths if p] + [0.0])
            rel.window_shows_cell(
                "record.section_window_um",
                self.record.section_window_um,
                self.cell.radius_um,
                reach,
            )
        parts = [("tools", self.tools), ("loads", self.loads)]
        for group, named in parts:
            for name, part in named.items():
                for key in PATH_FIELDS:
                    path = getattr(part, key, None)
                    if isinstance(path, PathSpec) and path.time_s[-1] > end:
                        raise ValueError(
                            f"{group}.{name}.{key}.time_s within time.duration_s = "
                            f"{self.time.duration_s:g} s (the path runs to {path.time_s[-1]:g} s; "
                            "its values after the duration would never be applied)"
                        )
        return self


def neck_geometry(tool: NeckedPipette) -> neck.NeckedPipette:
    """The necked pipette's wall (not yet placed against the cell)."""
    return neck.NeckedPipette(
        bore_radius_um=tool.bore_diameter_um / 2,
        neck_radius_um=tool.neck_diameter_um / 2,
        taper_length_um=tool.taper_length_um,
        bore_length_um=tool.bore_length_um,
        neck_length_um=tool.neck_length_um,
        taper_points=tool.taper_points,
    )


PATH_FIELDS = ("displacement_um", "suction_Pa", "pressure_Pa", "scale")
"""The fields of tools and loads that hold a :class:`PathSpec` (a history in time)."""


def _cone_reaches(where: str, cone: Cone, travel_um: float) -> None:
    """ValueError unless the cone's flank reaches deeper than its travel into the cell: past
    its end (``length_um`` along the flank) the cell would wrap around the cone's base."""
    reach = cone.reach_um
    if travel_um >= reach:
        raise ValueError(
            f"{where}.length_um: a cone reaching deeper than its travel into the cell "
            f"({travel_um:g} um; length_um = {cone.length_um:g} um reaches {reach:.4g} um)"
        )
