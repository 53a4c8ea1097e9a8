"""The report of the case kind ``microchannel_vof``: Table 4 beside the VOF runs, the mesh,
cap and time-step studies, figures (the kind's run only solves)."""

from __future__ import annotations

import math

import numpy as np

from oocyte_fe.kinds.microchannel_vof_inputs import HPA, VofInputs
from oocyte_fe.microchannel.vof.extrapolation import TimeStepStudy, time_step_study
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.microchannel.vof.plotting import plot_ratio_histories, plot_vof_ratio
from oocyte_fe.microchannel.vof.post import snapshot, time_directories
from oocyte_fe.microchannel.vof.runner import (
    INSTALL_HINT,
)
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure


def _lookup(p: np.ndarray, values: np.ndarray, at: float) -> float:
    hit = np.nonzero(np.isclose(p, at))[0]
    return float(values[hit[0]]) if len(hit) else math.nan


def skipped_outcome(inp: VofInputs, table, kv_p: np.ndarray, kv_ratio: np.ndarray) -> CaseOutcome:
    rows = [
        "| pressure (hPa) | experiment | paper VOF | Kelvin-Voigt estimate |",
        "|---|---|---|---|",
    ]
    for p in inp.pressures_hPa:
        rows.append(
            f"| {p:g} | {_lookup(table.pressure, table.ratio_experiment, p * HPA):.3f} "
            f"| {_lookup(table.pressure, table.ratio_simulation, p * HPA):.3f} "
            f"| {_lookup(kv_p, kv_ratio, p * HPA):.3f} |"
        )
    text = f"SKIPPED: OpenFOAM is not installed; the VOF was not run. Install: `{INSTALL_HINT}`."
    return CaseOutcome(
        metrics={},
        sections=[("SKIPPED", text), ("Kelvin-Voigt estimate (reduced model)", "\n".join(rows))],
        skipped=f"OpenFOAM is not installed: {INSTALL_HINT}",
    )


def _pct(a: float, b: float) -> float:
    return 100.0 * abs(a / b - 1.0)


def report_outcome(
    ctx: CaseContext,
    inp: VofInputs,
    table,
    kv_p: np.ndarray,
    kv_ratio: np.ndarray,
    pressures: np.ndarray,
    runs: list[JunctionRun],
    extra: dict[str, JunctionRun],
) -> CaseOutcome:
    rows = [
        "| p (hPa) | U_A (m/s) | ratio exp | ratio paper VOF | ratio VOF here (x = 0) "
        "| min ratio | ratio at end | err vs exp (%) | Kelvin-Voigt | cells | steps | wall (s) "
        "| s per sim. ms | max vol. err |",
        "|" + "---|" * 14,
    ]
    errs, paper_errs, kv_errs, vol = [], [], [], []
    for p, r in zip(pressures, runs, strict=True):
        exp = _lookup(table.pressure, table.ratio_experiment, p)
        paper = _lookup(table.pressure, table.ratio_simulation, p)
        kv = _lookup(kv_p, kv_ratio, p)
        v = max(float(np.max(np.abs(r.history.volume_error[k]))) for k in ("zp", "cytoplasm"))
        vol.append(v)
        err = _pct(r.ratio_at_junction, exp)
        if math.isfinite(err):
            errs.append(err)
            paper_errs.append(_pct(r.ratio_at_junction, paper))
        kv_errs.append(_pct(kv, exp))
        rows.append(
            f"| {p / HPA:g} | {r.velocity_a * 1e-6:.3f} | {exp:.3f} | {paper:.3f} "
            f"| {r.ratio_at_junction:.4f} | {r.min_ratio:.4f} | {r.history.ratio[-1]:.4f} "
            f"| {err:.2f} | {kv:.3f} | {r.n_cells} | {r.steps} | {r.wall_seconds:.0f} "
            f"| {r.seconds_per_ms:.0f} | {v:.1e} |"
        )
    metrics: dict[str, float | list[float]] = {
        "ratio_at_junction": [r.ratio_at_junction for r in runs],
        "ratio_end": [float(r.history.ratio[-1]) for r in runs],
        "mean_error_experiment_pct": float(np.mean(errs)) if errs else math.nan,
        "mean_error_paper_vof_pct": float(np.mean(paper_errs)) if paper_errs else math.nan,
        "kelvin_voigt_mean_error_pct": float(np.mean(kv_errs)),
        "max_volume_error": max(vol),
        "seconds_per_ms": runs[0].seconds_per_ms,
    }
    notes = []
    dt_runs = [r for label, r in extra.items() if "_dt" in label]
    for label, r in ((k, v) for k, v in extra.items() if "_dt" not in k):
        # at the junction when both runs reach it, else at the end of the (equal) window
        where = "x = 0" if math.isfinite(r.ratio_at_junction * runs[0].ratio_at_junction) else "end"
        ours, base = (
            (r.ratio_at_junction, runs[0].ratio_at_junction)
            if where == "x = 0"
            else (float(r.history.ratio[-1]), float(runs[0].history.ratio[-1]))
        )
        change = _pct(ours, base)
        key = "mesh_change_pct" if "_dx" in label else "cap_change_pct"
        metrics[key] = change
        notes.append(
            f"- {label}: ratio at {where} {ours:.4f} against {base:.4f} ({change:.2f} %; "
            f"deformation 1 - b/a {1 - ours:.4f} against {1 - base:.4f}); ratio at end "
            f"{r.history.ratio[-1]:.4f} against {runs[0].history.ratio[-1]:.4f} (x = "
            f"{r.history.centroid[-1, 0]:.0f} against {runs[0].history.centroid[-1, 0]:.0f} um); "
            f"{r.n_cells} cells, {r.wall_seconds:.0f} s wall"
        )
    checks = [
        Check(
            "max_volume_error",
            max(vol),
            max(vol) <= inp.max_volume_error,
            f"<= {inp.max_volume_error:g}",
        ),
        Check(
            "ratios_in_(0,1]",
            float(min(r.min_ratio for r in runs)),
            all(0 < r.min_ratio <= 1 for r in runs),
            "0 < b/a <= 1",
        ),
    ]
    if "mesh_change_pct" in metrics:
        change = float(metrics["mesh_change_pct"])  # type: ignore[arg-type]
        checks.append(
            Check(
                "mesh_change_pct",
                change,
                change <= inp.max_mesh_change_pct,
                f"<= {inp.max_mesh_change_pct:g} %",
            )
        )
    dt_text = "not run"
    if dt_runs:
        study_runs = [runs[0], *dt_runs]
        study = time_step_study(
            inp.time_step_s,
            [r.ratio_at_junction for r in study_runs],
            [float(r.history.ratio[-1]) for r in study_runs],
        )
        dt_text = _dt_section(study, study_runs)
        metrics.update(study.metrics())
    folders = time_directories(runs[0].case)
    shot = snapshot(
        folders[-1][1],
        _layout(inp, runs[0]),
        ("medium", "zp", "cytoplasm"),
        ctx.output("snapshot_end.png"),
    )
    fig1 = plot_ratio_histories(
        [f"{p / HPA:g} hPa" for p in pressures],
        [r.history for r in runs],
        ctx.output("ratio_history.png"),
    )
    figures = [
        Figure(shot.name, f"Phases at the end of the {pressures[0] / HPA:g} hPa run"),
        Figure(fig1.name, "Axis ratio b/a of the cell against time (VOF)"),
    ]
    if len(runs) > 1:
        fig2 = plot_vof_ratio(
            table.pressure / HPA,
            table.ratio_experiment,
            table.ratio_simulation,
            pressures / HPA,
            np.array(metrics["ratio_at_junction"]),
            kv_p / HPA,
            kv_ratio,
            ctx.output("vof_ratio.png"),
        )
        figures.append(Figure(fig2.name, "Axis ratio against pressure: experiment, paper, ours"))
    sections = [
        ("Per-pressure comparison", "\n".join(rows)),
        ("Mesh and viscosity-cap sensitivity (first pressure)", "\n".join(notes) or "not run"),
        ("Time-step convergence (first pressure)", dt_text),
        (
            "Files",
            "Each run's OpenFOAM case is in `openfoam/<run>/` (open `case.foam` in ParaView for "
            "the time series).",
        ),
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)


