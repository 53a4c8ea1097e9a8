"""The report of the neck passage (kind ``fe_neck_aspiration``): figures and Markdown sections.

The kind runs the passages (:mod:`oocyte_fe.neck.passage`) and computes the metrics; this
module picks the frames to show, draws them (:mod:`oocyte_fe.neck.plotting`) and writes the
tables. Lengths in um, suction in Pa (the seed's unit), moduli in kPa.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.neck import plotting
from oocyte_fe.neck.passage import PassageResult
from oocyte_fe.runner.registry import Figure

Output = Callable[[str], Path]
"""``ctx.output``: the path of a result file of the case."""
Section = tuple[str, str]


def table(header: list[str], rows: list[list[str]]) -> str:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return "\n".join(lines + ["| " + " | ".join(r) + " |" for r in rows])


def passage_figures(
    main: PassageResult,
    output: Output,
    cytoplasm_radius_um: float,
    zona_um: float,
    suction_kPa: float,
) -> list[Figure]:
    """Sections at the start, on entering the neck (front pole past ``z_neck``) and at the end;
    the histories against the applied suction; the wall contact pressure."""
    n = len(main.frames)
    front = main.series("front_pole_um") + cytoplasm_radius_um + zona_um
    entering = int(np.argmax(front > main.pipette.z_neck_um))
    picks = [
        (0, "start (touching the taper)"),
        (entering, "entering the neck"),
        (n - 1, "in the neck"),
    ]
    figures = []
    for k, label in picks:
        name = f"section_{k:02d}.png"
        plotting.plot_state(main, k, output(name), f"t = {main.frames[k].t:.2f} s: {label}")
        figures.append(
            Figure(
                name,
                f"Section at t = {main.frames[k].t:.2f} s ({label}), oocyte "
                "frame (centroid advance removed), coloured by |u - (0, w)| in um.",
            )
        )
    plotting.plot_history(main, output("history.png"), suction_kPa)
    plotting.plot_wall_pressure(main, output("wall_pressure.png"), [k for k, _ in picks[1:]])
    figures += [
        Figure(
            "history.png",
            "Advance against time; suction the quasi-static passage needs "
            "against the advance (dotted: the seed's 100 Pa); axial force balance.",
        ),
        Figure("wall_pressure.png", "Contact pressure along the pipette wall."),
    ]
    return figures


def elastic_section(
    polar_deg: Sequence[float],
    visco_um: np.ndarray,
    elastic_um: np.ndarray,
    visco_suction_Pa: float,
    elastic_suction_Pa: float,
) -> Section:
    """Deformation at the five points with and without the Prony terms."""
    rows = [
        [f"{a:.1f}", f"{v:.2f}", f"{e:.2f}"]
        for a, v, e in zip(polar_deg, visco_um, elastic_um, strict=True)
    ]
    return (
        "Viscoelastic vs elastic",
        table(["polar angle (deg)", "viscoelastic (um)", "elastic (um)"], rows)
        + "\n\nSuction needed, max: viscoelastic "
        f"{visco_suction_Pa:.0f} Pa, "
        f"elastic {elastic_suction_Pa:.0f} Pa.",
    )


def sensitivity_section(
    size_um: float, runs: Sequence[tuple[str, np.ndarray, float, float]]
) -> Section:
    """One row per run: label, deformation at the five points (um), largest suction needed
    (Pa), stall advance (um)."""
    rows = [
        [label, f"{d.min():.2f}", f"{d.max():.2f}", f"{suction:.0f}", f"{stall:.1f}"]
        for label, d, suction, stall in runs
    ]
    header = [
        "run",
        "deformation min (um)",
        "max (um)",
        "suction needed max (Pa)",
        "stall advance at 100 Pa (um)",
    ]
    return (f"Sensitivity (coarse mesh, size {size_um:g} um)", table(header, rows))


def mesh_section(study: Sequence[tuple[float, int, int, np.ndarray]]) -> Section:
    """One row per mesh: element size (um), elements, dofs, deformation at the five points."""
    rows = [
        [f"{s:g}", str(ne), str(nd), ", ".join(f"{v:.2f}" for v in d)] for s, ne, nd, d in study
    ]
    header = ["size (um)", "elements", "dofs", "deformation at the five points (um)"]
    return ("Mesh study", table(header, rows))


def periphery_figure(
    output: Output, polar_deg: Sequence[float], runs: Mapping[str, np.ndarray]
) -> Figure:
    """Deformation at the five points for each run, with the seed's 8-18 um range."""
    plotting.plot_periphery(polar_deg, runs, output("periphery.png"), (8.0, 18.0))
    return Figure(
        "periphery.png",
        "Deformation |u - (0, w)| at the five material "
        "points at t_end for each run, and the seed's 8-18 um range.",
    )


def neck_sections(
    main: PassageResult,
    radial_um: np.ndarray,
    deform_um: np.ndarray,
    mats: LayerMaterials,
    comparisons: list[Section],
    failures: list[str],
    materials_origin: str,
) -> list[Section]:
    """The report's sections: the main run's points and materials (``materials_origin``: where
    they came from), the ``comparisons`` (elastic, sensitivity, mesh study), the solver's cost
    and the runs that stopped early."""
    pts = table(
        ["polar angle (deg)", "radial inward -u_R (um)", "deformation (um)"],
        [
            [f"{a:.1f}", f"{r:.2f}", f"{d:.2f}"]
            for a, r, d in zip(main.points.polar_deg, radial_um, deform_um, strict=True)
        ],
    )
    materials = (
        f"ZP: E0 = {mats.zona.E_kPa:.4g} kPa, g = {mats.zona.prony.g}, "
        f"tau = {mats.zona.prony.tau_s} s; cytoplasm: E = "
        f"{mats.cytoplasm.E_kPa:.4g} kPa (elastic); {materials_origin}."
    )
    steps = main.steps
    body = main.problem.body
    solver = (
        f"{len(steps)} steps, {sum(s.iterations for s in steps)} Newton "
        f"iterations, {sum(s.cutbacks for s in steps)} cutbacks; "
        f"{body.mesh.nelements} P2/P1 triangles, {body.n_dofs} dofs."
    )
    sections = [
        ("Peripheral deformation at t_end (main run)", pts),
        ("Materials", materials),
        *comparisons,
        ("Solver", solver),
    ]
    if failures:
        sections.append(("Runs that stopped early", "\n".join(f"- {f}" for f in failures)))
    return sections
