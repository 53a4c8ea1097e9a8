"""The report of the FE / NMSD cross-check (kind ``nmsd_vs_fe``): figures and Markdown.

The kind presses both models and compares them (:mod:`oocyte_fe.crosscheck`); this module
draws the comparison (:mod:`oocyte_fe.crosscheck.plotting`, :func:`oocyte_fe.plotting.
plot_section`) and writes the sections. Forces arrive in nN and are shown in uN (Table II's
unit); lengths in um.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from nmsd.area import poisson_ratio
from nmsd.calibration import CalibrationResult, FitMetrics, describe_starts
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement
from oocyte_fe.crosscheck.agreement import DisplacementAgreement
from oocyte_fe.crosscheck.fe_press import FePress, pipette_at
from oocyte_fe.crosscheck.plotting import plot_displacement_arrows, plot_force_overlay
from oocyte_fe.crosscheck.scenario import PressScenario
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.io import FieldSeriesWriter, write_history_csv
from oocyte_fe.plotting import plot_section
from oocyte_fe.runner.registry import Figure

UN = 1e-3  # nN -> uN

Output = Callable[[str], Path]
"""``ctx.output``: the path of a result file of the case."""
Section = tuple[str, str]


def crosscheck_figures(
    output: Output,
    fe: FePress,
    fe_nN: np.ndarray,
    thickness_um: float,
    cal: CalibrationResult,
    vs_fe: FitMetrics,
    table: ForceDisplacement,
    agree: DisplacementAgreement,
    points: np.ndarray,
    u_fe: np.ndarray,
    u_nm: np.ndarray,
    arrows: Sequence[float],
    scenario: PressScenario,
    setup: PressSetup,
    edge_radius_um: float = 0.0,
) -> list[Figure]:
    """Force curves (with Table II and NMSD - FE), displacement arrows at the ``arrows``
    advances, and the FE section at the end of the travel (the FE's wedge: its mouth edges
    rounded with ``edge_radius_um``)."""
    plot_force_overlay(
        output("force_curves.png"),
        {
            f"FE (AFM moduli, x {thickness_um:g} um)": (fe.advance_um, fe_nN * UN),
            f"NMSD calibrated to FE (R^2 {vs_fe.r2:.4f})": (fe.advance_um, cal.force_nN * UN),
        },
        measured=(table.displacement_um, table.force_nN * UN),
        difference=(fe.advance_um, (cal.force_nN - fe_nN) * UN),
    )
    plot_displacement_arrows(
        output("displacement_arrows.png"),
        points,
        agree,
        u_fe,
        u_nm,
        list(arrows),
        scenario.radius_um,
        {a: setup.pipette.outline(a) for a in arrows},
    )
    end = pipette_at(scenario, fe.advance_um[-1], edge_radius_um=edge_radius_um)
    plot_section(
        output("fe_section_end.png"),
        fe.mesh,
        fe.vertex_displacement_um[-1],
        obstacles=[np.asarray(end.points)],
        title=f"FE at {fe.advance_um[-1]:g} um advance, displacement magnitude",
    )
    return [
        Figure(
            "force_curves.png",
            "FE force (per unit thickness times the effective thickness) and the NMSD "
            "calibrated to it, with Table II (measured, not fitted); lower panel NMSD - FE.",
        ),
        Figure(
            "displacement_arrows.png",
            "Displacements (true scale) at the spindle (star) and the grid: FE blue, NMSD "
            "red, pipette grey; last panel: spindle displacement, error and goal.",
        ),
        Figure("fe_section_end.png", "FE disc at the end of the travel (ZP and cytoplasm)."),
    ]


def crosscheck_sections(
    materials: LayerMaterials,
    creep_file: str,
    ring_input: float | str,
    cal: CalibrationResult,
    vs_fe: FitMetrics,
    agree: DisplacementAgreement,
    slow_error: np.ndarray,
    scale: float,
    departure: tuple[float, float],
    fe: FePress,
) -> list[Section]:
    """Materials, calibrated constants, spindle table, where the NMSD departs, FE cost.

    ``departure`` is the advance (um) and size (nN) of the largest NMSD - FE force difference;
    ``slow_error`` the spindle error (um) with the NMSD drag scaled by ``scale``.
    """
    depart_um, depart_nN = departure
    n = len(agree.advance_um)
    return [
        ("Materials (AFM chain)", materials_text(materials, creep_file, ring_input)),
        ("NMSD constants calibrated to the FE curve (um, nN, s)", params_text(cal, vs_fe)),
        ("Spindle displacement by advance (um)", spindle_table(agree, slow_error, scale)),
        (
            "Where the reduced model departs",
            f"Largest force difference NMSD - FE: {depart_nN * UN:+.2f} uN at "
            f"{depart_um:g} um. Spindle goal met at "
            f"{int(np.sum(agree.spindle_ratio <= 1))} of {n} advances. "
            f"With the NMSD drag d0, d1 scaled by {scale:g} (springs unchanged, "
            f"force no longer fitted) the spindle error falls to at most "
            f"{slow_error.max():.1f} um (from {agree.spindle_error_um.max():.1f} um).",
        ),
        (
            "FE solver",
            f"{fe.steps} steps, {fe.cutbacks} cutbacks, {fe.newton_iterations} Newton "
            f"iterations, {fe.seconds:.1f} s; {fe.mesh.nelements} P2 triangles; largest "
            f"penetration {fe.penetration_um.max():.3f} um.",
        ),
    ]


def materials_text(materials: LayerMaterials, creep_file: str, ring_input: float | str) -> str:
    """The ZP Prony series and the cytoplasm from the AFM chain; the layers' modulus ratio."""
    z = materials.zona
    terms = ", ".join(
        f"g={g:.4f} tau={t:.4g} s" for g, t in zip(z.prony.g, z.prony.tau_s, strict=True)
    )
    return (
        f"ZP: E0 = {z.E_kPa:.4g} kPa, nu = {z.nu:g}, Prony {terms} (from `{creep_file}`"
        f": {materials.zona.source}). Cytoplasm: E = {materials.cytoplasm.E_kPa:g} kPa, "
        f"nu = {materials.cytoplasm.nu:g}, elastic."
        f" E_zp / E_cyto: {materials.stiffness_ratio(relaxed=False):.4g} instantaneous, "
        f"{materials.stiffness_ratio(relaxed=True):.4g} relaxed (NMSD ring input: "
        f"`{ring_input}`)."
    )


