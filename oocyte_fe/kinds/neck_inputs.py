"""Inputs and metrics of the case kind ``fe_neck_aspiration`` (its schema, apart from its run)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

from pydantic import Field, ValidationInfo, field_validator, model_validator

from oocyte_fe.errors import InputError
from oocyte_fe.experiment import relations as rel
from oocyte_fe.experiment.paths import PathSpec
from oocyte_fe.fe.material import read_material_file
from oocyte_fe.kinds.data_templates import CYTOPLASM_MATERIAL, ZONA_MATERIAL
from oocyte_fe.neck.passage import PassageSettings
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.runner.casefile import read_toml
from oocyte_fe.runner.schema import CaseInputs, DataFile, DataReader, Refining, Relation

SizeUm = Annotated[float, Field(ge=1, le=100)]

POINT_ARC = "(cytoplasm_radius_um + zona_thickness_um) pi / 6"


def _point_arc_um(m: NeckInputs) -> float:
    """Arc between two neighbouring surface points of the five (30 deg apart), um."""
    return (m.cytoplasm_radius_um + m.zona_thickness_um) * math.pi / 6


class NeckInputs(CaseInputs):
    material_case: str | None = Field(
        default=None,
        description="folder of an afm_creep_prony case, relative (chained: it is re-run); "
        "or give zona_material_file and cytoplasm_material_file",
    )
    zona_material_file: Annotated[DataFile, DataReader(read_material_file)] | None = Field(
        default=None,
        description="ZP material file (TOML, as afm_creep_prony writes it)",
        json_schema_extra=ZONA_MATERIAL,
    )
    cytoplasm_material_file: Annotated[DataFile, DataReader(read_material_file)] | None = Field(
        default=None,
        description="cytoplasm material file (TOML, as afm_creep_prony writes it)",
        json_schema_extra=CYTOPLASM_MATERIAL,
    )
    cytoplasm_radius_um: float = Field(
        gt=0, description="cytoplasm radius (inside the ZP)", json_schema_extra={"unit": "um"}
    )
    zona_thickness_um: float = Field(
        gt=0, description="ZP thickness", json_schema_extra={"unit": "um"}
    )
    bore_diameter_um: float = Field(
        gt=0, description="pipette bore diameter before the neck", json_schema_extra={"unit": "um"}
    )
    neck_diameter_um: float = Field(
        gt=0, description="pipette neck diameter", json_schema_extra={"unit": "um"}
    )
    taper_length_um: float = Field(
        gt=0, description="length of the cosine taper", json_schema_extra={"unit": "um"}
    )
    friction: float = Field(
        ge=0,
        le=2,
        description="Coulomb friction coefficient at the pipette wall",
        json_schema_extra={"unit": "1"},
    )
    suction_Pa: float = Field(
        gt=0,
        description="the seed's suction (compared, see reading)",
        json_schema_extra={"unit": "Pa"},
    )
    duration_s: float = Field(
        gt=0, description="duration of the passage", json_schema_extra={"unit": "s"}
    )
    steps: int = Field(
        ge=2, le=10_000, description="time steps over duration_s", json_schema_extra={"unit": "1"}
    )
    advance_um: float = Field(
        gt=0, description="rear-cap advance over duration_s", json_schema_extra={"unit": "um"}
    )
    size_um: float = Field(
        ge=1,
        le=100,
        description="element size away from the side band",
        json_schema_extra={"unit": "um"},
    )
    refine_factor: float = Field(
        ge=1,
        le=10,
        description="side-band element size = size_um / this",
        json_schema_extra={"unit": "1"},
    )
    penalty_factor: float = Field(
        gt=0, description="normal penalty = factor * E_max / h", json_schema_extra={"unit": "1"}
    )
    mesh_study_sizes_um: list[SizeUm] = Field(
        default_factory=list,
        description="element sizes of the mesh study (coarse to fine); empty: no study",
        json_schema_extra={"unit": "um"},
    )
    mesh_change_max_pct: float = Field(
        default=2.0,
        gt=0,
        description="largest change between the two finest meshes",
        json_schema_extra={"unit": "%"},
    )
    sensitivity: bool = Field(True, description="run the friction and modulus sensitivity")
    sensitivity_size_um: float = Field(
        default=14.0,
        ge=1,
        le=100,
        description="element size of the sensitivity runs",
        json_schema_extra={"unit": "um"},
    )
    friction_values: list[Annotated[float, Field(ge=0, le=2)]] = Field(
        default_factory=lambda: [0.0, 0.4],
        description="friction coefficients of the sensitivity runs",
        json_schema_extra={"unit": "1"},
    )
    zona_E_sd_kPa: float = Field(
        default=2.88,
        ge=0,
        description="SD of the ZP modulus (sensitivity at mean +- SD)",
        json_schema_extra={"unit": "kPa"},
    )
    zona_E_kPa: float | None = Field(
        default=None,
        gt=0,
        description="replaces the ZP modulus of the material file",
        json_schema_extra={"unit": "kPa"},
    )
    cytoplasm_E_kPa: float | None = Field(
        default=None,
        gt=0,
        description="replaces the cytoplasm modulus of the material file",
        json_schema_extra={"unit": "kPa"},
    )
    vtu: bool = Field(True, description="write the VTU/PVD series of the main run")

    @field_validator("material_case")
    @classmethod
    def _afm_case(cls, value: str | None, info: ValidationInfo) -> str | None:
        case_dir = (info.context or {}).get("case_dir")
        if value is not None and case_dir is not None:
            folder = Path(case_dir) / value
            try:
                kind = read_toml(folder / "case.toml").get("kind")
            except InputError as exc:
                raise ValueError(
                    f"material_case naming a folder with an afm_creep_prony case.toml "
                    f"({exc.expected}: {folder / 'case.toml'}); a copied case can name "
                    "material files instead (zona_material_file, cytoplasm_material_file)"
                ) from None
            if kind != "afm_creep_prony":
                raise ValueError(f"material_case naming an afm_creep_prony case, not {kind!r}")
        return value

    @model_validator(mode="after")
    def _one_material_source(self) -> NeckInputs:
        files = (self.zona_material_file, self.cytoplasm_material_file)
        given = sum(f is not None for f in files)
        if self.material_case is None and given != 2:
            raise ValueError(
                "material_case, or both zona_material_file and cytoplasm_material_file"
            )
        if self.material_case is not None and given:
            raise ValueError("material_case or the two material files, not both")
        return self

    @model_validator(mode="after")
    def _passage(self) -> NeckInputs:
        """The passage experiment's own rules (``fe_experiment``'s necked pipette, the same
        functions), so that ``validate`` finds what ``run`` would: a bore that takes the cell,
        a neck narrower than it, a rear-cap advance onto the taper within the modelled neck."""
        if self.neck_diameter_um >= self.bore_diameter_um:
            return self  # the rule below names it
        settings = PassageSettings()
        radius = self.cytoplasm_radius_um + self.zona_thickness_um
        rel.neck_fits(
            2 * radius, self.bore_diameter_um, self.neck_diameter_um, settings.clearance_um
        )
        pipette = NeckedPipette(
            self.bore_diameter_um / 2, self.neck_diameter_um / 2, self.taper_length_um
        )
        advance = PathSpec(time_s=[0.0, self.duration_s], value=[0.0, self.advance_um])
        travel = rel.Travel("advance_um", "bottom", advance)
        rel.neck_advance(radius, pipette, settings.clearance_um, travel)
        return self

    rules = (
        Relation("neck_diameter_um", "<", lambda m: m.bore_diameter_um, "bore_diameter_um"),
        Refining("mesh_study_sizes_um"),
        # an element no longer than the arc between two of the five surface points (30 deg):
        # a coarser mesh cannot tell them apart (the study's and the sensitivity's meshes too)
        *(
            Relation(name, "<=", _point_arc_um, POINT_ARC, measure)
            for name, measure in (
                ("size_um", "value"),
                ("mesh_study_sizes_um", "max"),
                ("sensitivity_size_um", "value"),
            )
        ),
    )


UNITS = {"s", "um", "kPa", "nN"}
METRICS = {
    "deformation_min_um": "smallest deformation |u - (0, w)| at the five points at t_end, um",
    "deformation_max_um": "largest deformation at the five points at t_end, um",
    "radial_inward_max_um": "largest radial inward displacement -u_R at the five points, um",
    "volume_change_pct": "largest |V/V0 - 1| over the passage, %",
    "suction_needed_max_Pa": "largest suction the quasi-static passage needs, Pa",
    "stall_advance_um": "centroid advance where the needed suction first exceeds suction_Pa, um",
    "centroid_advance_um": "centroid advance at t_end, um",
    "push_fraction_max": "largest |rear-cap push| / wall force after contact (driver lag), 1",
    "mesh_change_pct": "largest change of the five deformations between the two finest meshes, %",
    "elastic_vs_visco_pct": "largest change of the five deformations without the Prony terms, %",
}
