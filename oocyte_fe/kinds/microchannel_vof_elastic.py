"""The ``microchannel_vof`` report's elastic-cell section: the AFM-elastic FE cell under the
liquid VOF's traction at every pressure run (one-way,
:mod:`oocyte_fe.microchannel.elastic_junction`), against the experiment, the paper's VOF and
the liquid cell (mean absolute error of b/a)."""

from __future__ import annotations

import math

import numpy as np

from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.kinds.microchannel_vof_elastic_notes import (
    follower_note,
    left_out_note,
    mesh_limit_note,
    mesh_note,
    solved_again_note,
    stretch_note,
)
from oocyte_fe.kinds.microchannel_vof_inputs import HPA, VofInputs
from oocyte_fe.microchannel.elastic_junction import (
    ElasticAtPressure,
    compare_table4,
    elastic_cells_at_junction,
)
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.microchannel.vof.restart import step_pair
from oocyte_fe.microchannel.vof.runner import find_openfoam
from oocyte_fe.runner.registry import CaseContext


def _lookup(p: np.ndarray, values: np.ndarray, at: float) -> float:
    hit = np.nonzero(np.isclose(p, at))[0]
    return float(values[hit[0]]) if len(hit) else math.nan


def one_way_cells(
    ctx: CaseContext, inp: VofInputs, pressures: np.ndarray, runs: list[JunctionRun]
) -> list[ElasticAtPressure] | str:
    """The AFM-elastic cell under the traction of each run's writes around the junction
    (one-way; dead load and follower reading, :func:`.elastic_junction.
    elastic_cells_at_junction`), in the order of the pressures, or why not computed. Each
    write's load is taken two solver steps later (:func:`.elastic_junction.write_traction`)."""
    geometry = inp.geometry.to_geometry()
    by_p = {float(p / HPA): r for p, r in zip(pressures, runs, strict=True)}

    def layout_of(p_hpa: float):
        r = by_p[p_hpa]
        return geometry.layout(inp.dx_um, r.velocity_a, r.velocity_b)

    try:
        steps = step_pair(find_openfoam(inp.openfoam), inp.nice)
        jobs = [(p, r.case, r.ratio_at_junction) for p, r in by_p.items()]
        return elastic_cells_at_junction(
            jobs, layout_of, inp.fluids, ctx.output("."), steps, follower=True
        )
    except (InputError, SolverError) as exc:  # SolverError: a restart for the load
        return f"not computed: {exc}"