def params_text(cal: CalibrationResult, metrics: FitMetrics) -> str:
    """The NMSD constants calibrated to the FE curve and the fit's metrics."""
    p = cal.params
    area = (
        f"area term {p.area_stiffness:g} k1/h (small-strain plane-strain Poisson ratio "
        f"{poisson_ratio(p.area_stiffness):.3f}); ZP ring k1, k2 x {p.zona_stiffness_ratio:.4g}"
        f" beyond r = {p.zona_inner_radius_um:.2f} um; "
    )
    return (
        f"k1 = {p.k1:.4g} nN, k2 = {p.k2:.4g} nN, dl_c = {p.dl_c:g}, d0 = {p.d0:.4g} nN s/um, "
        f"d1 = {p.d1:.4g} nN s/um^2; {area}RMSE {metrics.rmse_nN * UN:.3f} uN, "
        f"R^2 {metrics.r2:.4f}, S {metrics.similarity:.5f}; {cal.evaluations} presses in "
        f"{cal.seconds:.1f} s. {describe_starts(cal)}"
    )


def spindle_table(agree: DisplacementAgreement, slow_error: np.ndarray, scale: float) -> str:
    """Spindle displacement of both models, error and goal by advance (um)."""
    rows = [
        "| advance | FE (ux, uy) | NMSD (ux, uy) | error | goal | max grid error | "
        f"error, drag x {scale:g} |",
        "|---|---|---|---|---|---|---|",
    ]
    for k, a in enumerate(agree.advance_um):
        fe, nm = agree.spindle_fe_um[k], agree.spindle_nmsd_um[k]
        rows.append(
            f"| {a:g} | ({fe[0]:.2f}, {fe[1]:.2f}) | ({nm[0]:.2f}, {nm[1]:.2f}) | "
            f"{agree.spindle_error_um[k]:.2f} | {agree.spindle_tolerance_um[k]:.2f} | "
            f"{agree.error_um[k].max():.2f} | {slow_error[k]:.2f} |"
        )
    return "\n".join(rows)


def write_press_outputs(
    output: Callable[[str], Path],
    fe: FePress,
    fe_nN: np.ndarray,
    cal: CalibrationResult,
    agree: DisplacementAgreement,
    scenario: PressScenario,
    edge_radius_um: float = 0.0,
) -> None:
    """The FE press's VTU/PVD series (``fields/``, with the FE's wedge: mouth edges rounded
    with ``edge_radius_um``), ``force_history.csv`` (uN) and ``spindle_history.csv`` (um) of
    both models."""
    with FieldSeriesWriter(output("fields"), fe.mesh, "press") as series:
        for k, advance in enumerate(fe.advance_um):
            series.write(
                advance / scenario.speed_um_s,  # s
                fe.vertex_displacement_um[k],
                pressure=fe.vertex_pressure_kPa[k],
                obstacles={
                    "pipette": np.asarray(
                        pipette_at(scenario, advance, edge_radius_um=edge_radius_um).points
                    )
                },
            )
    write_history_csv(
        output("force_history.csv"),
        {
            "advance": fe.advance_um,
            "force_fe_per_thickness": fe.force_nN_per_um,
            "force_fe": fe_nN * UN,
            "force_nmsd": cal.force_nN * UN,
            "penetration": fe.penetration_um,
        },
        {
            "advance": "um",
            "force_fe_per_thickness": "nN_per_um",
            "force_fe": "uN",
            "force_nmsd": "uN",
            "penetration": "um",
        },
    )
    columns = {
        "advance": fe.advance_um[1:],
        "spindle_fe_ux": agree.spindle_fe_um[:, 0],
        "spindle_fe_uy": agree.spindle_fe_um[:, 1],
        "spindle_nmsd_ux": agree.spindle_nmsd_um[:, 0],
        "spindle_nmsd_uy": agree.spindle_nmsd_um[:, 1],
        "spindle_error": agree.spindle_error_um,
        "goal": agree.spindle_tolerance_um,
        "grid_error_max": agree.error_um.max(axis=1),
    }
    write_history_csv(output("spindle_history.csv"), columns, dict.fromkeys(columns, "um"))
