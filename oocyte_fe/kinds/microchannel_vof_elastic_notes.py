"""Sentences of the ``microchannel_vof`` report's elastic-cell section: writes left out,
the flow's mesh, the crease, and the follower reading of the load."""

from __future__ import annotations

import math

from oocyte_fe.microchannel.elastic_junction import CREASE_STRETCH, ElasticAtPressure
from oocyte_fe.microchannel.vof.extrapolation import power_law


def left_out_note(at: ElasticAtPressure) -> str:
    """A sentence for a pressure whose b/a is read from some of its writes (empty when it is
    read from all or from none): which writes stopped short, and how far they carried."""
    if not at.left_out:
        return ""
    kept = ", ".join(f"{at.traction_x_um[k]:+.1f}" for k in at.read_from)
    out = "; ".join(
        f"{at.traction_x_um[k]:+.1f} um (at most {at.cells[k].load_fraction:.0%} of its load "
        f"on any element size; b/a {at.cells[k].b_over_a:.3f} there)"
        for k in at.left_out
    )
    return (
        f"At {at.pressure_hPa:g} hPa b/a at x = 0 is read from the line through the writes at "
        f"{kept} um, which carried their whole traction, leaving out the write at {out}."
    )


def solved_again_note(cells: list[ElasticAtPressure], reading: str = "") -> str:
    """A paragraph (starting with a blank line; empty when none) naming each write of
    ``cells`` that the first FE run did not carry: its stopped attempts and the one that
    carried it (``reading``: which load, e.g. "the follower reading")."""
    remeshed = [
        f"{c.pressure_hPa:g} hPa, write at {x:+.1f} um: "
        + ", ".join(str(attempt) for attempt in cell.stopped)
        + (f", carried by {cell.attempt}" if cell.experiment.success else ", none carried")
        for c in cells
        for cell, x in zip(c.cells, c.traction_x_um, strict=True)
        if cell.stopped
    ]
    if not remeshed:
        return ""
    return (
        f"\n\nSolved again{' (' + reading + ')' if reading else ''} where Newton stopped short "
        "on the first element size: with a line search, then on other sizes, each plain and "
        "with it (the answer does not depend on the size or the search where two carry the "
        "load; the stalls do): " + "; ".join(remeshed) + "."
    )


def mesh_note(
    base: ElasticAtPressure, other: ElasticAtPressure, dx_um: float, other_dx_um: float
) -> tuple[str, dict[str, float]]:
    """The elastic cell under the second mesh's flow against the first mesh's (same pressure):
    a sentence and ``elastic_mesh_change_pct`` = 100 (b/a_other / b/a - 1), where both carry."""
    head = (
        f"**Flow mesh**: the same FE cell under the traction of the {other_dx_um:g} um flow "
        f"({other.pressure_hPa:g} hPa)"
    )
    if not (base.carried and other.carried):
        return head + ": not compared (the FE did not carry one of the two loads).", {}
    change = 100.0 * (other.b_over_a / base.b_over_a - 1.0)
    text = (
        f"{head}: b/a {other.b_over_a:.4f} against {base.b_over_a:.4f} on {dx_um:g} um "
        f"(**{change:+.1f} %**; 1 - b/a {1 - other.b_over_a:.4f} against "
        f"{1 - base.b_over_a:.4f}). The flow's mesh, not the FE's, sets this spread "
        "(docs/microchannel.md, mesh study)."
    )
    if other.left_out:
        text += " " + left_out_note(other)
    return text, {"elastic_mesh_change_pct": change}


def _b_over_a(at: ElasticAtPressure | None) -> float:
    return at.b_over_a if at is not None and at.carried else math.nan


def mesh_limit_note(
    dx_um: list[float], cells: list[ElasticAtPressure]
) -> tuple[str, dict[str, float | list[float]]]:
    """The elastic cell under the flows of each mesh ``dx_um`` (coarsest first; ``cells`` one
    per mesh, with the follower reading), both readings of the load, and with three meshes or
    more the power law ``b/a(h) = b/a_0 + C h^p`` through the finest three
    (:func:`.vof.extrapolation.power_law`): metrics ``elastic_follower_mesh_b_over_a`` (the
    follower reading on each mesh after the first), ``elastic_mesh_limit_b_over_a`` and
    ``elastic_follower_mesh_limit_b_over_a`` (nan: no order above 0, or the FE stops on one
    of the three)."""
    dead = [_b_over_a(c) for c in cells]
    follower = [_b_over_a(c.follower) for c in cells]
    rows = ["| flow dx (um) | dead load b/a | follower load b/a |", "|---|---|---|"]
    for h, d, f in zip(dx_um, dead, follower, strict=True):
        rows.append(f"| {h:g} | {d:.4f} | {f:.4f} |".replace("nan", "FE stops"))
    metrics: dict[str, float | list[float]] = {"elastic_follower_mesh_b_over_a": follower[1:]}
    text = (
        f"**The elastic cell on every flow mesh** ({cells[0].pressure_hPa:g} hPa; b/a at x = 0 "
        "from the writes of each flow):\n\n" + "\n".join(rows)
    )
    if len(cells) < 3:
        return text, metrics
    limits = []
    for name, values in (("dead load", dead), ("follower load", follower)):
        law = power_law(dx_um[-3:], values[-3:]) if all(map(math.isfinite, values[-3:])) else None
        limit = law.limit if law is not None and math.isfinite(law.order) else math.nan
        limits.append(limit)
        if math.isfinite(limit):
            text += (
                f"\n\n{name.capitalize()}: the power law through the finest three meshes has "
                f"order {law.order:.2f} and the limit b/a **{limit:.4f}** (h -> 0)"
            )
            if math.isfinite(values[0]):
                text += (
                    f"; the case's mesh ({dx_um[0]:g} um) is "
                    f"{100 * (values[0] / limit - 1):+.1f} % from it"
                )
            text += (
                f", the finest ({dx_um[-1]:g} um) {100 * (values[-1] / limit - 1):+.1f} % (how "
                "far the limit is extrapolated; an order well below 1 says the meshes are not "
                "yet in the power law's range)."
            )
        else:
            text += f"\n\n{name.capitalize()}: no h -> 0 limit (no order above 0, or the FE stops)."
    metrics["elastic_mesh_limit_b_over_a"] = limits[0]
    metrics["elastic_follower_mesh_limit_b_over_a"] = limits[1]
    return text, metrics


