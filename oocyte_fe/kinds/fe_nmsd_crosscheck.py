"""Case kind ``nmsd_vs_fe``: one pipette press by the layered plane-strain FE model and by the
NMSD lattice calibrated to the FE force curve; forces and internal displacements compared
(issue 9)."""

from __future__ import annotations

from dataclasses import replace
from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from afm.curve_io import read_creep
from nmsd.calibration import CalibrationResult, calibrate, near_best
from nmsd.displacement_field import DisplacementField, press_displacements
from nmsd.errors import NmsdDivergence
from nmsd.parameters import NmsdParameters
from nmsd.pipette import (
    CONTACT_STIFFNESS_NN_PER_UM,
    HOLD_HALF_WIDTH_UM,
    TABLE_I_TIP_ANGLE_DEG,
    TABLE_I_WIDTH_UM,
)
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement, read_force_displacement
from nmsd.zona import zona_link_factor
from oocyte_fe.crosscheck.agreement import (
    displacement_agreement,
    force_agreement,
    largest_departure,
)
from oocyte_fe.crosscheck.fe_press import FeSettings, pipette_at, run_fe_press
from oocyte_fe.crosscheck.report import crosscheck_figures, crosscheck_sections
from oocyte_fe.crosscheck.scenario import PressScenario, interior_grid
from oocyte_fe.crosscheck.zp_material import LayerMaterials, afm_layer_materials
from oocyte_fe.errors import InputError
from oocyte_fe.io import FieldSeriesWriter, write_history_csv
from oocyte_fe.kinds.data_templates import CREEP, TABLE_II
from oocyte_fe.kinds.nmsd_cases import build_press
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind
from oocyte_fe.runner.schema import CaseInputs, DataFile, DataReader

UN = 1e-3  # nN -> uN
ZonaRatioReading = Literal["afm_relaxed", "afm_instantaneous"]


