"""The report of an FE experiment: history CSV, curves against closed forms, fields, text.

Physics stays in :mod:`~oocyte_fe.experiment.driver` and :mod:`~oocyte_fe.experiment.analysis`;
this module only writes what they return (off-screen figures, Agg backend).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from oocyte_fe.experiment import analysis as an
from oocyte_fe.experiment.driver import ExperimentResult
from oocyte_fe.fe.contact import Contact
from oocyte_fe.fe.obstacles import Circle
from oocyte_fe.io import write_history_csv
from oocyte_fe.plotting import plot_section
from oocyte_fe.verification import (
    THERET_PHI,
    theret_length_um,
)

Output = Callable[[str], Path]


def write_history(result: ExperimentResult, output: Output) -> str:
    """``history.csv``: one row per frame, every recorded series with its unit (a force on a
    tool in plane strain per um of thickness: ``<tool>_force_nN_per_um``)."""
    cols: dict[str, np.ndarray] = {"time": result.times_s, "volume_change": result.volume_change}
    units = {"time": "s", "volume_change": "1"}
    force_unit = "nN_per_um" if an.plane_strain(result) else "nN"
    for name in result.force_nN:
        cols[f"{name}_advance"], units[f"{name}_advance"] = result.advance_um[name], "um"
        cols[f"{name}_force"], units[f"{name}_force"] = an.push_force_nN(result, name), force_unit
        cols[f"{name}_contact_radius"] = result.contact_radius_um[name]
        units[f"{name}_contact_radius"] = "um"
    for name in result.suction_kPa:
        cols[f"{name}_suction"], units[f"{name}_suction"] = result.suction_kPa[name], "kPa"
    for name, length in result.aspiration_change_um.items():
        cols[f"{name}_aspiration"], units[f"{name}_aspiration"] = length, "um"
    for point, track in result.tracks_um.items():
        for i, axis in enumerate("xy"):
            cols[f"{point}_u{axis}"], units[f"{point}_u{axis}"] = track[:, i], "um"
    write_history_csv(output("history.csv"), cols, units)
    return "history.csv"


def _save(fig: plt.Figure, output: Output, name: str) -> str:
    """Lay out, write ``name`` (PNG, 120 dpi) and close ``fig``; the file's name."""
    fig.tight_layout()
    fig.savefig(output(name), dpi=120)
    plt.close(fig)
    return name


def force_figure(result: ExperimentResult, output: Output) -> tuple[str, str]:
    """Force against advance per tool, with Sneddon/Hertz of the outer layer's modulus (not
    in plane strain, nor for probes on a free cell: see :func:`analysis.closed_form_notes`)."""
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for name in result.force_nN:
        d = an.depth_um(result, name)
        ax.plot(d, an.push_force_nN(result, name), "o-", ms=3, label=f"{name} (FE)")
        exact = an.closed_form_force_nN(result, name, d)
        if np.isfinite(exact).any() and an.compared(result, name):
            ax.plot(d, exact, "--", label=f"{name}: closed form, E of the outer layer")
    ax.set_xlabel("advance beyond contact (um)")
    ax.set_ylabel(f"force on the tool ({an.force_unit(result)})")
    ax.legend(fontsize=7)
    ax.set_title(result.experiment.description[:60] or "force against advance", fontsize=9)
    return _save(
        fig, output, "force_advance.png"
    ), "Force on each tool against its advance; dashed: closed form"


def aspiration_figure(result: ExperimentResult, output: Output) -> tuple[str, str]:
    """Aspiration length against suction, with Theret's line (Phi = 2.1)."""
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    E, _ = an.outer_layer_modulus(result)
    for name, length in result.aspiration_change_um.items():
        p = result.suction_kPa[name]
        a = result.experiment.tools[name].inner_radius_um
        ax.plot(1e3 * p, length, "o-", ms=3, label=f"{name} (FE)")
        line = theret_length_um(p, a, E, THERET_PHI)
        ax.plot(1e3 * p, line, "--", label=f"Theret, Phi = {THERET_PHI}, E = {E:g} kPa")
    ax.set_xlabel("suction (Pa)")
    ax.set_ylabel("aspiration length change (um)")
    ax.legend(fontsize=7)
    return _save(
        fig, output, "aspiration.png"
    ), "Aspirated length (apex) against suction; dashed: Theret et al. 1988"


def suction_figure(result: ExperimentResult, output: Output) -> tuple[str, str]:
    """Suction of each pipette against time (prescribed, or the one a control needs)."""
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    for name, p in result.suction_kPa.items():
        ax.plot(result.times_s, 1e3 * p, "o-", ms=3, label=name)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("suction (Pa)")
    ax.legend(fontsize=7)
    controlled = [
        n
        for n in result.suction_kPa
        if getattr(result.experiment.tools[n], "suction_control", None)
    ]
    how = (
        f" ({', '.join(controlled)}: controlled, the suction the path needs)"
        if controlled
        else " (prescribed)"
    )
    return _save(fig, output, "suction.png"), f"Suction against time{how}"


def held_or_reversed(result: ExperimentResult) -> bool:
    """Whether a tool's advance or a pipette's suction stands still or goes back between two
    frames (a hold or a retract): then the curves against advance or suction hide the time."""

    def in_time(series: np.ndarray) -> bool:
        span = float(np.ptp(series))
        return span > 0 and bool((np.diff(series) <= 1e-9 * span).any())

    driven = [*result.advance_um.values(), *result.suction_kPa.values()]
    return any(in_time(np.asarray(s, dtype=float)) for s in driven)


