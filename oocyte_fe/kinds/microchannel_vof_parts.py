"""The parts of the ``microchannel_vof`` inputs: one cell phase, the junction's geometry and
isoAdvector's alpha controls (and the field helper the inputs share)."""

from __future__ import annotations

from pydantic import Field, field_validator

from oocyte_fe.kinds.microchannel_inputs import ETA_INF_BELOW_ETA0
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.isoadvector import IsoControls
from oocyte_fe.runner.schema import CaseInputs, Relation


def _f(default: object, description: str, unit: str, **kw: object) -> object:
    return Field(default, description=description, json_schema_extra={"unit": unit}, **kw)


class CellPhaseInputs(CaseInputs):
    """One of the cell's phases (Table 3 of seed 001): density and Carreau limits."""

    density_kg_m3: float = Field(gt=0, description="density", json_schema_extra={"unit": "kg/m^3"})
    eta0_Pa_s: float = Field(
        gt=0,
        description="zero-shear viscosity (before the cap)",
        json_schema_extra={"unit": "Pa s"},
    )
    eta_inf_Pa_s: float = Field(
        gt=0, description="infinite-shear viscosity", json_schema_extra={"unit": "Pa s"}
    )

    rules = (ETA_INF_BELOW_ETA0,)


class GeometryInputs(CaseInputs):
    """The Fig. 6 junction as read here (docs/microchannel.md, VOF section)."""

    channel_width_um: float = _f(250.0, "main channel width (paper)", "um", gt=0)
    branch_width_um: float = _f(250.0, "width of the medium branch B (reading)", "um", gt=0)
    upstream_length_um: float = _f(875.0, "inlet A to the junction centre (reading)", "um", gt=0)
    downstream_length_um: float = _f(1125.0, "junction centre to outlet C (reading)", "um", gt=0)
    branch_length_um: float = _f(500.0, "length of branch B (reading)", "um", gt=0)
    cell_diameter_um: float = _f(140.0, "oocyte diameter (paper)", "um", gt=0)
    cytoplasm_diameter_um: float = _f(110.0, "cytoplasm diameter (paper)", "um", gt=0)
    cell_offset_um: float = _f(500.0, "start of the cell before the junction centre", "um", gt=0)

    rules = (
        Relation("cytoplasm_diameter_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation("cell_diameter_um", "<", lambda m: m.channel_width_um, "channel_width_um"),
        Relation(
            "cell_offset_um",
            "<",
            lambda m: m.upstream_length_um - m.cell_diameter_um / 2,
            "upstream_length_um - cell_diameter_um / 2 (the cell in the upstream arm)",
        ),
    )

    def to_geometry(self) -> JunctionGeometry:
        return JunctionGeometry(
            self.channel_width_um,
            self.branch_width_um,
            self.upstream_length_um,
            self.downstream_length_um,
            self.branch_length_um,
            self.cell_diameter_um,
            self.cytoplasm_diameter_um,
            self.cell_offset_um,
        )


class IsoAdvectorInputs(CaseInputs):
    """isoAdvector's alpha controls (``interIsoFoam``; defaults: v1912's damBreak tutorial)."""

    iso_face_tol: float = _f(1e-6, "isoFaceTol: tolerance of the isoface's position", "1", gt=0)
    surf_cell_tol: float = _f(
        1e-6, "surfCellTol: alpha within this of 0 or 1 is not an interface cell", "1", gt=0
    )
    n_alpha_bounds: int = _f(3, "nAlphaBounds: passes of the local bounding", "1", ge=0)
    snap_tol: float = _f(1e-12, "snapTol: alpha within this of 0 or 1 is snapped", "1", ge=0)
    clip: bool = _f(True, "clip alpha to [0, 1] after the bounding", "1")

    @field_validator("surf_cell_tol", "snap_tol")
    @classmethod
    def _below_half(cls, value: float) -> float:
        if value >= 0.5:  # every alpha lies within 0.5 of 0 or 1
            raise ValueError(
                "a tolerance below 0.5 (alpha within it of 0 or 1 counts as 0 or 1: at 0.5 "
                "every cell would, and the interface would vanish)"
            )
        return value

    def to_controls(self) -> IsoControls:
        return IsoControls(
            self.iso_face_tol, self.surf_cell_tol, self.n_alpha_bounds, self.snap_tol, self.clip
        )
