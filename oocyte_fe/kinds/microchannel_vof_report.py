"""The report of the case kind ``microchannel_vof``: Table 4 headlined by the case's model,
the beside model, the studies (:mod:`.microchannel_vof_studies`) and figures (the kind's run
only solves)."""

from __future__ import annotations

import math

import numpy as np

from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.kinds.microchannel_vof_checks import courant_check
from oocyte_fe.kinds.microchannel_vof_converged import converged_section, pressure_limits
from oocyte_fe.kinds.microchannel_vof_elastic import elastic_section
from oocyte_fe.kinds.microchannel_vof_inputs import HPA, KG_M3, PA_S, VofInputs
from oocyte_fe.kinds.microchannel_vof_recompute import recompute_section, recompute_summary
from oocyte_fe.kinds.microchannel_vof_runs import BESIDE, mesh_label, run_specs
from oocyte_fe.kinds.microchannel_vof_studies import (
    dt_study,
    mesh_study,
    sensitivity_notes,
    traction_study,
)
from oocyte_fe.microchannel.elastic_iteration import DeformRecompute
from oocyte_fe.microchannel.elastic_junction import ElasticAtPressure
from oocyte_fe.microchannel.vof.isoadvector import LIQUID_CELL, MODEL_SOLVER
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.microchannel.vof.plotting import plot_ratio_histories, plot_vof_ratio
from oocyte_fe.microchannel.vof.post import snapshot, time_directories
from oocyte_fe.microchannel.vof.runner import INSTALL_HINT, find_openfoam
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
    recompute: list[tuple[float, DeformRecompute | str]] = (),
    one_way: list[ElasticAtPressure] | str = "not computed (the liquid-cell model only)",
) -> CaseOutcome:
    beside = {k: v for k, v in extra.items() if k.startswith(BESIDE) and "_dt" not in k}
    beside_at = {round(float(r.velocity_a), 3): r for r in beside.values()}
    rows = [
        "| p (hPa) | U_A (m/s) | ratio exp | ratio paper VOF | **ratio here (x = 0)** "
        f"| 1 - b/a | err vs exp (%) | beside: {inp.beside_model or '-'} (x = 0) "
        "| Kelvin-Voigt | min ratio | ratio at end | cells | steps | wall (s) | max vol. err |",
        "|" + "---|" * 15,
    ]
    errs, paper_errs, kv_errs, vol = [], [], [], []
    for p, r in zip(pressures, runs, strict=True):
        exp = _lookup(table.pressure, table.ratio_experiment, p)
        paper = _lookup(table.pressure, table.ratio_simulation, p)
        kv = _lookup(kv_p, kv_ratio, p)
        v = max(float(np.max(np.abs(e))) for e in r.history.volume_error.values())
        vol.append(v)
        err = _pct(r.ratio_at_junction, exp)
        if math.isfinite(err):
            errs.append(err)
            paper_errs.append(_pct(r.ratio_at_junction, paper))
        kv_errs.append(_pct(kv, exp))
        other = beside_at.get(round(float(r.velocity_a), 3))
        other_text = f"{other.ratio_at_junction:.4f}" if other else "-"
        rows.append(
            f"| {p / HPA:g} | {r.velocity_a * 1e-6:.3f} | {exp:.3f} | {paper:.3f} "
            f"| **{r.ratio_at_junction:.4f}** | {1 - r.ratio_at_junction:.4f} | {err:.2f} "
            f"| {other_text} | {kv:.3f} | {r.min_ratio:.4f} | {r.history.ratio[-1]:.4f} "
            f"| {r.n_cells} | {r.steps} | {r.wall_seconds:.0f} | {v:.1e} |"
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
    correctors = {label: n for label, n in _correctors(inp, pressures).items()}
    first_hpa = float(pressures[0] / HPA)
    of_first = {k: v for k, v in extra.items() if k.split("_")[0] == f"p{first_hpa:g}hPa"}
    notes, sens = sensitivity_notes(of_first, runs[0], correctors)
    metrics.update(sens)
    meshes = [(m, extra[mesh_label(first_hpa, m)]) for m, _ in inp.mesh_checks]
    if meshes:
        mesh_text, more = mesh_study(inp.dx_um, runs[0], meshes)
        metrics.update(more)
        notes = [*notes, "", "**Mesh study** (the first pressure):", "", mesh_text]
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
    checks += courant_check(inp, [*runs, *extra.values()], metrics)
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
    dt_runs = [r for k, r in extra.items() if "_dt" in k and not k.startswith(BESIDE)]
    dt_text = "not run"
    if dt_runs:
        dt_text, study, worst = dt_study(inp.time_step_s, [runs[0], *dt_runs])
        metrics.update(study.metrics())
        metrics["dt_change_max_pct"] = worst
    beside_text = _beside(inp, table, beside, extra, metrics)
    traction_text = elastic_text = "not computed (the liquid-cell model only)"
    if inp.model == LIQUID_CELL:
        ph = inp.cytoplasm if inp.cell_curve == "cytoplasm" else inp.zp
        try:
            traction_text, more = traction_study(
                runs[0],
                _layout(inp, runs[0]),
                inp.channel.viscosity_Pa_s * PA_S,
                ph.density_kg_m3 * KG_M3,
                ctx.output(f"traction_p{pressures[0] / HPA:g}hPa.csv"),
                (find_openfoam(inp.openfoam), inp.channel.density_kg_m3 * KG_M3, inp.nice),
            )
            metrics.update(more)
        except InputError as exc:  # e.g. a mesh too coarse for the probes between cell and wall
            traction_text = f"not computed: {exc}"
        try:
            elastic_text, more = elastic_section(ctx, inp, table, pressures, one_way, meshes)
            metrics.update(more)
        except (InputError, SolverError) as exc:  # SolverError: a restart for the load
            elastic_text = f"not computed: {exc}"
    names = ("medium", "cell") if inp.model == LIQUID_CELL else ("medium", "zp", "cytoplasm")
    shot = snapshot(
        time_directories(runs[0].case)[-1][1],
        _layout(inp, runs[0]),
        names,
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
    solver = MODEL_SOLVER[inp.model]
    sections = [
        (f"Table 4: {inp.model} ({solver}), {_cell_text(inp)}", "\n".join(rows)),
        ("Mesh, viscosity-cap and ZP sensitivity (first pressure)", "\n".join(notes) or "not run"),
        (f"Time-step convergence of {inp.model} (first pressure)", dt_text),
        (f"Beside: {inp.beside_model or 'no second model'}", beside_text),
        (f"Traction on the cell at the junction ({pressures[0] / HPA:g} hPa)", traction_text),
        ("The AFM-elastic cell under the flow's traction (one-way)", elastic_text),
    ]
    if inp.mesh_check_pressures == "all":
        limits = pressure_limits(
            inp.dx_um, [float(p / HPA) for p in pressures], runs, extra, list(inp.mesh_check_dx_um)
        )
        text, more = converged_section(
            limits,
            [_lookup(table.pressure, table.ratio_experiment, p) for p in pressures],
            [_lookup(table.pressure, table.ratio_simulation, p) for p in pressures],
        )
        metrics.update(more)
        sections.insert(1, ("Table 4 from the mesh limits (every pressure on every mesh)", text))
    if recompute:
        texts = []
        for p_hpa, result in recompute:
            text, more = recompute_section(result, p_hpa)
            texts.append(text)
            for key, value in more.items():
                metrics.setdefault(key, value)  # the first pressure's, as with one
        if len(recompute) > 1:
            text, more = recompute_summary(recompute)
            texts.insert(0, text)
            metrics.update(more)
        sections.append(
            ("Deform and recompute: the flow past the deformed cell", "\n\n".join(texts))
        )
    sections += [
        (
            "Files",
            "Each run's OpenFOAM case is in `openfoam/<run>/` (open `case.foam` in ParaView for "
            "the time series).",
        ),
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)


def _cell_text(inp: VofInputs) -> str:
    """The cell's viscosity model, as the report states it."""
    if inp.model != LIQUID_CELL:
        return (
            f"ZP and cytoplasm as two Carreau phases, eta0 capped at "
            f"{inp.zero_shear_cap_Pa_s:g} Pa s"
        )
    ph = inp.cytoplasm if inp.cell_curve == "cytoplasm" else inp.zp
    return (
        f"the whole cell one liquid of the {inp.cell_curve}'s Carreau curve (eta0 "
        f"{ph.eta0_Pa_s:g} Pa s capped at {inp.zero_shear_cap_Pa_s:g}, eta_inf "
        f"{ph.eta_inf_Pa_s:g} Pa s, lambda and n of the Table 2 fit, rho {ph.density_kg_m3:g} "
        "kg/m^3)"
    )


def _correctors(inp: VofInputs, pressures: np.ndarray) -> dict[str, int]:
    return {s.label: s.correctors for s in run_specs(inp, [p / HPA for p in pressures])}


def _beside(inp: VofInputs, table, beside: dict, extra: dict, metrics: dict) -> str:
    """The beside model's table against the experiment and its dt dependence; fills its
    metrics."""
    if not beside:
        return "not run"
    rows = ["| p (hPa) | ratio exp | ratio beside (x = 0) | 1 - b/a | err vs exp (%) |"]
    rows.append("|---|---|---|---|---|")
    errs = []
    for label, r in beside.items():
        p = float(label[len(BESIDE) + 1 :].removesuffix("hPa")) * HPA
        exp = _lookup(table.pressure, table.ratio_experiment, p)
        err = _pct(r.ratio_at_junction, exp)
        if math.isfinite(err):
            errs.append(err)
        rows.append(
            f"| {p / HPA:g} | {exp:.3f} | {r.ratio_at_junction:.4f} "
            f"| {1 - r.ratio_at_junction:.4f} | {err:.2f} |"
        )
    metrics["beside_ratio_at_junction"] = [r.ratio_at_junction for r in beside.values()]
    metrics["beside_mean_error_experiment_pct"] = float(np.mean(errs)) if errs else math.nan
    text = "\n".join(rows)
    dt_runs = [r for k, r in extra.items() if k.startswith(BESIDE) and "_dt" in k]
    if dt_runs:
        step = inp.time_step_at(inp.beside_pressures_hPa[0])
        dt_text, study, _ = dt_study(step, [next(iter(beside.values())), *dt_runs])
        metrics["beside_dt_change_pct"] = study.change_pct
        text += f"\n\nIts time step (first beside pressure):\n\n{dt_text}"
    return text


def _layout(inp: VofInputs, run: JunctionRun):
    return inp.geometry.to_geometry().layout(inp.dx_um, run.velocity_a, run.velocity_b)