def history_figure(result: ExperimentResult, output: Output) -> tuple[str, str]:
    """Force on each moving tool and each pipette's aspirated length against time: where a
    hold relaxes (force at a held depth) or creeps (length at a held suction)."""
    moving = [n for n, a in result.advance_um.items() if np.ptp(a) > 0]
    panels = [p for p, has in (("force", moving), ("length", result.aspiration_change_um)) if has]
    fig, axes = plt.subplots(len(panels), 1, figsize=(5.5, 2.4 + 1.6 * len(panels)), sharex=True)
    axes = np.atleast_1d(axes)
    for ax, panel in zip(axes, panels, strict=True):
        if panel == "force":
            for name in moving:
                ax.plot(result.times_s, an.push_force_nN(result, name), "o-", ms=3, label=name)
            ax.set_ylabel(f"force on the tool ({an.force_unit(result)})")
        else:
            for name, length in result.aspiration_change_um.items():
                ax.plot(result.times_s, length, "o-", ms=3, label=name)
            ax.set_ylabel("aspiration length change (um)")
        ax.legend(fontsize=7)
    axes[-1].set_xlabel("time (s)")
    what = " and ".join({"force": "force", "length": "aspirated length"}[p] for p in panels)
    return _save(fig, output, "history.png"), (
        f"{what[0].upper()}{what[1:]} against time (a hold or a retract: the relaxation or "
        "creep is read here)"
    )


def tracks_figure(result: ExperimentResult, output: Output) -> tuple[str, str]:
    """Displacement magnitude of each material point against time."""
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    for point, track in result.tracks_um.items():
        ax.plot(result.times_s, np.linalg.norm(track, axis=1), label=point)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("|u| (um)")
    ax.legend(fontsize=7)
    return _save(fig, output, "tracks.png"), "Displacement of the material points"


def summary_text(result: ExperimentResult, metrics: dict[str, float]) -> str:
    """The report's run summary: what was solved, how, and how it ended."""
    exp = result.experiment
    unit = an.force_unit(result)
    lines = [
        f"{exp.cell.symmetry}, outer diameter {exp.cell.outer_diameter_um:g} um, ZP "
        f"{exp.cell.zona_thickness_um:g} um; {result.n_dofs} unknowns; "
        f"{len(result.steps)} steps, {result.newton_iterations} Newton iterations, "
        f"{result.cutbacks} cutbacks; {result.seconds:.1f} s.",
    ]
    if exp.tools:
        lines += [
            "",
            f"| tool | type | final advance (um) | final force ({unit}) | contact radius (um) |",
            "|---|---|---|---|---|",
        ]
    for name in result.force_nN:
        lines.append(
            f"| {name} | {exp.tools[name].type} | {result.advance_um[name][-1]:.4g} | "
            f"{an.push_force_nN(result, name)[-1]:.4g} | "
            f"{result.contact_radius_um[name][-1]:.4g} |"
        )
    if exp.loads:
        lines += ["", f"| load | type | final resultant on the cell ({unit}) |", "|---|---|---|"]
        lines += [
            f"| {name} | {exp.loads[name].type} | ({f[-1, 0]:.4g}, {f[-1, 1]:.4g}) |"
            for name, f in result.load_force_nN.items()
        ]
        if exp.support == "inertia_relief":
            lines += [
                "",
                "A free cell: the loads' resultant and moment are balanced by the body force of "
                "its rigid-body acceleration (inertia relief); the pins' reaction, "
                f"({result.hold_reaction_nN[-1, 0]:.3g}, {result.hold_reaction_nN[-1, 1]:.3g}) "
                f"{unit}, is what that balance leaves.",
            ]
    if not result.success:
        lines += ["", f"**Ended early** at t = {result.times_s[-1]:.4g} s: {result.reason}"]
    for note in an.closed_form_notes(result):
        lines += ["", note]
    lines += ["", "| metric | value |", "|---|---|"]
    lines += [f"| {k} | {v:.5g} |" for k, v in metrics.items()]
    return "\n".join(lines)


def _obstacle_points(contact: Contact, t: float) -> np.ndarray:
    """The tool's section curve (k, 2) um at time ``t`` (a circle sampled at 90 points)."""
    shape = contact.obstacle
    if isinstance(shape, Circle):
        a = np.linspace(0.0, 2.0 * np.pi, 91)
        pts = np.column_stack(
            [shape.center[0] + shape.radius * np.cos(a), shape.center[1] + shape.radius * np.sin(a)]
        )
    else:
        pts = np.asarray(shape.points, dtype=float)
    return pts + np.asarray(contact.motion(t), dtype=float)


def section_figures(result: ExperimentResult, output: Output) -> list[tuple[str, str]]:
    """A section (displacement magnitude, tools drawn) at each of ``record.sections_at_s``:
    the output frame nearest each time."""
    problem = result.problem
    axisym = problem.body.axisym > 0
    times = np.array([f.t for f in result.frames])
    window = result.experiment.record.section_window_um
    figures = []
    for want in result.experiment.record.sections_at_s:
        frame = result.frames[int(np.argmin(np.abs(times - want)))]
        name = f"section_t{frame.t:.4g}s.png"
        plot_section(
            output(name),
            problem.body.mesh,
            problem.body.vertex_displacement(frame.x),
            mirror=axisym,
            obstacles=[_obstacle_points(c, frame.t) for c, _ in problem.contacts],
            title=f"t = {frame.t:.4g} s: displacement magnitude (um)",
            window=tuple(window) if window else None,
        )
        figures.append((name, f"Section at t = {frame.t:.4g} s (asked: {want:g} s), |u| (um)"))
    return figures
