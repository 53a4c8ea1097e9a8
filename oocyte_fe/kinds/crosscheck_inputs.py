"""Inputs and metrics of the case kind ``nmsd_vs_fe`` (its schema, apart from its run)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, field_validator, model_validator

from afm.curve_io import read_creep
from nmsd.pipette import (
    CONTACT_STIFFNESS_NN_PER_UM,
    HOLD_HALF_WIDTH_UM,
    TABLE_I_TIP_ANGLE_DEG,
    TABLE_I_WIDTH_UM,
)
from oocyte_fe.experiment.description import MAX_FRAMES
from oocyte_fe.kinds.data_templates import CREEP
from oocyte_fe.kinds.nmsd_checks import (
    CELLS_ACROSS,
    FINEST,
    ZonaRatioReading,
    arrows_on_frames,
    edge_radius_limit,
    press_scenario,
    radius,
    ratio_or_reading,
    second_speed_given,
)
from oocyte_fe.kinds.nmsd_inputs import (
    CellDiameter,
    ContactStiffness,
    CriticalStrain,
    Damping,
    Evaluations,
    HoldHalfWidth,
    PipetteWidth,
    SpacingsAcross,
    Speed,
    Starts,
    Steps,
    TableIIFile,
    TipAngle,
    Travel,
)
from oocyte_fe.runner.schema import (
    CaseInputs,
    DataFile,
    DataReader,
    Distinct,
    Relation,
    Setup,
)


class CrosscheckInputs(CaseInputs):
    """Scenario, materials, FE mesh/steps, NMSD lattice/calibration, comparison grid."""

    creep_data: Annotated[DataFile, DataReader(read_creep)] = Field(
        description="ZP force-clamp creep CSV (afm.curve_io format)",
        json_schema_extra=CREEP,
    )
    table2_data: TableIIFile
    cell_diameter_um: CellDiameter = 115.625
    cytoplasm_diameter_um: float = Field(
        83.597, gt=0, description="Table I R_zp, inside the ZP", json_schema_extra={"unit": "um"}
    )
    pipette_width_um: PipetteWidth = TABLE_I_WIDTH_UM
    tip_angle_deg: TipAngle = TABLE_I_TIP_ANGLE_DEG
    speed_um_s: Speed = 30.0
    hold_half_width_um: HoldHalfWidth = HOLD_HALF_WIDTH_UM
    spindle_paper_um: tuple[float, float] = Field(
        (15.8718, 18.1392),
        description="the paper's spindle position (x, y)",
        json_schema_extra={"unit": "um"},
    )
    travel_um: Travel = 62.5
    nu: float = Field(
        0.5,
        gt=-1,
        le=0.5,
        description="Poisson ratio of both layers",
        json_schema_extra={"unit": "1"},
    )
    cytoplasm_E_kPa: float = Field(
        1.55,
        gt=0,
        description="cytoplasm Young's modulus (seed 001 Table 1)",
        json_schema_extra={"unit": "kPa"},
    )
    afm_half_angle_deg: float = Field(
        10.0,
        description="AFM cone half angle of the creep record, in [0.1, 89] deg",
        json_schema_extra={"unit": "deg", "quantity": "cone_half_angle_deg"},
    )
    thickness_um: float = Field(
        115.625,
        gt=0,
        description="effective plane-strain thickness",
        json_schema_extra={"unit": "um"},
    )
    fe_size_um: float = Field(
        6.0, gt=0, description="FE element size off the pipette", json_schema_extra={"unit": "um"}
    )
    fe_refine_size_um: float = Field(
        2.5, gt=0, description="FE element size under the pipette", json_schema_extra={"unit": "um"}
    )
    fe_refine_half_window_deg: float = Field(
        30.0,
        gt=0,
        lt=90,
        description="half angle of the refined window",
        json_schema_extra={"unit": "deg"},
    )
    fe_refine_depth_um: float = Field(
        20.0, gt=0, description="depth of the refined band", json_schema_extra={"unit": "um"}
    )
    fe_step_um: float = Field(
        2.5, gt=0, description="FE pipette advance per step", json_schema_extra={"unit": "um"}
    )
    fe_max_step_um: float = Field(
        1.25, gt=0, description="largest FE step after cutbacks", json_schema_extra={"unit": "um"}
    )
    fe_penalty_factor: float = Field(
        30.0,
        gt=0,
        description="FE contact penalty = factor * E_max / h",
        json_schema_extra={"unit": "1"},
    )
    fe_rtol: float = Field(
        1e-6,
        gt=0,
        lt=1e-2,
        description="FE Newton relative tolerance",
        json_schema_extra={"unit": "1"},
    )
    fe_contact_smoothing_um: float = Field(
        0.2,
        ge=0,
        description="C1 smoothing of the normal contact law, um (0: exact kink)",
        json_schema_extra={"unit": "um"},
    )
    fe_contact_quadrature_order: int = Field(
        20,
        ge=2,
        le=40,
        description="Gauss order of the FE contact quadrature per facet (4: the body's; the "
        "wedge's mouth corners press between 3 points and fold the ZP: docs/cases/nmsd_vs_fe.md)",
        json_schema_extra={"unit": "1"},
    )
    fe_pipette_edge_radius_um: float = Field(
        0.0,
        ge=0,
        description="the FE wedge's mouth edges rounded (0: sharp; docs/cases/nmsd_vs_fe.md)",
        json_schema_extra={"unit": "um"},
    )
    nmsd_spacings_across: SpacingsAcross = 17
    nmsd_dl_c: CriticalStrain = 0.8
    nmsd_damping: Damping = "nodal"
    nmsd_area_stiffness: float = Field(
        0.0,
        ge=0,
        description="NMSD cell area term kappa h / k1 (dimensionless, nmsd.area); 0: the paper's "
        "model. nmsd.area.area_stiffness_for_poisson(nu) gives the value for a Poisson ratio",
        json_schema_extra={"unit": "1"},
    )
    nmsd_zona_stiffness_ratio: Annotated[float, Field(gt=0)] | ZonaRatioReading = Field(
        1.0,
        description="NMSD ZP ring: k1, k2 of the links beyond cytoplasm_diameter_um / 2 times "
        "this (E_zp / E_cyto, nmsd.zona); 1: the paper's uniform lattice; 'afm_relaxed' / "
        "'afm_instantaneous': the ratio of the FE layers' relaxed / instantaneous moduli",
        json_schema_extra={"unit": "1"},
    )
    nmsd_contact_stiffness_nN_per_um: ContactStiffness = CONTACT_STIFFNESS_NN_PER_UM
    nmsd_k2_over_k1_min: float = Field(
        50.0,
        ge=0,
        description="calibration constraint k2 >= this x k1 (eq 8: 50; 0 lifts it, e.g. against "
        "a neo-Hookean FE reference, which does not stiffen like k2 >= 50 k1 cubic links)",
        json_schema_extra={"unit": "1"},
    )
    nmsd_n_steps: Steps = 50
    n_starts: Starts = 2
    max_evaluations: Evaluations = 60
    grid_spacing_um: float = Field(
        10.0,
        gt=0,
        description="spacing of the displacement comparison grid",
        json_schema_extra={"unit": "um"},
    )
    grid_margin_um: float = Field(
        8.0,
        ge=0,
        description="margin of the grid inside the cell boundary",
        json_schema_extra={"unit": "um"},
    )
    arrow_advances_um: list[Annotated[float, Field(gt=0)]] = Field(
        default_factory=lambda: [20.0, 40.0, 60.0],
        description="pipette advances of the displacement arrow plots",
        json_schema_extra={"unit": "um"},
    )
    goal_abs_um: float = Field(
        2.0,
        gt=0,
        description="displacement agreement goal, absolute",
        json_schema_extra={"unit": "um"},
    )
    goal_rel: float = Field(
        0.10,
        gt=0,
        description="displacement agreement goal, relative",
        json_schema_extra={"unit": "1"},
    )
    drag_scale: float = Field(
        0.01,
        gt=0,
        description="diagnostic: NMSD drag d0, d1 times this",
        json_schema_extra={"unit": "1"},
    )
    check_speed_um_s: float = Field(
        0.0,
        ge=0,
        description="rate check: press both models again at this speed, the NMSD with the "
        "constants calibrated at speed_um_s (not refitted); 0: off",
        json_schema_extra={"unit": "um/s"},
    )
    calibrate_both_speeds: bool = Field(
        False,
        description="fit the NMSD to the FE force at speed_um_s and check_speed_um_s together "
        "(eq 7 summed); the rate check then reports a fitted curve, not a prediction",
    )

    rules = (
        Relation("cytoplasm_diameter_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation("travel_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation("pipette_width_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation(  # the FE cell's ZP, (cell - cytoplasm) / 2, thinner than half its radius
            "cytoplasm_diameter_um",
            ">",
            lambda m: 0.5 * m.cell_diameter_um,
            "half the cell diameter (a ZP thinner than half the cell radius)",
        ),
        Relation(
            "fe_size_um",
            "<=",
            lambda m: 0.25 * m.cytoplasm_diameter_um,
            "half the cytoplasm radius",
        ),
        *(
            Relation(name, ">=", lambda m: m.cell_diameter_um / CELLS_ACROSS, FINEST)
            for name in ("fe_size_um", "fe_refine_size_um", "grid_spacing_um")
        ),
        Relation("fe_refine_size_um", "<=", lambda m: m.fe_size_um, "fe_size_um"),
        Relation(
            "fe_step_um",
            ">=",
            lambda m: m.travel_um / MAX_FRAMES,
            f"travel_um / {MAX_FRAMES} (at most {MAX_FRAMES} output frames)",
        ),
        Distinct("arrow_advances_um"),
        Relation("hold_half_width_um", "<", radius, "cell_diameter_um / 2"),
        Relation("grid_margin_um", "<", radius, "cell_diameter_um / 2 (a grid inside the cell)"),
        Relation("arrow_advances_um", "<=", lambda m: m.travel_um, "travel_um", measure="max"),
        Relation("fe_step_um", "<=", lambda m: m.travel_um, "travel_um"),
        Relation("fe_pipette_edge_radius_um", "<", edge_radius_limit, "what fits the mouth"),
        Setup(press_scenario),
    )

    _ratio = field_validator("nmsd_zona_stiffness_ratio", mode="before")(ratio_or_reading)
    _second_speed = model_validator(mode="after")(second_speed_given)
    _arrows = model_validator(mode="after")(arrows_on_frames)


METRICS = {
    "fe_force_end_uN": "FE force at the end of the travel times the effective thickness, uN",
    "fe_vs_table2_rmse_uN": "RMSE of the unfitted FE force against Table II, uN",
    "fe_vs_table2_r2": "R^2 of the unfitted FE force against Table II",
    "fe_over_table2_end": "FE force / measured force at the last Table II point within travel",
    "nmsd_fe_rmse_uN": "RMSE of the NMSD calibrated to the FE curve, uN",
    "nmsd_fe_r2": "R^2 of the NMSD calibrated to the FE curve",
    "nmsd_fe_similarity": "cosine similarity of NMSD and FE force curves",
    "nmsd_departure_um": "advance of the largest NMSD - FE force difference, um",
    "spindle_fe_end_um": "FE spindle displacement at the end of the travel, um",
    "spindle_nmsd_end_um": "NMSD spindle displacement at the end of the travel, um",
    "spindle_error_max_um": "largest spindle error |u_FE - u_NMSD| over the advances, um",
    "spindle_goal_ratio_max": "largest spindle error / max(goal_abs, goal_rel |u_FE|)",
    "near_best_fits": "calibration starts ending within 10 % of the best RMSE (eq 7 flat there)",
    "near_best_spindle_goal_ratio_min": "spindle_goal_ratio_max, lowest over the near-best fits",
    "near_best_spindle_goal_ratio_max": "spindle_goal_ratio_max, highest over the near-best fits",
    "grid_error_max_um": "largest point error over the grid and advances, um",
    "grid_error_mean_um": "mean point error over the grid and advances, um",
    "drag_scaled_spindle_error_max_um": "spindle error max, NMSD drag scaled down (NaN: diverged)",
    "penetration_max_um": "largest pipette penetration into the FE surface, um",
    "fe_steps": "FE solver steps",
    "fe_cutbacks": "FE step cutbacks",
    "fe_seconds": "wall time of the FE press, s",
    "calibration_seconds": "wall time of the NMSD calibration to the FE curve, s",
    "rate_check_force_r2": "R^2 of the NMSD force against the FE at check_speed_um_s (NaN: off)",
    "rate_check_spindle_goal_ratio_max": "spindle error / goal at check_speed_um_s (NaN: off)",
}