def stretch_note(cells: list[ElasticAtPressure]) -> str:
    """How far into compression the carried elastic answers reach, against the crease of a
    compressed neo-Hookean surface (:data:`.elastic_junction.CREASE_STRETCH`)."""
    past = [c for c in cells if c.carried and c.smallest_stretch < CREASE_STRETCH]
    if not past:
        return (
            "The smallest principal stretch in the FE cell stays above "
            f"{CREASE_STRETCH} (where a compressed neo-Hookean surface creases) at every "
            "pressure carried."
        )
    where = ", ".join(f"{c.pressure_hPa:g} hPa ({c.smallest_stretch:.2f})" for c in past)
    return (
        f"The smallest principal stretch in the FE cell falls below {CREASE_STRETCH}, where a "
        f"compressed neo-Hookean surface creases (Hong, Zhao & Suo 2009), at {where}: there "
        "the FE follows a smooth solution the solid need not keep, with moduli measured at "
        "the small strains of AFM indentation, so those rows are outside the elastic "
        "model's range."
    )


def follower_note(
    cells: list[ElasticAtPressure], experiment: list[float]
) -> tuple[str, dict[str, float | list[float]]]:
    """The cell under the traction's normal part as a follower pressure (the flow's pressure
    on the deformed outline) beside the dead-load reading: a table and the metrics
    ``elastic_follower_b_over_a`` and ``elastic_follower_min_stretch`` (NaN where the FE
    does not carry the load), and ``elastic_follower_mae`` against ``experiment`` (b/a per
    pressure of ``cells``) over the pressures it carries."""
    rows = [
        "| p (hPa) | dead load b/a | **follower load b/a** | change | smallest stretch "
        "(follower) |",
        "|---|---|---|---|---|",
    ]
    ratio, stretch, misses = [], [], []
    for c, e in zip(cells, experiment, strict=True):
        f = c.follower
        if f is None:
            continue
        dead = f"{c.b_over_a:.4f}" if c.carried else "-"
        if not f.carried:
            worst = min(f.cells, key=lambda cell: cell.load_fraction)
            rows.append(
                f"| {c.pressure_hPa:g} | {dead} | FE stops at {worst.load_fraction:.0%} | - | - |"
            )
            ratio.append(math.nan)
            stretch.append(math.nan)
            continue
        change = f"{100 * (f.b_over_a / c.b_over_a - 1):+.1f} %" if c.carried else "-"
        rows.append(
            f"| {c.pressure_hPa:g} | {dead} | **{f.b_over_a:.4f}** | {change} "
            f"| {f.smallest_stretch:.3f} |"
        )
        ratio.append(f.b_over_a)
        stretch.append(f.smallest_stretch)
        if math.isfinite(e):
            misses.append(abs(f.b_over_a - e))
    text = (
        "**The load's two readings.** Above, the traction is a dead load on the undeformed "
        "outline (force per reference length, by reference polar angle). Read instead as the "
        "flow's pressure on the deformed cell, its normal part is a follower pressure on the "
        "current outline by current polar angle (the tangential part stays dead; the resultant's "
        "change as the cell deforms is taken by the inertia relief): the same writes, b/a at "
        "x = 0 from the line through them:\n\n" + "\n".join(rows)
    )
    metrics: dict[str, float | list[float]] = {
        "elastic_follower_b_over_a": ratio,
        "elastic_follower_min_stretch": stretch,
    }
    if misses:
        metrics["elastic_follower_mae"] = sum(misses) / len(misses)
        text += (
            f"\n\nFollower reading against the experiment: mean |b/a - experiment| = "
            f"{metrics['elastic_follower_mae']:.4f} over the pressures it carries ({len(misses)})."
        )
    text += solved_again_note(
        [c.follower for c in cells if c.follower is not None], "the follower reading"
    )
    return text, metrics