def elastic_section(
    ctx: CaseContext,
    inp: VofInputs,
    table,
    pressures: np.ndarray,
    one_way: list[ElasticAtPressure] | str,
    meshes: list[tuple[float, JunctionRun]] = (),
) -> tuple[str, dict[str, float | list[float]]]:
    """The section text and metrics ``elastic_cell_b_over_a`` (per pressure) and the mean
    absolute errors ``elastic_mae``, ``liquid_mae``, ``paper_vof_mae`` against the experiment;
    ``one_way`` from :func:`one_way_cells` (a string, why they were not computed, is the
    text); with ``meshes`` (the first pressure on each of
    ``mesh_check_dx_um``: (dx, run)) also :func:`mesh_note` for each
    (``elastic_mesh_change_pct``: the first of them) and ``elastic_mesh_b_over_a`` (b/a under
    each mesh's flow, NaN where the FE stops)."""
    if isinstance(one_way, str):
        return one_way, {}
    geometry = inp.geometry.to_geometry()
    cells = sorted(one_way, key=lambda c: c.pressure_hPa)
    rows = [
        "| p (hPa) | experiment | paper VOF | liquid cell (VOF) | **AFM-elastic cell** "
        "| 1 - b/a elastic | smallest stretch | writes at x (um): b/a at 0 from the line "
        "through them |",
        "|---|---|---|---|---|---|---|---|",
    ]
    exp, paper, failed = [], [], []
    for c in cells:
        e = _lookup(table.pressure, table.ratio_experiment, c.pressure_hPa * HPA)
        v = _lookup(table.pressure, table.ratio_simulation, c.pressure_hPa * HPA)
        exp.append(e)
        paper.append(v)
        where = ", ".join(f"{x:+.1f}" for x in c.traction_x_um)
        if c.carried:
            rows.append(
                f"| {c.pressure_hPa:g} | {e:.3f} | {v:.3f} | {c.liquid_b_over_a:.4f} "
                f"| **{c.b_over_a:.4f}** | {1 - c.b_over_a:.4f} | {c.smallest_stretch:.3f} "
                f"| {where} |"
            )
            continue
        worst = min(c.cells, key=lambda cell: cell.load_fraction)
        failed.append(
            f"{c.pressure_hPa:g} hPa: {worst.load_fraction:.0%} of the load carried, b/a "
            f"{worst.b_over_a:.3f} there ({worst.experiment.reason[:90]})"
        )
        rows.append(
            f"| {c.pressure_hPa:g} | {e:.3f} | {v:.3f} | {c.liquid_b_over_a:.4f} "
            f"| < {worst.b_over_a:.3f} (FE stops) | - | - | {where} |"
        )
    elastic = [c.b_over_a if c.carried else math.nan for c in cells]
    stretch = [c.smallest_stretch if c.carried else math.nan for c in cells]
    metrics: dict[str, float | list[float]] = {
        "elastic_cell_b_over_a": elastic,
        "elastic_min_stretch": stretch,
    }
    known = np.isfinite(exp) & np.isfinite(elastic)
    text = "\n".join(rows) + "\n\n" + stretch_note(cells)
    text += solved_again_note(cells)
    partial = [left_out_note(c) for c in cells if c.left_out]
    if partial:
        text += "\n\n" + " ".join(partial)
    if failed:
        text += (
            "\n\nThe FE cell does not carry the whole traction at "
            + "; ".join(failed)
            + ". The elastic cell of the AFM moduli is crushed there (Newton's iterates fold a "
            "ZP element before the full load, on every size, plain and with the line search): "
            "no b/a at the junction, and "
            "these pressures are left out of the errors below."
        )
    if known.any():
        k = np.nonzero(known)[0]
        cmp = compare_table4(
            np.array(exp)[k],
            **{
                "AFM-elastic cell (one-way)": np.array(elastic)[k],
                "liquid cell (converged VOF)": np.array([c.liquid_b_over_a for c in cells])[k],
                "paper VOF (Fluent, 3-D)": np.array(paper)[k],
            },
        )
        e_el, e_liq, e_pap = cmp.errors.values()
        metrics.update({"elastic_mae": e_el, "liquid_mae": e_liq, "paper_vof_mae": e_pap})
        text += f"\n\nOver the {known.sum()} pressures the FE carries: " + cmp.sentence()
    note, more = follower_note(cells, exp)
    metrics.update(more)
    text += "\n\n" + note
    first = float(pressures[0] / HPA)
    base = next(c for c in cells if c.pressure_hPa == first)
    on_meshes = [base]
    steps = step_pair(find_openfoam(inp.openfoam), inp.nice) if meshes else None
    for m, mesh_run in meshes:
        [other] = elastic_cells_at_junction(
            [(first, mesh_run.case, mesh_run.ratio_at_junction)],
            lambda _, m=m, r=mesh_run: geometry.layout(m, r.velocity_a, r.velocity_b),
            inp.fluids,
            ctx.output(f"mesh_dx{m:g}"),
            steps,
            follower=True,
        )
        on_meshes.append(other)
        note, more = mesh_note(base, other, inp.dx_um, m)
        for key, value in more.items():
            metrics.setdefault(key, value)
        text += "\n\n" + note
    if meshes:
        metrics["elastic_mesh_b_over_a"] = [
            c.b_over_a if c.carried else math.nan for c in on_meshes[1:]
        ]
        note, more = mesh_limit_note([inp.dx_um, *(m for m, _ in meshes)], on_meshes)
        metrics.update(more)
        text += "\n\n" + note
    text += (
        "\n\nOne-way: the force of the flow past the LIQUID cell (each write within 12.5 um "
        "of the junction crossing) from its diffuse interface, -sum sigma . grad(alpha) dA, "
        "put on the outline by polar angle (its Fourier harmonics down to four lattice "
        "spacings; net force exact: the force whose momentum budget is checked above; "
        "vof.band_traction), on the layered plane-strain "
        "FE cell (ZP 7.0, cytoplasm 1.55 kPa: the instantaneous AFM moduli; the ZP's Prony "
        "series relaxes 0.16 % in the millisecond of the transit), free (inertia relief); the "
        "flow is not recomputed around the deformed cell. Nothing is tuned to Table 4."
    )
    return text, metrics
