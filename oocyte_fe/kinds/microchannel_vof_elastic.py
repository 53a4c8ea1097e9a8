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
    stretch_note,
)
from oocyte_fe.kinds.microchannel_vof_inputs import HPA, VofInputs
from oocyte_fe.microchannel.elastic_iteration import DeformRecompute
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
    remeshed = [
        f"{c.pressure_hPa:g} hPa, write at {x:+.1f} um: "
        + ", ".join(f"{m:g} um stopped at {f:.0%}" for m, f in cell.stopped)
        + (f", carried on {cell.mesh_um:g} um" if cell.experiment.success else ", none carried")
        for c in cells
        for cell, x in zip(c.cells, c.traction_x_um, strict=True)
        if cell.stopped
    ]
    if remeshed:
        text += (
            "\n\nMeshed again where Newton stopped short on the first element size (the "
            "answer does not depend on the size where two carry the load; the stalls do): "
            + "; ".join(remeshed)
            + "."
        )
    partial = [left_out_note(c) for c in cells if c.left_out]
    if partial:
        text += "\n\n" + " ".join(partial)
    if failed:
        text += (
            "\n\nThe FE cell does not carry the whole traction at "
            + "; ".join(failed)
            + ". The elastic cell of the AFM moduli is crushed there (a ZP element inverts "
            "before the full load): no b/a at the junction, and "
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


def recompute_section(
    result: DeformRecompute | str, pressure_hPa: float
) -> tuple[str, dict[str, float | list[float]]]:
    """The deform-recompute passes' table and metrics ``recompute_b_over_a`` (each pass's
    b/a, NaN where the FE did not carry its traction) and ``recompute_last_change_pct``."""
    if isinstance(result, str):
        return result, {}
    rows = [
        "| pass | the shape the flow starts from, b/a (principal extents) "
        "| the flow's cell shape, b/a at the junction (area moments) "
        "| traction taken at x (um) | FE b/a at x = 0 (principal extents) | traction carried "
        "| smallest stretch | change of b/a |",
        "|---|---|---|---|---|---|---|---|",
    ]
    previous = None  # the last carried pass's b/a
    for k, ps in enumerate(result.passes):
        change = "-"
        if previous is not None and ps.carried:
            change = f"{100 * (ps.b_over_a / previous - 1):+.1f} %"
        out = ps.elastic.left_out  # writes whose FE stopped while the others give b/a
        where = ", ".join(
            f"{x:+.1f}" + (" (left out)" if k in out else "")
            for k, x in enumerate(ps.elastic.traction_x_um)
        )
        rows.append(
            f"| {k} | {ps.start_b_over_a:.4f} | {ps.flow_b_over_a:.4f} | {where} "
            f"| {ps.b_over_a:.4f} "
            f"| {ps.load_fraction:.0%} | {ps.elastic.smallest_stretch:.3f} | {change} |"
        )
        if ps.carried:
            previous = ps.b_over_a
    ratios = [p.b_over_a if p.carried else math.nan for p in result.passes]
    carried = result.carried
    last = 100 * (carried[-1] / carried[-2] - 1) if len(carried) > 1 else math.nan
    text = (
        f"At {pressure_hPa:g} hPa: pass 0 is the one-way cell (the traction of each write "
        "around the junction crossing, b/a read to x = 0 by a line through them); pass k "
        "runs the flow again with the liquid cell "
        "started in the FE's deformed outline of pass k - 1 (at x = 0: a line through the "
        "writes' radii) and loads the FE cell with the new "
        + (
            "traction (its normal part a follower pressure on the deformed outline)"
            if result.follower
            else "traction (a dead load on the undeformed outline)"
        )
        + (
            f", the next shape {result.relaxation:g} of the FE's outline and the rest of the "
            "last one (under-relaxed)"
            if result.relaxation < 1.0
            else ""
        )
        + ", until the FE's b/a is within "
        f"{100 * result.tolerance:g} % of the b/a of the shape its flow started from (principal "
        "extents; without relaxation, the pass before's).\n\n"
        + "\n".join(rows)
        + f"\n\n**{result.stopped}**."
    )
    if not result.converged and len(carried) > 1:
        text += f" The last carried pass changed b/a by {last:+.1f} %."
    return text, {"recompute_b_over_a": ratios, "recompute_last_change_pct": last}


def recompute_summary(
    results: list[tuple[float, DeformRecompute | str]],
) -> tuple[str, dict[str, float | list[float]]]:
    """The passes at several pressures in one table: the one-way b/a, the last carried pass's,
    how many passes ran and whether they converged; metrics ``recompute_final_b_over_a``
    (the last carried pass's b/a where the passes converged, NaN elsewhere) and
    ``recompute_passes_run`` per pressure."""
    rows = [
        "| p (hPa) | one-way b/a | after the passes | passes run | converged |",
        "|---|---|---|---|---|",
    ]
    final, count = [], []
    for p_hpa, r in results:
        if isinstance(r, str):
            rows.append(f"| {p_hpa:g} | - | - | 0 | {r} |")
            final.append(math.nan)
            count.append(0.0)
            continue
        carried = r.carried
        first = f"{carried[0]:.4f}" if r.passes[0].carried else "-"
        last = f"{carried[-1]:.4f}" if carried else "-"
        rows.append(
            f"| {p_hpa:g} | {first} | {last} | {len(r.passes)} "
            f"| {'yes' if r.converged else 'no: ' + r.stopped} |"
        )
        final.append(carried[-1] if r.converged else math.nan)
        count.append(float(len(r.passes)))
    text = "Every pressure (each pressure's passes below):\n\n" + "\n".join(rows)
    return text, {"recompute_final_b_over_a": final, "recompute_passes_run": count}
