"""Case kind ``fe_verification``: the FE core against closed forms on gmsh meshes.

Lame sphere (nu 0.3 and 0.499), incompressible neo-Hookean inflation, Hertz contact on three
meshes (observed order), with VTU/PVD, a section PNG and a force history of the Hertz run.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
from typing import Annotated

import matplotlib.pyplot as plt
import numpy as np
from pydantic import Field

from oocyte_fe.fe.fields import contact_pressure_at_vertices, stress_fields
from oocyte_fe.io import FieldSeriesWriter, write_history_csv
from oocyte_fe.plotting import plot_section
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Refining
from oocyte_fe.verification import (
    Verification,
    hertz,
    lame_sphere,
    monotone_observed_order,
    neo_hookean_inflation,
)


class FeVerificationInputs(CaseInputs):
    shell_size_um: float = Field(
        2.0,
        gt=0.2,
        le=10,
        description="element size of the 10-20 um shells",
        json_schema_extra={"unit": "um"},
    )
    hertz_fractions: list[Annotated[float, Field(gt=0.01, le=4)]] = Field(
        [0.5, 0.25, 0.125],
        min_length=3,
        max_length=3,
        description="contact element size / contact radius a, three meshes, each finer",
        json_schema_extra={"unit": "1"},
    )

    rules = (Refining("hertz_fractions"),)


METRICS = {
    "lame_error_nu0.3": "relative error of the inner radial displacement, nu = 0.3",
    "lame_error_nu0.499": "relative error of the inner radial displacement, nu = 0.499",
    "inflation_error": "relative error of the inflation pressure at inner stretch 1.5",
    "inflation_volume_change": "relative volume change in the inflation (nu = 0.5)",
    "hertz_error": "relative error of the Hertz force, finest mesh",
    "hertz_mesh_change": "relative change of the Hertz force between the two finest meshes",
    "hertz_observed_order": "observed convergence order of the Hertz force (NaN where the "
    "three forces do not converge monotonically: not in the asymptotic range)",
}


def _write_hertz_outputs(ctx: CaseContext, v: Verification) -> list[Figure]:
    prob, res = v.problem, v.result
    mesh = prob.body.mesh
    contact = prob.contacts[0][0]
    sphere = contact.obstacle
    theta = np.linspace(-np.pi / 2, 0.0, 60)

    def circle(t: float) -> np.ndarray:
        """The sphere's section (its lower right quarter, um) at time ``t``."""
        cx, cy = np.asarray(sphere.center) + np.asarray(contact.motion(t))
        return np.column_stack(
            [cx + sphere.radius * np.cos(theta), cy + sphere.radius * np.sin(theta)]
        )

    depth = abs(contact.motion(res.frames[-1].t)[1])
    a = np.sqrt(sphere.radius * depth)  # contact radius of the final indentation, um
    top = float(mesh.doflocs[1].max())
    window = (-5 * a, 5 * a, top - 6 * a, top + 1.5 * a)  # the contact zone, um
    with FieldSeriesWriter(
        ctx.output("fields/hertz"), mesh, name="hertz", axisymmetric=True, view_window=window
    ) as writer:
        for frame in res.frames:
            fields = stress_fields(prob, frame.x)
            writer.write(
                frame.t,
                prob.body.vertex_displacement(frame.x),
                pressure=-fields["mean_stress"],
                von_mises=fields["von_mises"],
                contact_pressure=contact_pressure_at_vertices(prob, frame),
                obstacles={"sphere": circle(frame.t)},
            )
    force = np.array([f.obstacle_forces["contact"][1] for f in res.frames])
    write_history_csv(
        ctx.output("hertz_history.csv"),
        {"time": res.times, "force": force, "volume": np.array([f.volume for f in res.frames])},
        {"time": "s", "force": "nN", "volume": "um3"},
    )
    last = res.frames[-1]
    plot_section(
        ctx.output("hertz_section.png"),
        mesh,
        prob.body.vertex_displacement(last.x),
        mirror=True,
        obstacles=[circle(last.t)],
        title=f"Hertz contact zone (contact radius a = {a:.2f} um), displacement magnitude",
        window=window,
    )
    return [
        Figure(
            "hertz_section.png",
            f"Hertz contact, the section within 5 a of the contact (a = {a:.2f} um, the "
            "half-space is 80 a wide), coloured by |u| (um)",
        )
    ]


@case_kind("fe_verification", inputs=FeVerificationInputs, metrics=METRICS)
def run_fe_verification(ctx: CaseContext) -> CaseOutcome:
    """FE core verification against closed-form solutions on gmsh meshes."""
    inp: FeVerificationInputs = ctx.inputs  # type: ignore[assignment]
    metrics: dict[str, float | list[float]] = {}
    rows = []
    for nu in (0.3, 0.499):
        ctx.step(f"Lame sphere nu={nu}")
        v = lame_sphere(nu, inp.shell_size_um)
        metrics[f"lame_error_nu{nu}"] = v.error
        rows.append(v)
    ctx.step("neo-Hookean inflation to stretch 1.5")
    v = neo_hookean_inflation(inp.shell_size_um)
    metrics["inflation_error"] = v.error
    v0 = v.problem.volume(np.zeros_like(v.result.frames[-1].x))
    metrics["inflation_volume_change"] = abs(v.result.frames[-1].volume / v0 - 1)
    rows.append(v)
    hertz_runs = []
    for frac in inp.hertz_fractions:
        ctx.step(f"Hertz, contact elements a*{frac:g}")
        hertz_runs.append(hertz(frac))
    rows += hertz_runs
    forces = [h.computed for h in hertz_runs]
    metrics["hertz_error"] = hertz_runs[-1].error
    metrics["hertz_mesh_change"] = abs(forces[-1] / forces[-2] - 1)
    metrics["hertz_observed_order"] = monotone_observed_order(forces, inp.hertz_fractions)
    ctx.step("writing fields and figures")
    figures = _write_hertz_outputs(ctx, hertz_runs[-1])
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.loglog(inp.hertz_fractions, [h.error for h in hertz_runs], "o-", label="|F/F_Hertz - 1|")
    ax.loglog(
        inp.hertz_fractions[:-1],
        [abs(f / forces[-1] - 1) for f in forces[:-1]],
        "s--",
        label="|F/F_finest - 1|",
    )
    ax.set_xlabel("contact element size / a")
    ax.set_ylabel("relative difference")
    ax.legend()
    fig.tight_layout()
    fig.savefig(ctx.output("hertz_convergence.png"), dpi=120)
    plt.close(fig)
    figures.append(Figure("hertz_convergence.png", "Hertz force against mesh size"))
    table = (
        "| problem | FE | closed form | rel. error | dofs | Newton its/step |\n"
        "|---|---|---|---|---|---|\n"
    )
    for v in rows:
        its = ", ".join(str(s.iterations) for s in v.result.steps)
        table += (
            f"| {v.name} | {v.computed:.6g} | {v.exact:.6g} | {v.error:.2e} | {v.n_dofs} "
            f"| {its} |\n"
        )
    return CaseOutcome(metrics=metrics, figures=figures, sections=[("Verification table", table)])