class CrosscheckInputs(CaseInputs):
    """Scenario, materials, FE mesh/steps, NMSD lattice/calibration, comparison grid."""

    creep_data: Annotated[DataFile, DataReader(read_creep)] = Field(
        description="ZP force-clamp creep CSV (afm.curve_io format)",
        json_schema_extra=CREEP,
    )
    table2_data: Annotated[DataFile, DataReader(read_force_displacement)] = Field(
        description="Table II CSV: displacement_um, force_*_uN",
        json_schema_extra=TABLE_II,
    )
    cell_diameter_um: float = Field(
        115.625, gt=0, description="Table I R_c, outer diameter", json_schema_extra={"unit": "um"}
    )
    cytoplasm_diameter_um: float = Field(
        83.597, gt=0, description="Table I R_zp, inside the ZP", json_schema_extra={"unit": "um"}
    )
    pipette_width_um: float = Field(
        TABLE_I_WIDTH_UM,
        gt=0,
        description="injection pipette width (Table I d_inj)",
        json_schema_extra={"unit": "um"},
    )
    tip_angle_deg: float = Field(
        TABLE_I_TIP_ANGLE_DEG,
        ge=0,
        lt=180,
        description="injection pipette tip angle (Table I theta_inj)",
        json_schema_extra={"unit": "deg"},
    )
    speed_um_s: float = Field(
        30.0, gt=0, description="pipette speed", json_schema_extra={"unit": "um/s"}
    )
    hold_half_width_um: float = Field(
        HOLD_HALF_WIDTH_UM,
        gt=0,
        description="holding pipette mouth half-width",
        json_schema_extra={"unit": "um"},
    )
    spindle_paper_um: tuple[float, float] = Field(
        (15.8718, 18.1392),
        description="the paper's spindle position (x, y)",
        json_schema_extra={"unit": "um"},
    )
    travel_um: float = Field(
        62.5, gt=0, description="pipette travel, um", json_schema_extra={"unit": "um"}
    )
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
        gt=0,
        lt=90,
        description="AFM cone half angle of the creep record",
        json_schema_extra={"unit": "deg"},
    )
    thickness_um: float = Field(
        115.625,
        gt=0,
        description="effective plane-strain thickness",
        json_schema_extra={"unit": "um"},
    )
    fe_size_um: float = Field(
        6.0,
        gt=0,
        description="FE element size away from the pipette",
        json_schema_extra={"unit": "um"},
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
    nmsd_spacings_across: int = Field(
        17,
        ge=2,
        le=101,
        description="NMSD grid spacings across the diameter",
        json_schema_extra={"unit": "1"},
    )
    nmsd_dl_c: float = Field(
        0.8, gt=0, description="NMSD critical link strain of eq 3", json_schema_extra={"unit": "1"}
    )
    nmsd_damping: Literal["nodal", "link"] = Field(
        "nodal", description="NMSD eq 6 per node (as printed) or per link (Voigt, Fig. 3)"
    )
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
    nmsd_contact_stiffness_nN_per_um: float = Field(
        CONTACT_STIFFNESS_NN_PER_UM,
        gt=0,
        description="NMSD penalty stiffness of the pipette contact",
        json_schema_extra={"unit": "nN/um"},
    )
    nmsd_k2_over_k1_min: float = Field(
        50.0,
        ge=0,
        description="calibration constraint k2 >= this x k1 (eq 8: 50; 0 lifts it, e.g. against "
        "a neo-Hookean FE reference, which does not stiffen like k2 >= 50 k1 cubic links)",
        json_schema_extra={"unit": "1"},
    )
    nmsd_n_steps: int = Field(
        50,
        ge=1,
        le=100_000,
        description="NMSD steps over the travel",
        json_schema_extra={"unit": "1"},
    )
    n_starts: int = Field(
        2, ge=1, le=100, description="calibration starts", json_schema_extra={"unit": "1"}
    )
    max_evaluations: int = Field(
        60,
        ge=4,
        le=100_000,
        description="press simulations per calibration start",
        json_schema_extra={"unit": "1"},
    )
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


def _scenario(ctx: CaseContext) -> tuple[PressScenario, FeSettings]:
    inp = ctx.inputs
    source = str(ctx.case_dir / "case.toml")
    scenario = PressScenario(
        inp.cell_diameter_um,
        inp.cytoplasm_diameter_um,
        inp.pipette_width_um,
        inp.tip_angle_deg,
        inp.speed_um_s,
        inp.hold_half_width_um,
        tuple(inp.spindle_paper_um),
        source=source,
    )
    settings = FeSettings(
        inp.fe_size_um,
        inp.fe_refine_size_um,
        inp.fe_refine_half_window_deg,
        inp.fe_refine_depth_um,
        inp.fe_step_um,
        inp.fe_max_step_um,
        inp.fe_penalty_factor,
        inp.fe_rtol,
        inp.fe_contact_smoothing_um,
        source=source,
    )
    return scenario, settings


def _zona_ratio(inp: CrosscheckInputs, materials: LayerMaterials) -> float:
    """The NMSD ring's spring factor: the input number, or the FE layers' modulus ratio."""
    ratio = inp.nmsd_zona_stiffness_ratio
    if isinstance(ratio, str):
        return materials.stiffness_ratio(relaxed=ratio == "afm_relaxed")
    return ratio


def _nmsd_setup(ctx: CaseContext, zona_ratio: float) -> tuple[PressSetup, NmsdParameters]:
    inp = ctx.inputs
    setup, base = build_press(
        ctx,
        spacings_across=inp.nmsd_spacings_across,
        contact_stiffness_nN_per_um=inp.nmsd_contact_stiffness_nN_per_um,
        n_steps=inp.nmsd_n_steps,
        dl_c=inp.nmsd_dl_c,
        damping=inp.nmsd_damping,
    )
    params = base.with_values(
        area_stiffness=inp.nmsd_area_stiffness,
        zona_stiffness_ratio=zona_ratio,
        zona_inner_radius_um=0.5 * inp.cytoplasm_diameter_um,
    )
    try:
        zona_link_factor(setup.lattice, params)
    except InputError as exc:
        raise InputError(
            ctx.case_dir / "case.toml", "inputs (cytoplasm_diameter_um)", str(exc)
        ) from None
    return setup, params


def _fe_check_press(
    ctx: CaseContext,
    scenario: PressScenario,
    materials: LayerMaterials,
    settings: FeSettings,
    points: np.ndarray,
) -> tuple[ForceDisplacement, np.ndarray] | None:
    """The FE press at ``check_speed_um_s``: its force curve (nN) and point displacements
    (k, p, 2) um, or None when the rate check is off."""
    inp = ctx.inputs
    if inp.check_speed_um_s == 0:
        return None
    ctx.step(f"FE press at the check speed, {inp.check_speed_um_s:g} um/s")
    slow = replace(scenario, speed_um_s=inp.check_speed_um_s)
    fe = run_fe_press(slow, materials, settings, inp.travel_um, points, ctx.log)
    curve = ForceDisplacement(fe.advance_um, fe.force_nN_per_um * inp.thickness_um, source="FE")
    return curve, fe.point_displacement_um


def _rate_check(
    ctx: CaseContext,
    check: tuple[ForceDisplacement, np.ndarray] | None,
    setup: PressSetup,
    params: NmsdParameters,
    points: np.ndarray,
) -> tuple[float, float]:
    """The NMSD pressed at ``check_speed_um_s`` with ``params`` against the FE there: force
    R^2 and the largest spindle error / goal (NaN, NaN when off or diverged).

    A force-only calibration at one speed does not fix how the NMSD splits its resistance
    between springs and dashpots; a second speed does (docs/cases/nmsd_vs_fe.md).
    """
    inp = ctx.inputs
    if check is None:
        return float("nan"), float("nan")
    curve, u_fe = check
    slow = replace(setup, speed_um_s=inp.check_speed_um_s)
    advances = curve.displacement_um[1:]
    try:
        field = press_displacements(slow, params, advances, points[:1])
    except NmsdDivergence as exc:
        ctx.log.warning("rate check: the NMSD press diverged at the check speed: %s", exc)
        return float("nan"), float("nan")
    nmsd_nN = field.press.force_at(curve.displacement_um)
    ratio = _spindle_goal_ratio(field, advances, u_fe[1:, :1], inp)
    return force_agreement(nmsd_nN, curve.force_nN).r2, ratio


def _spindle_goal_ratio(
    field: DisplacementField, advances: np.ndarray, u_fe_spindle: np.ndarray, inp: CrosscheckInputs
) -> float:
    """Largest spindle error / goal over ``advances`` of an NMSD press against the FE's
    spindle displacements (k, 1, 2) um."""
    u_nm = np.array([field.at_points[float(a)] for a in advances])
    agree = displacement_agreement(advances, u_fe_spindle, u_nm, 0, inp.goal_abs_um, inp.goal_rel)
    return float(agree.spindle_ratio.max())


@case_kind("nmsd_vs_fe", inputs=CrosscheckInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Layered FE press and NMSD press (calibrated to it): forces and internal motion."""
    inp: CrosscheckInputs = ctx.inputs  # type: ignore[assignment]
    scenario, settings = _scenario(ctx)
    ctx.step("ZP material from the AFM creep record")
    materials = afm_layer_materials(
        inp.creep_data, inp.cytoplasm_E_kPa, inp.nu, inp.afm_half_angle_deg
    )
    grid = interior_grid(scenario.radius_um, inp.grid_spacing_um, inp.grid_margin_um)
    points = np.vstack([scenario.spindle_world_um, grid])

    ctx.step("FE press (plane strain)")
    fe = run_fe_press(scenario, materials, settings, inp.travel_um, points, log=ctx.log)
    fe_nN = fe.force_nN_per_um * inp.thickness_um
    table = read_force_displacement(inp.table2_data)
    within = table.displacement_um <= fe.advance_um[-1] + 1e-9
    d_tab = table.displacement_um[within]
    fe_at_tab = np.interp(d_tab, fe.advance_um, fe_nN)
    vs_table = force_agreement(fe_at_tab, table.force_nN[within])

    ctx.step("NMSD calibrated to the FE force curve")
    setup, base = _nmsd_setup(ctx, _zona_ratio(inp, materials))
    fe_curve = ForceDisplacement(fe.advance_um, fe_nN, source="FE press")
    check = _fe_check_press(ctx, scenario, materials, settings, points)
    also = []
    if check is not None and inp.calibrate_both_speeds:
        also = [(replace(setup, speed_um_s=inp.check_speed_um_s), check[0])]
    cal = calibrate(
        setup,
        fe_curve,
        "nmsd",
        base,
        inp.n_starts,
        max_evaluations=inp.max_evaluations,
        on_press=lambda done, most: ctx.progress(done, most, "calibration presses"),
        k2_over_k1_min=inp.nmsd_k2_over_k1_min,
        also=also,
    )
    vs_fe = force_agreement(cal.force_nN, fe_nN)
    depart_um, depart_nN = largest_departure(fe.advance_um, cal.force_nN, fe_nN)

    ctx.step("displacement fields of both models")
    advances = fe.advance_um[1:]
    field = press_displacements(setup, cal.params, advances, points)
    u_nm = np.array([field.at_points[float(a)] for a in advances])
    u_fe = fe.point_displacement_um[1:]
    agree = displacement_agreement(advances, u_fe, u_nm, 0, inp.goal_abs_um, inp.goal_rel)
    scale, slow_error = _drag_scaled_error(setup, cal.params, advances, points[0], u_fe[:, 0], inp)
    spread = _near_best_spindle_ratios(setup, cal, advances, points[:1], u_fe[:, :1], inp)
    rate = _rate_check(ctx, check, setup, cal.params, points)

    ctx.step("figures and tables")
    arrows = [a for a in inp.arrow_advances_um if np.any(np.isclose(advances, a))]
    figures = crosscheck_figures(
        ctx.output,
        fe,
        fe_nN,
        inp.thickness_um,
        cal,
        vs_fe,
        table,
        agree,
        points,
        u_fe,
        u_nm,
        arrows,
        scenario,
        setup,
    )
    with FieldSeriesWriter(ctx.output("fields"), fe.mesh, "press") as series:
        for k, advance in enumerate(fe.advance_um):
            series.write(
                advance / scenario.speed_um_s,  # s
                fe.vertex_displacement_um[k],
                pressure=fe.vertex_pressure_kPa[k],
                obstacles={"pipette": np.asarray(pipette_at(scenario, advance).points)},
            )
    write_history_csv(
        ctx.output("force_history.csv"),
        {
            "advance": fe.advance_um,
            "force_fe_per_thickness": fe.force_nN_per_um,
            "force_fe": fe_nN * UN,
            "force_nmsd": cal.force_nN * UN,
            "penetration": fe.penetration_um,
        },
        {
            "advance": "um",
            "force_fe_per_thickness": "nN_per_um",
            "force_fe": "uN",
            "force_nmsd": "uN",
            "penetration": "um",
        },
    )
    write_history_csv(
        ctx.output("spindle_history.csv"),
        {
            "advance": advances,
            "spindle_fe_ux": agree.spindle_fe_um[:, 0],
            "spindle_fe_uy": agree.spindle_fe_um[:, 1],
            "spindle_nmsd_ux": agree.spindle_nmsd_um[:, 0],
            "spindle_nmsd_uy": agree.spindle_nmsd_um[:, 1],
            "spindle_error": agree.spindle_error_um,
            "goal": agree.spindle_tolerance_um,
            "grid_error_max": agree.error_um.max(axis=1),
        },
        {k: "um" for k in ("advance", "spindle_fe_ux", "spindle_fe_uy", "spindle_nmsd_ux",
                           "spindle_nmsd_uy", "spindle_error", "goal", "grid_error_max")},
    )  # fmt: skip

    metrics = {
        "fe_force_end_uN": float(fe_nN[-1] * UN),
        "fe_vs_table2_rmse_uN": vs_table.rmse_nN * UN,
        "fe_vs_table2_r2": vs_table.r2,
        "fe_over_table2_end": float(fe_at_tab[-1] / table.force_nN[within][-1]),
        "nmsd_fe_rmse_uN": vs_fe.rmse_nN * UN,
        "nmsd_fe_r2": vs_fe.r2,
        "nmsd_fe_similarity": vs_fe.similarity,
        "nmsd_departure_um": depart_um,
        "spindle_fe_end_um": float(np.linalg.norm(agree.spindle_fe_um[-1])),
        "spindle_nmsd_end_um": float(np.linalg.norm(agree.spindle_nmsd_um[-1])),
        "spindle_error_max_um": float(agree.spindle_error_um.max()),
        "spindle_goal_ratio_max": float(agree.spindle_ratio.max()),
        "near_best_fits": float(len(spread)),
        "near_best_spindle_goal_ratio_min": min(spread, default=float("nan")),
        "near_best_spindle_goal_ratio_max": max(spread, default=float("nan")),
        "grid_error_max_um": agree.max_error_um,
        "grid_error_mean_um": float(agree.error_um.mean()),
        "drag_scaled_spindle_error_max_um": float(slow_error.max()),
        "penetration_max_um": float(fe.penetration_um.max()),
        "fe_steps": float(fe.steps),
        "fe_cutbacks": float(fe.cutbacks),
        "fe_seconds": fe.seconds,
        "calibration_seconds": cal.seconds,
        "rate_check_force_r2": rate[0],
        "rate_check_spindle_goal_ratio_max": rate[1],
    }
    return CaseOutcome(
        metrics=metrics,
        figures=figures,
        sections=crosscheck_sections(
            materials,
            inp.creep_data.name,
            inp.nmsd_zona_stiffness_ratio,
            cal,
            vs_fe,
            agree,
            slow_error,
            scale,
            (depart_um, depart_nN),
            fe,
        ),
    )


def _near_best_spindle_ratios(
    setup: PressSetup,
    cal: CalibrationResult,
    advances: np.ndarray,
    spindle: np.ndarray,
    u_fe_spindle: np.ndarray,
    inp: CrosscheckInputs,
) -> list[float]:
    """Spindle goal ratio (max over the advances) of every start within 10 % of the best RMSE.

    Eq 7 does not tell these fits apart; the spread of their spindle predictions is how far
    the force curve pins the spindle path (docs/nmsd.md, "Starts that cannot be pressed, and
    near-equal fits").
    """
    ratios = []
    for end in near_best(cal, 0.1):
        try:
            field = press_displacements(setup, end.params, advances, spindle)
        except NmsdDivergence:
            continue
        ratios.append(_spindle_goal_ratio(field, advances, u_fe_spindle, inp))
    return ratios


def _drag_scaled_error(setup, params, advances, spindle, u_fe_spindle, inp: CrosscheckInputs):
    """Diagnostic: spindle error (um) with the NMSD drag scaled by ``drag_scale`` (or ten
    times that if the nearly undamped lattice diverges); NaN if both diverge."""
    for scale in (inp.drag_scale, 10 * inp.drag_scale):
        slow = params.with_values(d0=params.d0 * scale, d1=params.d1 * scale)
        try:
            field = press_displacements(setup, slow, advances, spindle[None, :])
        except NmsdDivergence:
            continue
        u = np.array([field.at_points[float(a)][0] for a in advances])
        return scale, np.linalg.norm(u - u_fe_spindle, axis=1)
    return inp.drag_scale, np.full(len(advances), np.nan)
