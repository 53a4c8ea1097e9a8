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

from collections.abc import Callable

import numpy as np

from oocyte_fe.kinds.microchannel_vof_inputs import HPA, KG_M3, METRICS, PA_S, VofInputs
from oocyte_fe.kinds.microchannel_vof_report import report_outcome, skipped_outcome
from oocyte_fe.microchannel.junction_deformation import JunctionCell, fit_junction_model
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.microchannel.tables import read_deformation_table, read_flow_curve
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import Numerics, Phase
from oocyte_fe.microchannel.vof.junction import junction_setup, run_junction
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.microchannel.vof.rheology import cap_zero_shear
from oocyte_fe.microchannel.vof.runner import (
    OpenFoamMissing,
    find_openfoam,
)
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind


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
        return skipped_outcome(inp, table, kv_p, kv_ratio)

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
    return report_outcome(ctx, inp, table, kv_p, kv_ratio, pressures, main, extra)
