"""Inputs and metrics of the case kind ``afm_fit_files`` (its schema, apart from its run), and
the check of what the inputs name (:func:`check_case`, run by ``validate`` and before ``run``
with the functions ``run`` uses): the curve files, the tip's geometry, the groups, the creep
records, the fit keywords, the correction, the known-moduli file. The creep records and the
known-moduli file are read at validation with the run's readers (:class:`DataReader`)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from afm.fit_files import read_known_moduli
from afm.models import MODELS
from oocyte_fe.checks import inside, regular_file
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_fit_files_check import check_case, read_creep_records
from oocyte_fe.kinds.afm_fit_files_tables import Calibration, CorrectionInputs, Viscoelastic
from oocyte_fe.kinds.data_templates import AFM_CURVES_FOLDER, KNOWN_MODULI
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.schema import CaseInputs, DataReader, RuleBroken


class FitFilesInputs(CaseInputs):
    curves: str = Field(
        min_length=1,
        description="folder (searched recursively) or glob of curve files, relative to the "
        "case folder: CSV/TSV tables or any instrument file afmformats reads",
        json_schema_extra=AFM_CURVES_FOLDER,
    )
    model: str = Field("sneddon_cone", description="tip model key (afm.models)")
    geometry: dict[str, float] = Field(
        default_factory=dict,
        description="tip parameters of the model, e.g. half_angle_deg = 10 (deg) or "
        "radius_um (um); left-out ones take the model's default",
        json_schema_extra={"unit": "deg or um, by the key's suffix"},
    )
    nu: float = Field(
        0.5,
        gt=-1,
        le=0.5,
        description="Poisson ratio of the sample",
        json_schema_extra={"unit": "1"},
    )
    spring_constant_N_per_m: float | None = Field(
        None,
        gt=0,
        description="spring constant for every file (overrides the files' own; needed for "
        "files without one, e.g. AFM-Workshop CSV, NT-MDT)",
        json_schema_extra={"unit": "N/m"},
    )
    sensitivity_nm_per_V: float | None = Field(
        None,
        gt=0,
        description="deflection sensitivity for every file (overrides the files' own)",
        json_schema_extra={"unit": "nm/V"},
    )
    calibration: dict[str, Calibration] = Field(
        default_factory=dict,
        description="glob pattern on the file path relative to the case folder -> "
        "{ spring_constant_N_per_m, sensitivity_nm_per_V } for those files (first match; "
        "over the global values)",
    )
    max_indentation_um: float | None = Field(
        None, gt=0, description="fit range: depth past contact", json_schema_extra={"unit": "um"}
    )
    max_force_fraction: float | None = Field(
        None,
        gt=0,
        le=1,
        description="fit range: fraction of the maximum force",
        json_schema_extra={"unit": "1"},
    )
    contact_method: Literal["fit", "deviation"] = Field(
        "fit", description="contact point: a fit parameter, or the deviation estimate"
    )
    analysis: Literal["default", "nanite"] = Field(
        "default",
        description="default: afm.fit.fit_indentation (baseline line, unweighted fit); nanite: "
        "afm.nanite_pipeline.fit_nanite_default (nanite's offset, contact weighting, free "
        "baseline; whole approach, so no fit range)",
    )
    groups: dict[str, str] = Field(
        default_factory=dict,
        description="group name -> glob pattern on the file path relative to the case folder; "
        "files matching none are grouped by their subfolder",
    )
    height_channel: str | None = Field(
        None, description="height channel of instrument files (default: as the instrument does)"
    )
    creep: Annotated[dict[str, DataFile], DataReader(read_creep_records)] = Field(
        default_factory=dict,
        description="group name -> force-clamp creep CSV: its material gets E0 and a Prony series",
    )
    half_angle_deg_creep: float | None = Field(
        None,
        description="cone half angle of the creep probe when it differs from the curves' tip "
        "(default: the creep fit uses the curves' model and geometry)",
        json_schema_extra={"unit": "deg", "quantity": "cone_half_angle_deg"},
    )
    pierce: bool | list[str] = Field(
        False,
        description="pierce-through curves (the force drops when the probe pierces the ZP): "
        "true (every curve), false (none) or a list of group names (the curves of those groups; "
        "the other groups fitted as plain curves); the ZP fitted up to the drop, the cytoplasm "
        "after it (afm.pierce.fit_pierce); a curve without a drop is refused (no pierce "
        "detected); materials per layer",
    )
    pierce_min_drop_fraction: float = Field(
        0.1,
        gt=0,
        lt=1,
        description="the least force drop taken as the pierce, a fraction of the curve's force "
        "range (the curves pierce takes; the prominence of the drop's peak, "
        "afm.pierce.detect_pierce)",
        json_schema_extra={"unit": "1"},
    )
    include_poor: bool = Field(
        False,
        description="keep fits rated poor in the group means and material files (default: "
        "left out, counted as n_poor)",
    )
    curve_plots: Literal["all", "poor", "none"] = Field(
        "all",
        description="per-curve figures: every curve, only the poor and refused ones, or none "
        "(large force maps)",
    )
    viscoelastic: Viscoelastic | None = Field(
        None,
        description="also fit every ramp (approach and retract) in time with a relaxation "
        "modulus; needs files with the time of every point",
    )
    correction: CorrectionInputs | None = Field(
        None,
        description="correct every modulus for the sample's shape: type = shelled_oocyte "
        "(spherical probe on the layered oocyte), dimitriadis_bonded (sphere) or garcia_bonded "
        "(cone) on a layer bonded to a rigid support; needs max_indentation_um",
    )
    known_moduli: Annotated[str, DataReader(read_known_moduli)] | None = Field(
        None,
        description="optional CSV (file, E_kPa) of known moduli to check the fits against, "
        "relative to the case folder",
        json_schema_extra=KNOWN_MODULI,
    )
    known_tolerance_pct: float = Field(
        5.0, gt=0, description="largest error against known_moduli", json_schema_extra={"unit": "%"}
    )

    @field_validator("known_moduli")
    @classmethod
    def _known_moduli_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        """A known-moduli file must exist inside the case folder (checked at ``validate``;
        a plain string, not a data file, so ``oocyte-fe new`` leaves it out). Resolved, so
        that ``validate`` reads it with the run's reader (:class:`DataReader`) wherever it
        runs from."""
        case_dir = (info.context or {}).get("case_dir")
        if value is None or case_dir is None:
            return value
        where = Path(case_dir) / "case.toml"
        try:
            return str(regular_file(inside(value, case_dir, where, "inputs.known_moduli")))
        except InputError as exc:
            raise ValueError(exc.expected + ("" if exc.got is None else f" ({exc.got})")) from None

    @field_validator("pierce", mode="before")
    @classmethod
    def _pierce_value(cls, value: object) -> object:
        """``pierce`` is true, false or a list of group names: anything else is refused in one
        line (not as the union's first error, "a valid boolean"). The names are checked
        against the case's groups by :func:`check_case`."""
        names = isinstance(value, list) and all(isinstance(g, str) and g for g in value)
        if isinstance(value, bool):
            return value
        if names and value and len(set(value)) == len(value):
            return value
        if names and value:  # a group named twice: a slip, perhaps for another group
            twice = sorted({g for g in value if value.count(g) > 1})
            raise ValueError(f"each group once (named twice: {', '.join(twice)})")
        raise ValueError('true, false or a list of one or more group names, e.g. ["zp"]')

    @field_validator("model")
    @classmethod
    def _known_model(cls, value: str) -> str:
        if value not in MODELS:
            raise ValueError(f"one of {', '.join(sorted(MODELS))}")
        return value

    @model_validator(mode="after")
    def _finite(self) -> FitFilesInputs:
        for key, value in self.geometry.items():
            if not math.isfinite(value):
                raise ValueError(f"geometry.{key}: a finite number")
        return self

    @model_validator(mode="after")
    def _what_the_case_names(self, info: ValidationInfo) -> FitFilesInputs:
        """:func:`check_case` when the case folder is known (``validate``, and ``run`` before
        it starts): its refusal names the input in ``case.toml``."""
        case_dir = (info.context or {}).get("case_dir")
        if case_dir is None:
            return self
        where = Path(case_dir) / "case.toml"
        try:
            check_case(self, Path(case_dir))
        except InputError as exc:
            expected = exc.expected
            if exc.file != str(where):  # (check_case names case.toml; kept for safety)
                expected += f" ({exc.file}{': ' + exc.field if exc.field else ''})"
            raise RuleBroken(exc.field.removeprefix("inputs."), expected, exc.got) from None
        return self


METRICS = {
    "n_curves": "curves read (a force map counts each of its curves)",
    "n_fitted": "curves fitted",
    "n_failed": "curves that could not be read or fitted (reported and skipped)",
    "n_poor": "fitted curves rated poor",
    "n_no_pierce": "pierce-through curves without a detectable pierce (pierce = true or groups)",
    "max_known_error_pct": "largest |E / E_known - 1| over curves with a known modulus, %",
    "n_ramps_fitted": "ramps fitted in time (viscoelastic option)",
    "ve_E0_kPa": "E0 of the first group's joint ramp fit (groups by name), kPa",
    "ve_E_inf_kPa": "E_inf of the first group's joint ramp fit, kPa",
    **{
        f"ve_E{i}_kPa": f"Prony modulus E_{i} of the first group's ramp fit, kPa"
        for i in (1, 2, 3, 4)
    },
    **{
        f"ve_tau{i}_s": f"Prony time tau_{i} of the first group's ramp fit, s" for i in (1, 2, 3, 4)
    },
    "ve_beta": "power-law exponent beta of the first group's ramp fit",
}
