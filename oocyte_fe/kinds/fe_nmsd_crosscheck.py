"""Case kind ``nmsd_vs_fe``: one pipette press by the layered plane-strain FE model and by the
NMSD lattice calibrated to the FE force curve; forces and internal displacements compared
(issue 9)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from nmsd.calibration import calibrate
from nmsd.displacement_field import press_displacements
from nmsd.parameters import NmsdParameters
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement, read_force_displacement
from nmsd.zona import zona_link_factor
from oocyte_fe.crosscheck.agreement import (
    displacement_agreement,
    force_agreement,
    largest_departure,
)
from oocyte_fe.crosscheck.comparison import (
    drag_scaled_error,
    near_best_spindle_ratios,
    rate_check,
    zona_ring_ratio,
)
from oocyte_fe.crosscheck.fe_press import FePress, FeSettings, run_fe_presses
from oocyte_fe.crosscheck.report import (
    crosscheck_figures,
    crosscheck_sections,
    write_press_outputs,
)
from oocyte_fe.crosscheck.scenario import PressScenario, interior_grid
from oocyte_fe.crosscheck.zp_material import afm_layer_materials
from oocyte_fe.errors import InputError
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.kinds.crosscheck_inputs import METRICS, CrosscheckInputs
from oocyte_fe.kinds.nmsd_cases import build_press
from oocyte_fe.kinds.nmsd_checks import press_scenario
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind

UN = 1e-3  # nN -> uN


def press_settings(inp: CrosscheckInputs, source: str) -> tuple[PressScenario, FeSettings]:
    """The press scenario and the FE press's settings of a case's inputs (``source``: its
    ``case.toml``, named in refusals)."""
    scenario = press_scenario(inp, source)
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
        inp.fe_contact_quadrature_order,
        inp.fe_pipette_edge_radius_um,
        source=source,
    )
    return scenario, settings


def nmsd_setup(ctx: CaseContext, zona_ratio: float) -> tuple[PressSetup, NmsdParameters]:
    """The Table I lattice and press of the case, the ring at ``zona_ratio``."""
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


def _fe_presses(
    ctx: CaseContext,
    scenario: PressScenario,
    materials: LayerMaterials,
    settings: FeSettings,
    points: np.ndarray,
) -> tuple[FePress, tuple[ForceDisplacement, np.ndarray] | None]:
    """The FE press at the scenario's speed and, unless the rate check is off, at
    ``check_speed_um_s``: its force curve (nN) and point displacements (k, p, 2) um. Both are
    asked for at once, so that a case pressing the same model solves the other one meanwhile."""
    inp = ctx.inputs
    speeds = [scenario] + (
        [replace(scenario, speed_um_s=inp.check_speed_um_s)] if inp.check_speed_um_s else []
    )
    ctx.step(f"FE presses (plane strain) at {', '.join(f'{s.speed_um_s:g}' for s in speeds)} um/s")
    fe, *slow = run_fe_presses(speeds, materials, settings, inp.travel_um, points, ctx.log)
    if not slow:
        return fe, None
    curve = ForceDisplacement(
        slow[0].advance_um, slow[0].force_nN_per_um * inp.thickness_um, source="FE"
    )
    return fe, (curve, slow[0].point_displacement_um)


@case_kind("nmsd_vs_fe", inputs=CrosscheckInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Layered FE press and NMSD press (calibrated to it): forces and internal motion."""
    inp: CrosscheckInputs = ctx.inputs  # type: ignore[assignment]
    scenario, settings = press_settings(inp, str(ctx.case_dir / "case.toml"))
    ctx.step("ZP material from the AFM creep record")
    materials = afm_layer_materials(
        inp.creep_data, inp.cytoplasm_E_kPa, inp.nu, inp.afm_half_angle_deg
    )
    grid = interior_grid(scenario.radius_um, inp.grid_spacing_um, inp.grid_margin_um)
    points = np.vstack([scenario.spindle_world_um, grid])

    fe, check = _fe_presses(ctx, scenario, materials, settings, points)
    fe_nN = fe.force_nN_per_um * inp.thickness_um
    table = read_force_displacement(inp.table2_data)
    within = table.displacement_um <= fe.advance_um[-1] + 1e-9
    d_tab = table.displacement_um[within]
    fe_at_tab = np.interp(d_tab, fe.advance_um, fe_nN)
    vs_table = force_agreement(fe_at_tab, table.force_nN[within])

    ctx.step("NMSD calibrated to the FE force curve")
    setup, base = nmsd_setup(ctx, zona_ring_ratio(inp.nmsd_zona_stiffness_ratio, materials))
    fe_curve = ForceDisplacement(fe.advance_um, fe_nN, source="FE press")
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
    goal = (inp.goal_abs_um, inp.goal_rel)
    scale, slow_error = drag_scaled_error(
        setup, cal.params, advances, points[0], u_fe[:, 0], inp.drag_scale
    )
    spread = near_best_spindle_ratios(setup, cal, advances, points[:1], u_fe[:, :1], *goal)
    rate = rate_check(check, setup, cal.params, points, inp.check_speed_um_s, *goal, ctx.log)

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
        settings.edge_radius_um,
    )
    write_press_outputs(ctx.output, fe, fe_nN, cal, agree, scenario, settings.edge_radius_um)

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
