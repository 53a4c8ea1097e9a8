"""The ``microchannel_vof`` report's deform-recompute sections: each pass of the elastic cell
in the flow around its own deformed shape (:mod:`oocyte_fe.microchannel.elastic_iteration`),
and every pressure's passes in one table."""

from __future__ import annotations

import math

from oocyte_fe.microchannel.elastic_iteration import DeformRecompute


def recompute_section(
    result: DeformRecompute | str, pressure_hPa: float
) -> tuple[str, dict[str, float | list[float]]]:
    """The deform-recompute passes' table and metrics ``recompute_b_over_a`` (each pass's
    b/a, NaN where the FE did not carry its traction), ``recompute_shape_b_over_a`` (its FE
    outline's at x = 0) and ``recompute_last_change_pct``."""
    if isinstance(result, str):
        return result, {}
    rows = [
        "| pass | the shape the flow starts from, b/a (principal extents) "
        "| the flow's cell shape, b/a at the junction (area moments) "
        "| traction taken at x (um) | FE b/a at x = 0 (principal extents) "
        "| FE outline at x = 0, b/a | residual | traction carried "
        "| smallest stretch | change of b/a |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    previous = None  # the last carried pass's b/a
    for k, ps in enumerate(result.passes):
        change, outline, residual = "-", "-", "-"  # no outline read where the FE stopped
        if ps.carried:
            outline, residual = f"{ps.shape_b_over_a:.4f}", f"{100 * ps.residual:+.2f} %"
            if previous is not None:
                change = f"{100 * (ps.b_over_a / previous - 1):+.1f} %"
        out = ps.elastic.left_out  # writes whose FE stopped while the others give b/a
        where = ", ".join(
            f"{x:+.1f}" + (" (left out)" if k in out else "")
            for k, x in enumerate(ps.elastic.traction_x_um)
        )
        rows.append(
            f"| {k} | {ps.start_b_over_a:.4f} | {ps.flow_b_over_a:.4f} | {where} "
            f"| {ps.b_over_a:.4f} | {outline} | {residual} "
            f"| {ps.load_fraction:.0%} | {ps.elastic.smallest_stretch:.3f} | {change} |"
        )
        if ps.carried:
            previous = ps.b_over_a
    ratios = [p.b_over_a if p.carried else math.nan for p in result.passes]
    shapes = [p.shape_b_over_a for p in result.passes]
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
        + ", until the FE's outline at x = 0 has the b/a of the shape its flow started from "
        f"within {100 * result.tolerance:g} % (the residual; principal extents of both "
        "outlines). The FE's b/a in the one-way reading (a line through the writes' b/a) is "
        "beside it: the two readings of the same writes differ where the writes jitter.\n\n"
        + "\n".join(rows)
        + f"\n\n**{result.stopped}**."
    )
    if not result.converged and len(carried) > 1:
        text += f" The last carried pass changed b/a by {last:+.1f} %."
    metrics = {"recompute_b_over_a": ratios, "recompute_shape_b_over_a": shapes}
    return text, {**metrics, "recompute_last_change_pct": last}


def recompute_summary(
    results: list[tuple[float, DeformRecompute | str]],
) -> tuple[str, dict[str, float | list[float]]]:
    """The passes at several pressures in one table: the one-way b/a, the last carried pass's,
    its FE outline's at x = 0, how many passes ran and whether they converged; metrics
    ``recompute_final_b_over_a`` and ``recompute_final_shape_b_over_a`` (those two where the
    passes converged, NaN elsewhere) and ``recompute_passes_run`` per pressure."""
    rows = [
        "| p (hPa) | one-way b/a | after the passes | its outline at x = 0 | passes run "
        "| converged |",
        "|---|---|---|---|---|---|",
    ]
    final, shape, count = [], [], []
    for p_hpa, r in results:
        if isinstance(r, str):
            rows.append(f"| {p_hpa:g} | - | - | - | 0 | {r} |")
            final.append(math.nan)
            shape.append(math.nan)
            count.append(0.0)
            continue
        carried = r.carried
        first = f"{carried[0]:.4f}" if r.passes[0].carried else "-"
        last = f"{carried[-1]:.4f}" if carried else "-"
        done = [p.shape_b_over_a for p in r.passes if p.carried]
        outline = f"{done[-1]:.4f}" if done else "-"
        rows.append(
            f"| {p_hpa:g} | {first} | {last} | {outline} | {len(r.passes)} "
            f"| {'yes' if r.converged else 'no: ' + r.stopped} |"
        )
        final.append(carried[-1] if r.converged else math.nan)
        shape.append(done[-1] if r.converged else math.nan)
        count.append(float(len(r.passes)))
    text = "Every pressure (each pressure's passes below):\n\n" + "\n".join(rows)
    metrics = {"recompute_final_b_over_a": final, "recompute_final_shape_b_over_a": shape}
    return text, {**metrics, "recompute_passes_run": count}
