"""Case kind ``fe_experiment``: any FE experiment on a layered cell, from ``case.toml`` alone.

Validate the description (:class:`~oocyte_fe.experiment.description.Experiment`), run the one
driver, hand the result to the report builder. ``oocyte-fe new fe_experiment DIR --template
NAME`` writes a ready case (docs/fe.md, "Experiments").
"""

from __future__ import annotations

import numpy as np

from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment import report as rp
from oocyte_fe.experiment.analysis import closed_form_metrics
from oocyte_fe.experiment.templates import TEMPLATES
from oocyte_fe.fe.fields import contact_pressure_at_vertices, stress_fields
from oocyte_fe.io import FieldSeriesWriter
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind

METRICS = {
    "theret_phi": "effective wall factor of the first suction pipette (homogeneous cell)",
    "theret_modulus_kPa": "modulus inferred from the aspiration curve with Theret, Phi = 2.1",
    "cone_force_ratio": "FE force / Sneddon cone (outer layer's E) at the deepest frame",
    "cone_fit_modulus_kPa": "modulus of afm's Sneddon cone fitted to the FE curve",
    "sphere_force_ratio": "FE force / Sneddon's exact sphere (effective radius), deepest frame",
    "sphere_fit_modulus_kPa": "modulus of afm's hertz_sphere (effective radius) fitted",
    "plate_hertz_ratio": "plate force / Hertz (sphere on a flat) at the first frame",
    "plate_force_nN": "force on the first plate at the last frame (plane strain: nN/um)",
    "aspect_ratio": "b/a of the deformed section under surface loads (principal extents)",
    "deformation": "1 - b/a of the deformed section under surface loads",
    "completed_fraction": "time reached / duration (1: the whole path solved)",
    "volume_change": "largest relative volume change",
}


def whole_path_check(result, fraction: float) -> Check:
    """``completed_fraction`` (the metric, ``fraction``) == 1: a run that ended early fails,
    the check's name (the summary's reason) giving the time reached and the solver's message."""
    reached, duration = float(result.times_s[-1]), result.experiment.time.duration_s
    name = "the whole path was solved"
    if not result.success:
        name += f" (ended early at t = {reached:.4g} s of {duration:g} s: {result.reason})"
    return Check(
        name,
        fraction,
        bool(result.success and fraction >= 1.0 - 1e-9),
        "completed_fraction = 1",
        reference=1.0,
        unit="1",
    )


def _fields(ctx: CaseContext, result) -> None:
    problem = result.problem
    with FieldSeriesWriter(
        ctx.output("fields/experiment"),
        problem.body.mesh,
        name="experiment",
        axisymmetric=problem.body.axisym > 0,
    ) as writer:
        for frame in result.frames:
            fields = stress_fields(problem, frame.x)
            writer.write(
                frame.t,
                problem.body.vertex_displacement(frame.x),
                pressure=-fields["mean_stress"],
                von_mises=fields["von_mises"],
                contact_pressure=contact_pressure_at_vertices(problem, frame),
            )


@case_kind("fe_experiment", inputs=Experiment, metrics=METRICS, templates=TEMPLATES)
def run_fe_experiment(ctx: CaseContext) -> CaseOutcome:
    """Run the experiment of ``case.toml`` and report its curves against closed forms."""
    exp: Experiment = ctx.inputs  # type: ignore[assignment]
    ctx.step("solving the experiment")
    result = run_experiment(exp, log=ctx.log)
    metrics = closed_form_metrics(result)
    ctx.step("writing the report")
    rp.write_history(result, ctx.output)
    moved = any(np.ptp(a) > 0 for a in result.advance_um.values())  # a still tool: no curve
    figures = [Figure(*rp.force_figure(result, ctx.output))] if moved else []
    if rp.held_or_reversed(result) and (moved or result.aspiration_change_um):
        figures.append(Figure(*rp.history_figure(result, ctx.output)))
    if result.suction_kPa:
        figures.append(Figure(*rp.suction_figure(result, ctx.output)))
    if result.aspiration_change_um:
        figures.append(Figure(*rp.aspiration_figure(result, ctx.output)))
    if result.tracks_um:
        figures.append(Figure(*rp.tracks_figure(result, ctx.output)))
    figures += [Figure(*f) for f in rp.section_figures(result, ctx.output)]
    if exp.record.fields:
        _fields(ctx, result)
    return CaseOutcome(
        metrics=metrics,
        figures=figures,
        sections=[("Experiment", rp.summary_text(result, metrics))],
        checks=[whole_path_check(result, metrics["completed_fraction"])],
    )
