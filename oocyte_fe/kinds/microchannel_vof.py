"""Case kind ``microchannel_vof``: VOF of the oocyte at the junction (OpenFOAM).

The ``model`` input picks the flow model: ``liquid_cell_isoadvector`` (two phases, the cell
as one liquid, ``interIsoFoam``) or ``three_phase_mules`` (medium, ZP, cytoplasm,
``multiphaseInterFoam``: the seed's reading). Runs
:func:`oocyte_fe.microchannel.vof.junction.run_junction` for each pressure and the studies of
:func:`.microchannel_vof_runs.run_specs` (on Dask, :mod:`oocyte_fe.microchannel.vof.pool`:
``concurrent`` at a time locally or on the workers of a scheduler: the CLI's ``--scheduler``,
else the ``scheduler`` input; each with ``ranks`` MPI ranks), and the reduced Kelvin-Voigt
model beside it. The liquid cell's deform-recompute passes at several pressures go the same
way, one task per pressure (:func:`recompute_at`).
Without OpenFOAM the case is SKIPPED (not a failure) with the install line as its reason; the
reduced model still runs and its table is in the report.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.kinds.microchannel_vof_elastic import one_way_cells
from oocyte_fe.kinds.microchannel_vof_inputs import HPA, KG_M3, PA_S, VofInputs
from oocyte_fe.kinds.microchannel_vof_metrics import METRICS
from oocyte_fe.kinds.microchannel_vof_report import report_outcome, skipped_outcome
from oocyte_fe.kinds.microchannel_vof_runs import RunSpec, run_specs
from oocyte_fe.microchannel.elastic_iteration import DeformRecompute, deform_recompute
from oocyte_fe.microchannel.elastic_junction import ElasticAtPressure
from oocyte_fe.microchannel.junction_deformation import JunctionCell, fit_junction_model
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.microchannel.tables import read_deformation_table, read_flow_curve
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import Numerics, Phase, VofSetup
from oocyte_fe.microchannel.vof.isoadvector import LIQUID_CELL, MODEL_SOLVER
from oocyte_fe.microchannel.vof.junction import (
    JunctionRun,
    junction_setup,
    liquid_cell_setup,
    run_junction,
)
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.microchannel.vof.restart import step_pair
from oocyte_fe.microchannel.vof.rheology import cap_zero_shear
from oocyte_fe.microchannel.vof.runner import (
    OpenFoamMissing,
    find_openfoam,
)
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind


def _cell_fit(inp: VofInputs) -> Rheology:
    """The Table 2 Carreau fit (eta_inf fixed at the cytoplasm's): lambda and n of both
    cell curves."""
    curve = read_flow_curve(inp.viscosity_data)
    return fit_viscosity(
        "carreau",
        curve.shear_rate,
        curve.viscosity,
        fixed={"eta_inf": inp.cytoplasm.eta_inf_Pa_s * PA_S},
        source=str(inp.viscosity_data),
    ).rheology


def _phases(inp: VofInputs, cap: float, model: str, curve: str) -> tuple[Phase, ...]:
    """(medium, zp, cytoplasm) for ``three_phase_mules``; (medium, cell) for
    ``liquid_cell_isoadvector``, the cell of the ``curve`` phase's Carreau curve and density."""
    fit = _cell_fit(inp)
    medium = Phase(
        "medium",
        Rheology.of("newtonian", mu=inp.channel.viscosity_Pa_s * PA_S),
        inp.channel.density_kg_m3 * KG_M3,
    )
    cell = {}
    for name, ph in (("zp", inp.zp), ("cytoplasm", inp.cytoplasm)):
        rheology = Rheology.of(
            "carreau",
            source=f"case inputs {name}",
            eta0=ph.eta0_Pa_s * PA_S,
            eta_inf=ph.eta_inf_Pa_s * PA_S,
            time_constant=fit.params["time_constant"],
            n=fit.params["n"],
        )
        cell[name] = Phase(name, cap_zero_shear(rheology, cap * PA_S), ph.density_kg_m3 * KG_M3)
    if model == LIQUID_CELL:
        return medium, Phase("cell", cell[curve].rheology, cell[curve].density)
    return medium, cell["zp"], cell["cytoplasm"]


def _kelvin_voigt(inp: VofInputs, source: str) -> tuple[np.ndarray, np.ndarray]:
    table = read_deformation_table(inp.deformation_data)
    channel = inp.channel.to_internal()
    cell = JunctionCell(inp.geometry.cell_diameter_um, inp.modulus_kPa, _cell_fit(inp))
    fit = fit_junction_model(
        channel,
        cell,
        table.pressure,
        table.ratio_experiment,
        [p * HPA for p in inp.kelvin_voigt_fit_hPa],
        source=source,
    )
    return table.pressure, fit.ratio


def _setup(inp: VofInputs, spec: RunSpec, outline: np.ndarray | None = None) -> VofSetup:
    """The OpenFOAM case of one run; ``outline`` (um about the cell's centre): the liquid
    cell starts in that shape (the deform-recompute passes)."""
    channel = inp.channel.to_internal()
    u = float(channel.mean_velocity(spec.pressure_hPa * HPA))
    end = inp.travel_um / u
    numerics = Numerics(
        time_step=spec.dt,
        end_time=end,
        write_interval=end / inp.writes,
        outer_correctors=inp.outer_correctors,
        momentum_predictor=inp.momentum_predictor and spec.model == LIQUID_CELL,
        correctors=spec.correctors,
        pressure_rel_tol=inp.pressure_rel_tol,
        solver=MODEL_SOLVER[spec.model],
        iso=inp.isoadvector.to_controls(),
    )
    phases = _phases(inp, spec.cap, spec.model, spec.curve)
    geometry, ub = inp.geometry.to_geometry(), inp.b_ratio * u
    if spec.model == LIQUID_CELL:
        return liquid_cell_setup(geometry, spec.dx, *phases, u, ub, numerics, outline=outline)
    return junction_setup(geometry, spec.dx, *phases, u, ub, numerics)


def _job(ctx: CaseContext, inp: VofInputs, spec: RunSpec) -> tuple:
    """Arguments of :func:`run_junction` for one run (plain data: they may go to a remote
    Dask worker)."""
    setup = _setup(inp, spec)
    foam = find_openfoam(inp.openfoam)
    end = setup.numerics.end_time
    ctx.step(f"{spec.label}: {spec.model}, {setup.layout.n_cells} cells, {end * 1e3:.3g} ms")
    return (foam, ctx.output(f"openfoam/{spec.label}"), setup, inp.ranks, inp.nice)


def recompute_at(
    inp: VofInputs,
    spec: RunSpec,
    first: JunctionRun,
    one_way: ElasticAtPressure | None,
    folder: Path,
    progress: Callable[[str], None] | None = None,
) -> DeformRecompute | str:
    """The deform-recompute passes at the pressure of ``spec`` in ``folder``, or why they did
    not run ("not computed: ..."). Pass 0 is the run ``first`` with ``one_way``, its elastic
    cell from the report's one-way section in the reading of ``recompute_load``, taken as it
    is. Plain data in and out, no case context: a task of :func:`run_concurrently` (it may run
    on a remote Dask worker); ``progress`` gets a line at each pass's flow."""
    foam = find_openfoam(inp.openfoam)

    def run_flow(outline: np.ndarray | None, sub: Path) -> tuple:
        setup = _setup(inp, spec, outline)
        run = first
        if outline is not None:
            if progress is not None:
                progress(
                    f"deform-recompute {spec.pressure_hPa:g} hPa: {sub.parent.name}, the flow "
                    "past the FE's shape"
                )
            run = run_junction(foam, sub, setup, inp.ranks, inp.nice)
        return run.case, setup.layout, run.ratio_at_junction

    try:
        return deform_recompute(
            run_flow,
            folder,
            inp.fluids,
            max_passes=inp.recompute_passes,
            steps=step_pair(foam, inp.nice),
            relaxation=inp.recompute_relaxation,
            follower=inp.recompute_load == "follower",
            pressure_hPa=spec.pressure_hPa,
            first=one_way,
        )
    except (InputError, SolverError) as exc:
        return f"not computed: {exc}"


def _recompute_all(
    ctx: CaseContext,
    inp: VofInputs,
    specs: list[RunSpec],
    main: list[JunctionRun],
    cells: Sequence[ElasticAtPressure | None],
) -> list[tuple[float, DeformRecompute | str]]:
    """:func:`recompute_at` at the first pressure, or at each with ``recompute_pressures =
    "all"``: one Dask task per pressure, ``concurrent`` at a time, on the case's scheduler
    when there are several (one pressure: in this process)."""
    at = range(len(main)) if inp.recompute_pressures == "all" else range(1)
    follower = inp.recompute_load == "follower"
    jobs = [
        (
            inp,
            specs[k],
            main[k],
            cells[k].follower if follower and cells[k] is not None else cells[k],
            ctx.output(f"recompute/p{specs[k].pressure_hPa:g}hPa"),
        )
        for k in at
    ]
    scheduler = None
    if len(jobs) > 1:
        scheduler = run_scheduler(ctx, inp)
        where = scheduler or f"a local cluster of {inp.concurrent}"
        ctx.step(f"deform-recompute passes at {len(jobs)} pressures on {where}")
    done = run_concurrently(recompute_at, jobs, inp.concurrent, scheduler, [ctx.step] * len(jobs))
    return [(job[1].pressure_hPa, r) for job, r in zip(jobs, done, strict=True)]


def run_scheduler(ctx: CaseContext, inp: VofInputs) -> str | None:
    """The Dask scheduler the runs go to: the CLI's ``--scheduler`` (``ctx.scheduler``) when
    given, else the case's ``scheduler`` input, else none (a local cluster)."""
    return ctx.scheduler or inp.scheduler


def _progress(ctx: CaseContext, label: str) -> Callable[[str], None]:
    return lambda msg: ctx.step(f"{label}: {msg}")


@case_kind("microchannel_vof", inputs=VofInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """VOF (OpenFOAM) of the oocyte at the junction against Table 4."""
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
        return skipped_outcome(inp, table, kv_p, kv_ratio)

    specs = run_specs(inp, [p / HPA for p in pressures])
    scheduler = run_scheduler(ctx, inp)
    where = scheduler or (f"a local cluster of {inp.concurrent}" if len(specs) > 1 else "")
    ctx.step(f"{len(specs)} runs on {where}" if where else "1 run in this process")
    runs = run_concurrently(
        run_junction,
        [_job(ctx, inp, spec) for spec in specs],
        inp.concurrent,
        scheduler,
        [_progress(ctx, spec.label) for spec in specs],
    )
    main = runs[: len(pressures)]
    n = len(pressures)
    extra = {s.label: r for s, r in zip(specs[n:], runs[n:], strict=True)}
    if inp.model != LIQUID_CELL:
        return report_outcome(ctx, inp, table, kv_p, kv_ratio, pressures, main, extra)
    ctx.step("the AFM-elastic cell under each run's traction (one-way)")
    one_way = one_way_cells(ctx, inp, pressures, main)  # in the order of the pressures
    cells = [None] * n if isinstance(one_way, str) else one_way
    recompute = _recompute_all(ctx, inp, specs, main, cells) if inp.recompute_passes else []
    return report_outcome(
        ctx, inp, table, kv_p, kv_ratio, pressures, main, extra, recompute, one_way
    )