def _dt_section(study: TimeStepStudy, runs: list[JunctionRun]) -> str:
    """The report's time-step table and the sentence on its dt -> 0 limit."""
    ratios, where, dt = study.ratios, study.where, study.dt_s
    rows = [
        f"| dt (s) | b/a at {where} | 1 - b/a | 1 - b/a against the previous dt | steps "
        "| wall (s) |",
        "|---|---|---|---|---|---|",
    ]
    for k, r in enumerate(runs):
        change = f"{100 * ((1 - ratios[k]) / (1 - ratios[k - 1]) - 1):+.1f} %" if k else ""
        rows.append(
            f"| {dt / 2**k:g} | {ratios[k]:.5f} | {1 - ratios[k]:.5f} | {change} "
            f"| {r.steps} | {r.wall_seconds:.0f} |"
        )
    lines = ["\n".join(rows), ""]
    ex = study.extrapolation
    if ex is None:
        lines.append("Two time steps: no observed order, no dt -> 0 estimate (set 2 refinements).")
    elif not ex.converging:
        lines.append(
            f"The differences of b/a do not shrink over the finest three time steps (factor "
            f"{ex.factor:.2f} per halving): no dt -> 0 estimate."
        )
    else:
        base = ratios[0]
        how = (
            f"Richardson over the finest three, observed order p = {ex.order:.2f}"
            if ex.monotone
            else f"the differences alternate, factor q = {ex.factor:.2f} per halving: no "
            "observed order; the geometric (Aitken) limit, which lies between the two "
            "finest values, is an estimate only"
        )
        lines.append(
            f"**dt -> 0 at {where} ({how}): b/a = {ex.limit:.5f}, 1 - b/a = "
            f"{1 - ex.limit:.5f}**, against b/a = {base:.5f}, 1 - b/a = {1 - base:.5f} at the "
            f"case's dt = {dt:g} s: its dt error is {100 * (base / ex.limit - 1):+.2f} % in "
            f"b/a and {100 * ((1 - base) / (1 - ex.limit) - 1):+.0f} % in 1 - b/a."
        )
    return "\n".join(lines)


def _layout(inp: VofInputs, run: JunctionRun):
    return inp.geometry.to_geometry().layout(inp.dx_um, run.velocity_a, run.velocity_b)
