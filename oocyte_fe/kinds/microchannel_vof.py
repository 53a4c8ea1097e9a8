"""Case kind ``microchannel_vof``: three-phase VOF of the oocyte at the junction (OpenFOAM).

Runs :func:`oocyte_fe.microchannel.vof.junction.run_junction` for each pressure (on Dask,
:mod:`oocyte_fe.microchannel.vof.pool`: ``concurrent`` at a time locally or on the workers of
a scheduler: the CLI's ``--scheduler``, else the ``scheduler`` input; each with ``ranks`` MPI
ranks), one extra run at a second mesh and one at a second viscosity cap (first pressure), and
the reduced Kelvin-Voigt model beside it.
Without OpenFOAM the case is SKIPPED (not a failure) with the install line as its reason; the
reduced model still runs and its table is in the report.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from pydantic import Field

from oocyte_fe.kinds.data_templates import DEFORMATION, FLOW_CURVE
from oocyte_fe.kinds.microchannel_inputs import ChannelInputs
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.junction_deformation import JunctionCell, fit_junction_model
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.microchannel.tables import read_deformation_table, read_flow_curve
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import Numerics, Phase
from oocyte_fe.microchannel.vof.extrapolation import TimeStepStudy, time_step_study
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import JunctionRun, junction_setup, run_junction
from oocyte_fe.microchannel.vof.plotting import plot_ratio_histories, plot_vof_ratio
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.microchannel.vof.post import snapshot, time_directories
from oocyte_fe.microchannel.vof.rheology import cap_zero_shear
from oocyte_fe.microchannel.vof.runner import (
    INSTALL_HINT,
    OpenFoamMissing,
    find_openfoam,
)
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Relation

PA_S = units.VISCOSITY["Pa_s"]
KG_M3 = units.DENSITY["kg_m3"]
HPA = units.PRESSURE["hPa"]


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


class VofInputs(CaseInputs):
    deformation_data: DataFile = Field(
        description="CSV: pressure_<unit>, ratio_experiment, ratio_simulation (Table 4)",
        json_schema_extra=DEFORMATION,
    )
    viscosity_data: DataFile = Field(
        description="CSV flow curve (Table 2) for the Carreau lambda and n",
        json_schema_extra=FLOW_CURVE,
    )
    channel: ChannelInputs = Field(description="the device (calibrates U(p))")
    zp: CellPhaseInputs = Field(description="zona pellucida phase (Table 3)")
    cytoplasm: CellPhaseInputs = Field(description="cytoplasm phase (Table 3)")
    geometry: GeometryInputs = Field(
        default_factory=GeometryInputs, description="junction dimensions (defaults: the reading)"
    )
    pressures_hPa: list[float] = _f(
        [300.0], "driving pressures run by the VOF", "hPa", min_length=1
    )
    zero_shear_cap_Pa_s: float = _f(46.0, "cap on both cell phases' eta0", "Pa s", gt=0)
    cap_sensitivity_Pa_s: float | None = _f(
        None, "second cap, run at the first pressure", "Pa s", gt=0
    )
    b_ratio: float = _f(1.0, "mean velocity of inlet B over that of inlet A", "1", gt=0)
    dx_um: float = _f(10.0, "cell size", "um", gt=0)
    mesh_check_dx_um: float | None = _f(None, "second mesh, first pressure", "um", gt=0)
    time_step_s: float = _f(1e-6, "time step (fixed)", "s", gt=0)
    dt_refinements: int = _f(
        0,
        "extra runs at dt/2, dt/4, ... (first pressure, dx_um); 2 or more: the dt -> 0 limit",
        "1",
        ge=0,
        le=3,
    )
    travel_um: float = _f(
        600.0, "run until the cell has moved this far at the mean velocity", "um", gt=0
    )
    writes: int = _f(20, "number of written times", "1", ge=2)
    outer_correctors: int = _f(1, "PIMPLE outer correctors", "1", ge=1)
    correctors: int = _f(3, "pressure correctors", "1", ge=1)
    pressure_rel_tol: float = _f(
        0.0, "GAMG relative tolerance of the correctors before the last", "1", ge=0, lt=1
    )
    ranks: int = _f(1, "MPI ranks per run (decomposePar + mpirun)", "1", ge=1)
    concurrent: int = _f(1, "runs at the same time (local Dask cluster of threads)", "1", ge=1)
    scheduler: str | None = _f(
        None,
        "Dask scheduler address (a cluster); none: a local cluster; the CLI's --scheduler wins",
        "address",
    )
    nice: int = _f(0, "niceness of the OpenFOAM processes", "1", ge=0, le=19)
    openfoam: str | None = _f(None, "OpenFOAM directory (else env var / WM_PROJECT_DIR)", "path")
    modulus_kPa: float = _f(1.55, "Kelvin-Voigt estimate: cell modulus (AFM)", "kPa", gt=0)
    kelvin_voigt_fit_hPa: list[float] = _f(
        [200.0, 500.0, 900.0], "Kelvin-Voigt estimate: pressures it is fitted on", "hPa"
    )
    max_volume_error: float = _f(1e-3, "check: |phase volume change| of the cell phases", "1", gt=0)
    max_mesh_change_pct: float = _f(2.0, "check: ratio change between the two meshes", "%", gt=0)


METRICS = {
    "ratio_at_junction": "axis ratio b/a when the centroid crosses x = 0, per pressure",
    "ratio_end": "axis ratio b/a at the end of the run, per pressure",
    "mean_error_experiment_pct": "mean |ratio_at_junction / experiment - 1| over the run, %",
    "mean_error_paper_vof_pct": "mean |ratio_at_junction / paper VOF - 1|, %",
    "kelvin_voigt_mean_error_pct": "reduced model against the experiment, same pressures, %",
    "max_volume_error": "largest |relative volume change| of the ZP and cytoplasm phases",
    "mesh_change_pct": "ratio change between the two meshes at x = 0 (else at the end), %",
    "cap_change_pct": "ratio change between the two caps at x = 0 (else at the end), %",
    "seconds_per_ms": "wall seconds per simulated ms (first pressure, one run)",
    "dt_change_pct": "change of 1 - b/a at x = 0 from dt to dt/2 (first pressure), %",
    "dt_order": "observed order in dt of b/a at x = 0 (dt, dt/2, dt/4; nan: not monotone)",
    "dt_factor": "ratio of successive differences of b/a over dt, dt/2, dt/4 (< 0: alternating)",
    "ratio_dt_limit": "b/a at x = 0 extrapolated to dt -> 0 (Richardson, first pressure)",
    "deformation_dt_limit": "1 - b/a at x = 0 extrapolated to dt -> 0 (first pressure)",
    "ratio_dt_error_pct": "b/a at x = 0 with the case's dt against its dt -> 0 limit, %",
}


def _phases(inp: VofInputs, cap: float) -> tuple[Phase, Phase, Phase]:
    curve = read_flow_curve(inp.viscosity_data)
    fit = fit_viscosity(
        "carreau",
        curve.shear_rate,
        curve.viscosity,
        fixed={"eta_inf": inp.cytoplasm.eta_inf_Pa_s * PA_S},
        source=str(inp.viscosity_data),
    ).rheology
    medium = Phase(
        "medium",
        Rheology.of("newtonian", mu=inp.channel.viscosity_Pa_s * PA_S),
        inp.channel.density_kg_m3 * KG_M3,
    )
    cell = []
    for name, ph in (("zp", inp.zp), ("cytoplasm", inp.cytoplasm)):
        rheology = Rheology.of(
            "carreau",
            source=f"case inputs {name}",
            eta0=ph.eta0_Pa_s * PA_S,
            eta_inf=ph.eta_inf_Pa_s * PA_S,
            time_constant=fit.params["time_constant"],
            n=fit.params["n"],
        )
        cell.append(Phase(name, cap_zero_shear(rheology, cap * PA_S), ph.density_kg_m3 * KG_M3))
    return medium, cell[0], cell[1]


def _kelvin_voigt(inp: VofInputs, source: str) -> tuple[np.ndarray, np.ndarray]:
    table = read_deformation_table(inp.deformation_data)
    channel = inp.channel.to_internal()
    curve = read_flow_curve(inp.viscosity_data)
    rheology = fit_viscosity(
        "carreau",
        curve.shear_rate,
        curve.viscosity,
        fixed={"eta_inf": inp.cytoplasm.eta_inf_Pa_s * PA_S},
        source=str(inp.viscosity_data),
    ).rheology
    cell = JunctionCell(inp.geometry.cell_diameter_um, inp.modulus_kPa, rheology)
    fit = fit_junction_model(
        channel,
        cell,
        table.pressure,
        table.ratio_experiment,
        [p * HPA for p in inp.kelvin_voigt_fit_hPa],
        source=source,
    )
    return table.pressure, fit.ratio


def _job(
    ctx: CaseContext,
    inp: VofInputs,
    label: str,
    p_hpa: float,
    dx: float,
    cap: float,
    dt: float,
) -> tuple:
    """Arguments of :func:`run_junction` for one run (plain data: they may go to a remote
    Dask worker)."""
    channel = inp.channel.to_internal()
    u = float(channel.mean_velocity(p_hpa * HPA))
    end = inp.travel_um / u
    numerics = Numerics(
        time_step=dt,
        end_time=end,
        write_interval=end / inp.writes,
        outer_correctors=inp.outer_correctors,
        correctors=inp.correctors,
        pressure_rel_tol=inp.pressure_rel_tol,
    )
    setup = junction_setup(
        inp.geometry.to_geometry(), dx, *_phases(inp, cap), u, inp.b_ratio * u, numerics
    )
    foam = find_openfoam(inp.openfoam)
    ctx.step(f"{label}: {setup.layout.n_cells} cells, {end * 1e3:.3g} ms")
    return (foam, ctx.output(f"openfoam/{label}"), setup, inp.ranks, inp.nice)


def run_scheduler(ctx: CaseContext, inp: VofInputs) -> str | None:
    """The Dask scheduler the runs go to: the CLI's ``--scheduler`` (``ctx.scheduler``) when
    given, else the case's ``scheduler`` input, else none (a local cluster)."""
    return ctx.scheduler or inp.scheduler


