"""Case kinds of the NMSD reduced model (seed 000): Table II calibration, spindle offset."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import Field

from nmsd.approach_pid import PidGains, pid_approach
from nmsd.calibration import MODELS, CalibrationResult, calibrate, fit_metrics
from nmsd.constants_file import constants_toml, read_constants, with_constants
from nmsd.cytoplasm_loss import loss_fraction
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import PressSetup, press_setup
from nmsd.spindle import predict_spindle_offset
from nmsd.tableII import read_force_displacement
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.nmsd_inputs import CalibrationInputs, SpindleInputs
from oocyte_fe.kinds.nmsd_report import calibration_report, spindle_report
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, case_kind

UN = 1e-3  # nN -> uN


PositiveUm = Annotated[float, Field(gt=0, le=1e4)]


def build_press(
    ctx: CaseContext,
    *,
    spacings_across: int,
    contact_stiffness_nN_per_um: float,
    n_steps: int,
    dl_c: float,
    gap_um: float = 0.0,
    damping: str = "nodal",
    symmetric: bool = True,
) -> tuple[PressSetup, NmsdParameters]:
    """The Table I lattice, pipette and hold from a case's inputs, and the base parameters.

    The geometry and speed fields (``cell_diameter_um``, ``pipette_width_um``, ...) are read
    from ``ctx.inputs``; an NMSD input error becomes an ``InputError`` naming the case file.
    """
    inp = ctx.inputs
    try:
        lattice = circular_lattice(inp.cell_diameter_um, spacings_across)
        setup = press_setup(
            lattice,
            inp.pipette_width_um,
            inp.tip_angle_deg,
            inp.hold_half_width_um,
            contact_stiffness_nN_per_um,
            inp.speed_um_s,
            inp.travel_um,
            n_steps,
            gap_um,
            symmetric,
        )
        base = NmsdParameters(
            dl_c=dl_c,
            node_mass=node_mass_for(inp.cell_diameter_um, lattice.n_nodes),
            damping=damping,
        )
    except InputError as exc:
        raise InputError(ctx.case_dir / "case.toml", f"inputs ({exc.field})", str(exc)) from None
    return setup, base


def _setup_and_data(ctx: CaseContext) -> tuple[PressSetup, NmsdParameters, object]:
    inp = ctx.inputs
    try:
        data = read_force_displacement(inp.data)
    except InputError as exc:
        raise InputError(ctx.case_dir / "case.toml", f"inputs ({exc.field})", str(exc)) from None
    setup, base = build_press(
        ctx,
        spacings_across=inp.spacings_across,
        contact_stiffness_nN_per_um=inp.contact_stiffness_nN_per_um,
        n_steps=inp.n_steps,
        dl_c=inp.dl_c,
        gap_um=inp.gap_um,
        damping=inp.damping,
        symmetric=inp.symmetric,
    )
    return setup, base, data


def _calibrate(ctx: CaseContext, setup, data, base, model: str) -> CalibrationResult:
    ctx.step(f"calibrating {model}")
    inp = ctx.inputs
    return calibrate(
        setup,
        data,
        model,
        base,
        inp.n_starts,
        max_evaluations=inp.max_evaluations,
        on_press=lambda done, most: ctx.progress(done, most, "calibration presses"),
        extra=tuple(inp.calibrate_extra),
    )


@case_kind(
    "nmsd_calibration",
    inputs=CalibrationInputs,
    metrics={
        "rmse_uN": "RMSE of the calibrated NMSD against the data file's measured forces, uN",
        "r2": "coefficient of determination of the NMSD fit",
        "similarity": "cosine similarity of NMSD and measured forces",
        "paper_rmse_uN": "RMSE of the data file's force_simulation column against its measured "
        "forces, uN (nan: no such column)",
        "rmse_linear_msd_uN": "RMSE of the linear MSD (k1, d0), uN (nan: not in models)",
        "rmse_msd_d0_uN": "RMSE of the cubic-linear MSD with d0 only, uN (nan: not in models)",
        "nmsd_not_identified": "NMSD constants the data do not identify (docs/nmsd.md)",
        "press_ms": "wall time of one 65 um press, ms",
        "calibration_s": "wall time of the NMSD calibration, s",
    },
)
def run_calibration(ctx: CaseContext) -> CaseOutcome:
    """Calibrate the MSD families of Section II.B.3 to the data file (eqs 7-8)."""
    inp = ctx.inputs
    unknown = set(inp.models) - set(MODELS)
    if unknown or "nmsd" not in inp.models:
        raise InputError(
            ctx.case_dir / "case.toml", "inputs.models", f"a list with nmsd of {MODELS}"
        )
    setup, base, data = _setup_and_data(ctx)
    results = {m: _calibrate(ctx, setup, data, base, m) for m in inp.models}
    best = results["nmsd"]
    if best.gap_um is not None:
        setup = setup.with_gap(best.gap_um)
    paper = None if data.paper_model_nN is None else fit_metrics(data.paper_model_nN, data.force_nN)
    ctx.step("rate dependence and snapshots")
    tic = time.perf_counter()
    press = setup.run(best.params, record_um=inp.snapshot_um)
    press_ms = 1e3 * (time.perf_counter() - tic)
    rate = {v: setup.run(best.params, speed_um_s=v) for v in inp.rate_speeds_um_s}
    figures, sections = calibration_report(
        ctx.output, data, results, paper, setup, press, rate, inp.travel_um
    )
    constants = ctx.output("nmsd_constants.toml")
    name = Path(inp.data).name
    rmse = best.metrics.rmse_nN * UN
    constants.write_text(
        constants_toml(best.params, inp.cell_diameter_um, inp.spacings_across, name, rmse)
    )
    sections.append(
        (
            "Constants file",
            f"`{constants.name}`: the NMSD constants (nN, um, s) and the lattice they hold on "
            f"({inp.cell_diameter_um:g} um, {inp.spacings_across} spacings across); an "
            "`nmsd_spindle_offset` case reads it as `constants_file` (copied into its folder) "
            "instead of calibrating again.",
        )
    )
    checks = [
        Check(
            "NMSD fit better than the mean force (R^2 >= 0)",
            best.metrics.r2,
            best.metrics.r2 >= 0,
            ">= 0 (below: a unit or sign mistake in the data, or a curve the press cannot follow)",
        )
    ]
    if "linear_msd" in results:
        checks.append(
            Check(
                "nmsd beats linear MSD (RMSE)",
                best.metrics.rmse_nN * UN,
                best.metrics.rmse_nN <= results["linear_msd"].metrics.rmse_nN,
                "<= linear MSD RMSE",
                unit="uN",
            )
        )
    fitted = {m: r.metrics.rmse_nN * UN for m, r in results.items()}
    return CaseOutcome(
        metrics={
            "rmse_uN": best.metrics.rmse_nN * UN,
            "r2": best.metrics.r2,
            "similarity": best.metrics.similarity,
            "paper_rmse_uN": math.nan if paper is None else paper.rmse_nN * UN,
            "rmse_linear_msd_uN": fitted.get("linear_msd", math.nan),
            "rmse_msd_d0_uN": fitted.get("msd_d0", math.nan),
            "nmsd_not_identified": float(len(best.identifiability.not_identified)),
            "press_ms": press_ms,
            "calibration_s": best.seconds,
        },
        figures=figures,
        sections=sections,
        checks=checks,
    )


@case_kind(
    "nmsd_spindle_offset",
    inputs=SpindleInputs,
    metrics={
        "offset_x_um": "predicted spindle X after the approach (paper frame), um",
        "offset_y_um": "predicted spindle Y after the approach (paper frame), um",
        "distance_to_paper_um": "distance between predicted and paper's offset point, um",
        "spindle_displacement_um": "distance the spindle moved, um",
        "pid_final_error_um": "PID final distance to the removal point, um",
        "pid_overshoot_um": "PID overshoot along the approach, um",
        "pid_settling_s": "time to stay within 0.1 um of the removal point, s",
        "loss_model_pct": "3D cytoplasm loss aspirating from the mouth to the moved spindle, %",
    },
)
def run_spindle(ctx: CaseContext) -> CaseOutcome:
    """Calibrate on the data file, predict the spindle offset, drive the PID approach to it."""
    inp = ctx.inputs
    setup, base, data = _setup_and_data(ctx)
    if inp.constants_file is None:
        cal = _calibrate(ctx, setup, data, base, "nmsd")
    else:
        ctx.step(f"the constants of {inp.constants_file.name} on the data")
        cal = with_constants(setup, read_constants(inp.constants_file), data)
    ctx.step("approach to the spindle")
    off = predict_spindle_offset(
        setup.lattice,
        cal.params,
        inp.spindle_initial_um,
        inp.pipette_width_um,
        inp.tip_angle_deg,
        inp.hold_half_width_um,
        inp.contact_stiffness_nN_per_um,
        inp.speed_um_s,
        inp.approach_step_um,
    )
    paper = np.asarray(inp.paper_offset_um)
    travel = np.linspace(0.0, off.advance_um, len(off.path_um))

    def target(s: float) -> np.ndarray:
        return np.array([np.interp(s, travel, off.path_um[:, k]) for k in range(2)])

    gains = PidGains(inp.kp, inp.ki, inp.kd, inp.period_s, inp.actuator_lag_s, inp.resolution_um)
    trace = pid_approach(target, gains, speed_um_s=inp.speed_um_s)
    moved = float(np.linalg.norm(off.final_um - off.initial_um))
    d = inp.cell_diameter_um
    loss = loss_fraction(moved + inp.spindle_length_um, inp.removal_pipette_um, d)
    figures, sections = spindle_report(
        ctx.output,
        setup.lattice,
        off,
        paper,
        trace,
        cal,
        data.source,
        inp.removal_pipette_um,
        d,
        inp.spindle_length_um,
    )
    return CaseOutcome(
        metrics={
            "offset_x_um": float(off.final_um[0]),
            "offset_y_um": float(off.final_um[1]),
            "distance_to_paper_um": float(np.linalg.norm(off.final_um - paper)),
            "spindle_displacement_um": moved,
            "pid_final_error_um": trace.final_error_um,
            "pid_overshoot_um": trace.overshoot_um,
            "pid_settling_s": trace.settling_time_s,
            "loss_model_pct": 100 * float(loss),
        },
        figures=figures,
        sections=sections,
    )
