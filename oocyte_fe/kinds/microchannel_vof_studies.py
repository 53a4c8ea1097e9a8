"""The study sections of the ``microchannel_vof`` report: time step, mesh, viscosity cap, the
ZP bound, the beside model (labels of :mod:`.microchannel_vof_runs`), and the traction on the
liquid cell.

Every comparison reads the deformation ``1 - b/a`` at the junction (the centroid at x = 0;
at the end of the runs when one does not reach it) and its change in per cent::

    change = 100 ((1 - b/a)_run / (1 - b/a)_reference - 1)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.kinds.microchannel_vof_runs import BESIDE
from oocyte_fe.microchannel.vof.control_volume import box_balance
from oocyte_fe.microchannel.vof.diffuse_force import cell_balance
from oocyte_fe.microchannel.vof.extrapolation import (
    TimeStepStudy,
    common_reading,
    power_law,
    time_step_study,
)
from oocyte_fe.microchannel.vof.foamfile import read_internal_field
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.microchannel.vof.post import moment_trace, time_directories
from oocyte_fe.microchannel.vof.restart import steps_from
from oocyte_fe.microchannel.vof.runner import OpenFoam
from oocyte_fe.microchannel.vof.traction import momentum_balance, surface_traction

TRACTION_OFFSET = 2.0  # cells: the velocity gradient's central stencil lies in the medium
PRESSURE_OFFSET = 1.0  # cells: outside the smeared interface (the inner pressure differs);
# the pressure is read there and twice as far and extrapolated back to the contour
ACCELERATION_WINDOW_S = 4e-5  # the centroid's acceleration: a parabola over +-20 us


def readings(runs: list[JunctionRun]) -> tuple[str, tuple[float, ...]]:
    """Where the runs are read together and their b/a there (:func:`.common_reading`)."""
    return common_reading(
        [r.ratio_at_junction for r in runs], [float(r.history.ratio[-1]) for r in runs]
    )


def deformation_change_pct(ours: float, theirs: float) -> float:
    """Signed change of 1 - b/a from b/a ``theirs`` to b/a ``ours`` (module docstring), %."""
    return 100.0 * ((1.0 - ours) / (1.0 - theirs) - 1.0)


def sensitivity_notes(
    extra: dict[str, JunctionRun], base: JunctionRun, correctors: dict[str, int]
) -> tuple[list[str], dict[str, float]]:
    """One line per cap / ZP run against ``base`` (the first pressure), and the metrics
    ``mesh_change_pct`` (b/a, %) and ``mesh_deformation_change_pct`` of the first finer mesh
    (its line is in :func:`mesh_study`'s table), ``cap_change_pct`` (b/a),
    ``zp_change_pct`` (1 - b/a)."""
    notes, metrics = [], {}
    for label, r in extra.items():
        if label.startswith(BESIDE) or "_dt" in label:
            continue
        where, (ours, theirs) = readings([r, base])
        ratio_change = 100.0 * abs(ours / theirs - 1.0)
        deformation = deformation_change_pct(ours, theirs)
        if "_dx" in label:  # the first finer mesh: the mesh check (listed in the mesh table)
            metrics.setdefault("mesh_change_pct", ratio_change)
            metrics.setdefault("mesh_deformation_change_pct", deformation)
            continue
        if "_cap" in label:
            metrics["cap_change_pct"] = ratio_change
        else:
            metrics["zp_change_pct"] = deformation
        notes.append(
            f"- {label}: b/a at {where} {ours:.5f} against {theirs:.5f} ({ratio_change:.2f} %); "
            f"1 - b/a {1 - ours:.5f} against {1 - theirs:.5f} (**{deformation:+.1f} %**); "
            f"{r.n_cells} cells, {correctors.get(label, 0)} pressure correctors, "
            f"{r.steps} steps, {r.wall_seconds:.0f} s wall"
        )
    return notes, metrics


def mesh_study(
    base_dx: float, base: JunctionRun, meshes: list[tuple[float, JunctionRun]]
) -> tuple[str, dict[str, float | list[float]]]:
    """The mesh section: 1 - b/a of the first pressure on ``base_dx`` and each finer mesh
    (where all reach x = 0, else at the end), and with three meshes or more the power law
    ``e(h) = e0 + C h^p`` through the finest three (:func:`.extrapolation.power_law`).
    Metrics ``mesh_dx_um``, ``mesh_deformation`` (per mesh); ``mesh_order``,
    ``deformation_mesh_limit`` and ``deformation_mesh_error_pct`` (the case's mesh against
    the limit) when the finest three give an order (:func:`.power_law`)."""
    runs = [(base_dx, base), *meshes]
    where, ratios = readings([r for _, r in runs])
    e = [1.0 - v for v in ratios]
    rows = [
        f"| dx (um) | cells | b/a at {where} | 1 - b/a | change of 1 - b/a against the "
        "previous mesh | largest Courant number | wall (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for k, (dx, r) in enumerate(runs):
        change = f"{100 * (e[k] / e[k - 1] - 1):+.1f} %" if k else ""
        rows.append(
            f"| {dx:.4g} | {r.n_cells} | {ratios[k]:.5f} | {e[k]:.5f} | {change} "
            f"| {r.max_courant:.2f} | {r.wall_seconds:.0f} |"
        )
    metrics: dict[str, float | list[float]] = {
        "mesh_dx_um": [dx for dx, _ in runs],
        "mesh_deformation": e,
    }
    text = "\n".join(rows)
    if len(runs) < 3:
        return text, metrics
    h = [dx for dx, _ in runs[-3:]]
    fit = power_law(h, e[-3:])
    hs = ", ".join(f"{v:.4g}" for v in h)
    if not math.isfinite(fit.order):
        text += (
            f"\n\nOn {hs} um the differences of 1 - b/a do not shrink monotonically (factor "
            f"{fit.factor:.2f}): no observed order, no h -> 0 limit; the finest mesh reads "
            f"{e[-1]:.5f}."
        )
        return text, metrics
    error = 100 * (e[0] / fit.limit - 1)
    text += (
        f"\n\nPower law e(h) = e0 + C h^p through {hs} um: observed order **p = "
        f"{fit.order:.2f}**, limit **1 - b/a = {fit.limit:.5f}** (b/a {1 - fit.limit:.5f}); "
        f"the case's {base_dx:g} um mesh is {error:+.0f} % from it in 1 - b/a."
    )
    metrics.update(
        mesh_order=fit.order, deformation_mesh_limit=fit.limit, deformation_mesh_error_pct=error
    )
    return text, metrics


def dt_study(dt: float, runs: list[JunctionRun]) -> tuple[str, TimeStepStudy, float]:
    """The time-step section for ``runs`` at dt, dt/2, ...: its text, the study, and the
    largest change of 1 - b/a between successive halvings (%)."""
    study = time_step_study(
        dt, [r.ratio_at_junction for r in runs], [float(r.history.ratio[-1]) for r in runs]
    )
    d = 1.0 - np.array(study.ratios)
    changes = 100.0 * (d[1:] / d[:-1] - 1.0)
    return _dt_section(study, runs), study, float(np.max(np.abs(changes)))


def _dt_section(study: TimeStepStudy, runs: list[JunctionRun]) -> str:
    """The report's time-step table and the sentence on its dt -> 0 limit."""
    ratios, where, dt = study.ratios, study.where, study.dt_s
    rows = [
        f"| dt (s) | b/a at {where} | 1 - b/a | 1 - b/a against the previous dt | steps "
        "| wall (s) |",
        "|---|---|---|---|---|---|",
    ]
    for k, r in enumerate(runs):
        change = f"{100 * ((1 - ratios[k]) / (1 - ratios[k - 1]) - 1):+.1f} %" if k else ""
        rows.append(
            f"| {dt / 2**k:g} | {ratios[k]:.5f} | {1 - ratios[k]:.5f} | {change} "
            f"| {r.steps} | {r.wall_seconds:.0f} |"
        )
    lines = ["\n".join(rows), ""]
    ex = study.extrapolation
    if ex is None:
        lines.append("Two time steps: no observed order, no dt -> 0 estimate (set 2 refinements).")
    elif not ex.converging:
        lines.append(
            f"The differences of b/a do not shrink over the finest three time steps (factor "
            f"{ex.factor:.2f} per halving): no dt -> 0 estimate."
        )
    else:
        base = ratios[0]
        how = (
            f"Richardson over the finest three, observed order p = {ex.order:.2f}"
            if ex.monotone
            else f"the differences alternate, factor q = {ex.factor:.2f} per halving: no "
            "observed order; the geometric (Aitken) limit, which lies between the two "
            "finest values, is an estimate only"
        )
        lines.append(
            f"**dt -> 0 at {where} ({how}): b/a = {ex.limit:.5f}, 1 - b/a = "
            f"{1 - ex.limit:.5f}**, against b/a = {base:.5f}, 1 - b/a = {1 - base:.5f} at the "
            f"case's dt = {dt:g} s: its dt error is {100 * (base / ex.limit - 1):+.2f} % in "
            f"b/a and {100 * ((1 - base) / (1 - ex.limit) - 1):+.0f} % in 1 - b/a."
        )
    return "\n".join(lines)


def traction_study(
    run: JunctionRun,
    layout: Layout,
    mu_medium: float,
    density: float,
    csv: Path,
    box: tuple[OpenFoam, float, int] | None = None,
) -> tuple[str, dict[str, float]]:
    """The traction of the flow on the liquid cell at the written time nearest its junction
    crossing (:mod:`oocyte_fe.microchannel.vof.traction`), written to ``csv``, and its
    momentum check: the section text and the metrics ``traction_imbalance_pct``,
    ``traction_force_x``, ``traction_force_y`` (nN/um), ``traction_at_x_um``. With ``box`` =
    (OpenFOAM, medium density, niceness): two more steps from that time and the momentum
    budget of a box around the cell (:mod:`oocyte_fe.microchannel.vof.control_volume`),
    metric ``cv_imbalance_pct``."""
    folders = time_directories(run.case)[1:]
    t_j = run.time_at_junction if math.isfinite(run.time_at_junction) else folders[-1][0]
    t, folder = min(folders, key=lambda tf: abs(tf[0] - t_j))
    trace = moment_trace(run.case, ["cell"])
    traction = surface_traction(
        folder, layout, "cell", mu_medium, TRACTION_OFFSET, PRESSURE_OFFSET, True
    )
    traction.write_csv(csv)
    area = _cell_area(folder, layout)
    window = ACCELERATION_WINDOW_S
    balance = momentum_balance(traction, trace, area, density, window)
    x_at = float(np.interp(t, trace.time, trace.centroid[:, 0]))
    f, ma = balance.force, balance.momentum_rate
    text = (
        f"`{csv.name}`: {len(traction.angle)} edges of the alpha = 0.5 contour at t = {t:.4g} s "
        f"(centroid x = {x_at:.1f} um); columns arc_angle_deg (about the centroid, from +x, "
        "counter-clockwise), x_um, y_um (edge midpoint), t_x_kPa, t_y_kPa (traction of the "
        f"medium on the cell, outward normal; pressure read {PRESSURE_OFFSET:g} and "
        f"{2 * PRESSURE_OFFSET:g} cells outside the contour and extrapolated to it, velocity "
        f"gradient {TRACTION_OFFSET:g} cells outside). Net force (per unit depth) "
        f"F = ({f[0]:.2f}, {f[1]:.2f}) nN/um against the cell's momentum rate M a = "
        f"({ma[0]:.2f}, {ma[1]:.2f}) nN/um (M = rho x area {area:.0f} um^2, a from the per-step "
        f"centroid over {window * 1e6:.0f} us): |F - M a| = **{balance.imbalance_pct:.1f} %** "
        f"of the load sum |t + p_mean n| ds = {balance.gross:.1f} nN/um. This reading is "
        "reported, not loaded: the FE cell takes the diffuse interface's force (below; "
        "vof.band_traction)."
    )
    metrics = {
        "traction_imbalance_pct": balance.imbalance_pct,
        "traction_force_x": float(f[0]),
        "traction_force_y": float(f[1]),
        "traction_at_x_um": x_at,
    }
    if box is not None:
        foam, rho_medium, nice = box
        try:
            first, second = steps_from(foam, run.case, folder, 2, "momentum_steps", nice)
            cv = box_balance(first, second, layout, "cell", density, rho_medium, mu_medium)
        except (InputError, SolverError) as exc:  # e.g. a box cut by a wall
            return text + f"\n\nControl volume around the cell: not computed: {exc}", metrics
        miss = cv.force - cv.outflow - cv.momentum_rate
        x0, x1, y0, y1 = cv.box_um
        text += (
            f"\n\n**Control volume around the cell** (two more steps from t = {t:.4g} s; the box "
            f"x {x0:.1f} to {x1:.1f}, y {y0:.1f} to {y1:.1f} um, faces in the medium): forces "
            f"on its faces less the momentum carried out ({cv.force[0] - cv.outflow[0]:.2f}, "
            f"{cv.force[1] - cv.outflow[1]:.2f}) nN/um against the rate of its momentum "
            f"({cv.momentum_rate[0]:.2f}, {cv.momentum_rate[1]:.2f}) nN/um: miss "
            f"({miss[0]:.2f}, {miss[1]:.2f}) = **{cv.imbalance_pct:.2f} %** of the load on the "
            f"box, {cv.load:.1f} nN/um."
        )
        metrics["cv_imbalance_pct"] = cv.imbalance_pct
        try:
            cb = cell_balance(first, second, layout, "cell", density, rho_medium, mu_medium)
        except InputError as exc:
            return text + f"\n\nThe cell's own budget: not computed: {exc}", metrics
        text += (
            "\n\n**The cell's own budget from its diffuse interface** (the same two steps): the "
            f"force -sum sigma . grad(alpha) dA = ({cb.force[0]:.2f}, {cb.force[1]:.2f}) nN/um "
            "against the rate of the cell's momentum d/dt sum alpha rho u dA = "
            f"({cb.momentum_rate[0]:.2f}, {cb.momentum_rate[1]:.2f}) nN/um: miss "
            f"**{cb.imbalance_pct:.2f} %** of the load on the band, {cb.load:.1f} nN/um "
            f"({100 * np.linalg.norm(cb.force - cb.momentum_rate) / balance.gross:.2f} % of the "
            "contour's load above). With the transposed part of the viscous stress at the "
            "first step's velocity, as the solver integrates it (explicitly): "
            f"({cb.force_explicit[0]:.2f}, {cb.force_explicit[1]:.2f}) nN/um, miss "
            f"**{cb.explicit_imbalance_pct:.2f} %**. With what the solver's upwind-biased "
            "convection leaves on the lattice, -sum alpha C dA + sum (d alpha) rho u dA / dt "
            f"= ({cb.convection[0]:.2f}, {cb.convection[1]:.2f}) nN/um (zero in the continuum; "
            f"vof.convection): miss **{cb.scheme_imbalance_pct:.2f} %**."
        )
        metrics["diffuse_imbalance_pct"] = cb.imbalance_pct
        metrics["diffuse_explicit_imbalance_pct"] = cb.explicit_imbalance_pct
        metrics["diffuse_scheme_imbalance_pct"] = cb.scheme_imbalance_pct
    return text, metrics


def _cell_area(folder: Path, layout: Layout) -> float:
    """The cell's area (um^2, per unit depth): sum alpha dx^2."""
    alpha = read_internal_field(folder / "alpha.cell", layout.n_cells)
    return float(alpha.sum() * layout.dx**2)