def _progress(ctx: CaseContext, label: str) -> Callable[[str], None]:
    return lambda msg: ctx.step(f"{label}: {msg}")


@case_kind("microchannel_vof", inputs=VofInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Three-phase VOF (OpenFOAM) of the oocyte at the junction against Table 4."""
    inp: VofInputs = ctx.inputs  # type: ignore[assignment]
    source = str(ctx.case_dir / "case.toml")
    table = read_deformation_table(inp.deformation_data)
    channel = inp.channel.to_internal()
    pressures = channel.check_pressures(
        np.array(inp.pressures_hPa) * HPA, source, "inputs.pressures_hPa"
    )
    ctx.step("Kelvin-Voigt estimate")
    kv_p, kv_ratio = _kelvin_voigt(inp, source)
    try:
        find_openfoam(inp.openfoam)
    except OpenFoamMissing:
        return _skipped(inp, table, kv_p, kv_ratio)

    dt, cap = inp.time_step_s, inp.zero_shear_cap_Pa_s
    jobs = [(f"p{p / HPA:g}hPa", p / HPA, inp.dx_um, cap, dt) for p in pressures]
    first = pressures[0] / HPA
    if inp.mesh_check_dx_um:
        dx = inp.mesh_check_dx_um
        jobs.append((f"p{first:g}hPa_dx{dx:g}", first, dx, cap, dt))
    if inp.cap_sensitivity_Pa_s:
        jobs.append(
            (
                f"p{first:g}hPa_cap{inp.cap_sensitivity_Pa_s:g}",
                first,
                inp.dx_um,
                inp.cap_sensitivity_Pa_s,
                dt,
            )
        )
    for k in range(1, inp.dt_refinements + 1):
        jobs.append((f"p{first:g}hPa_dt{dt / 2**k:g}", first, inp.dx_um, cap, dt / 2**k))
    scheduler = run_scheduler(ctx, inp)
    ctx.step(f"{len(jobs)} runs on " + (scheduler or f"a local cluster of {inp.concurrent}"))
    runs = run_concurrently(
        run_junction,
        [_job(ctx, inp, *job) for job in jobs],
        inp.concurrent,
        scheduler,
        [_progress(ctx, job[0]) for job in jobs],
    )
    main = runs[: len(pressures)]
    extra = dict(zip([j[0] for j in jobs[len(pressures) :]], runs[len(pressures) :], strict=True))
    return _report(ctx, inp, table, kv_p, kv_ratio, pressures, main, extra)


def _lookup(p: np.ndarray, values: np.ndarray, at: float) -> float:
    hit = np.nonzero(np.isclose(p, at))[0]
    return float(values[hit[0]]) if len(hit) else math.nan


def _skipped(inp: VofInputs, table, kv_p: np.ndarray, kv_ratio: np.ndarray) -> CaseOutcome:
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


def _report(
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
