"""Reports of the NMSD case kinds (:mod:`oocyte_fe.kinds.nmsd_cases`): figures and Markdown.

The kinds compute (calibration, presses, approach, cytoplasm loss) and hand the results here;
this module only draws the figures (through :mod:`nmsd.plotting`) and writes the sections.
Forces arrive in nN and are shown in uN (Table II's unit); lengths in um.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from nmsd.approach_pid import ApproachTrace
from nmsd.calibration import CalibrationResult, FitMetrics, describe_starts
from nmsd.cytoplasm_loss import aspirated_length_for, loss_fraction
from nmsd.lattice import Lattice
from nmsd.plotting import plot_force_curves, plot_snapshots, plot_spindle
from nmsd.press import PressResult, PressSetup
from nmsd.spindle import SpindleOffset
from nmsd.tableII import ForceDisplacement
from oocyte_fe.runner.registry import Figure

UN = 1e-3  # nN -> uN

Output = Callable[[str], Path]
"""``ctx.output``: the path of a result file of the case."""
Sections = list[tuple[str, str]]


def params_table(results: Mapping[str, CalibrationResult], paper: FitMetrics | None) -> str:
    """Calibrated constants and fit metrics of each model family, and the file's model column
    (``force_simulation``; the row is left out when the file has none)."""
    rows = [
        "| model | damping | k1 (nN) | k2 (nN) | d0 (nN s/um) | d1 (nN s/um^2) | dl_c | gap (um) "
        "| RMSE (uN) | R^2 | S |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, r in results.items():
        p = r.params
        m = r.metrics
        gap = "-" if r.gap_um is None else f"{r.gap_um:.3g}"
        rows.append(
            f"| {name} | {p.damping} | {p.k1:.4g} | {p.k2:.4g} | {p.d0:.4g} | {p.d1:.4g} | "
            f"{p.dl_c:.3g} | {gap} | {m.rmse_nN * UN:.3f} | {m.r2:.4f} | {m.similarity:.5f} |"
        )
    if paper is None:
        return "\n".join(rows) + (
            "\n\nThe data file has no force_simulation column: no model column is compared "
            "(paper_rmse_uN is nan)."
        )
    rows.append(
        f"| model column of the file | - | - | - | - | - | - | - | {paper.rmse_nN * UN:.3f} | "
        f"{paper.r2:.4f} | {paper.similarity:.5f} |"
    )
    return "\n".join(rows)


def identifiability_table(results: Mapping[str, CalibrationResult]) -> str:
    """Relative standard error of each fitted constant, or why it is not identified
    (:mod:`nmsd.identifiability`: ``C = sigma^2 (J^T J)^+`` on the log constants)."""
    rows = [
        "| model | constant | value | relative s.e. or not identified |",
        "|---|---|---|---|",
    ]
    for name, r in results.items():
        ident = r.identifiability
        values = {**vars(r.params), "gap_um": r.gap_um}
        rows += [
            f"| {name} | {c} | {values[c]:.4g} | {ident.describe(c)} |" for c in ident.relative_se
        ]
    sigma = {n: r.identifiability.sigma_nN * UN for n, r in results.items()}
    noise = ", ".join(f"{n} {v:.3g} uN" for n, v in sigma.items())
    return "\n".join(rows) + (
        f"\n\nNoise level used (residual s.d., at least 1 % of the RMS force): {noise}. A "
        "constant not identified can be changed many times over without changing the fitted "
        "force curve: do not read it from this fit."
    )


def calibration_report(
    output: Output,
    data: ForceDisplacement,
    results: Mapping[str, CalibrationResult],
    paper: FitMetrics | None,
    setup: PressSetup,
    press: PressResult,
    rate: Mapping[float, PressResult],
    travel_um: float,
) -> tuple[list[Figure], Sections]:
    """Figures and sections of ``nmsd_calibration``.

    ``press`` is the calibrated NMSD's press with its snapshots, ``rate`` its presses at the
    other speeds (um/s -> press); ``paper`` the fit of the file's model column (None: none).
    """
    d = data.displacement_um
    file = Path(data.source).name
    measured = data.force_nN * UN
    curves = {
        f"{name} (RMSE {r.metrics.rmse_nN * UN:.2f} uN)": (d, r.force_nN * UN)
        for name, r in results.items()
    }
    if data.paper_model_nN is not None:
        curves["model column of the file"] = (d, data.paper_model_nN * UN)
    plot_force_curves(output("force_models.png"), d, measured, curves)
    rate_curves = {f"NMSD at {v:g} um/s": (r.advance_um, r.force_nN * UN) for v, r in rate.items()}
    plot_force_curves(output("rate_dependence.png"), d, measured, rate_curves)
    snaps = {0.0: setup.lattice.nodes, **press.snapshots}
    plot_snapshots(output("snapshots.png"), setup.lattice, setup.pipette, snaps)
    rates = "\n".join(
        f"- {k}: force at {travel_um:g} um = {f[-1]:.2f} uN" for k, (_, f) in rate_curves.items()
    )
    cost = "\n".join(
        f"- {n}: {r.evaluations} presses in {r.seconds:.1f} s ({r.message}). {describe_starts(r)}"
        for n, r in results.items()
    )
    figures = [
        Figure("force_models.png", f"{file} against the calibrated model families"),
        Figure("rate_dependence.png", "calibrated NMSD pressed at three speeds (seed Fig. 4)"),
        Figure("snapshots.png", "lattice at 0, 15, 30, 45 um, coloured by |u| (seed Fig. 5)"),
    ]
    sections = [
        ("Calibrated constants (um, nN, s)", params_table(results, paper)),
        ("Identifiability of the constants (docs/nmsd.md)", identifiability_table(results)),
        ("Rate dependence", rates),
        ("Cost", cost),
    ]
    return figures, sections


def spindle_report(
    output: Output,
    lattice: Lattice,
    off: SpindleOffset,
    paper_um: np.ndarray,
    trace: ApproachTrace,
    cal: CalibrationResult,
    cal_source: str,
    removal_pipette_um: float,
    cell_diameter_um: float,
    spindle_length_um: float,
) -> tuple[list[Figure], Sections]:
    """Figures and sections of ``nmsd_spindle_offset``.

    The loss tables use :func:`nmsd.cytoplasm_loss.loss_fraction` (3D and focal-plane
    readings) for mouth-to-spindle distances 0-40 um, and the aspirated lengths that the
    paper's 4.5, 6.9 and 30 % would need.
    """
    plot_spindle(output("spindle_path.png"), off.path_um, paper_um, trace.position_um)
    keys = sorted(off.press.snapshots)
    snaps = {a: off.press.snapshots[a] for a in keys[:: max(1, len(keys) // 3)]}
    plot_snapshots(output("approach_snapshots.png"), lattice, off.pipette, snaps)
    w, d = removal_pipette_um, cell_diameter_um
    lengths = {
        name: (aspirated_length_for(f / 100, w, d), aspirated_length_for(f / 100, w, d, plane=True))
        for name, f in (("proposed", 4.5), ("previous method", 6.9), ("blind aspiration", 30.0))
    }
    gaps = np.array([0.0, 5.0, 10.0, 20.0, 40.0])
    aspirated = gaps + spindle_length_um
    loss3 = 100 * loss_fraction(aspirated, w, d)
    loss2 = 100 * loss_fraction(aspirated, w, d, plane=True)
    loss_rows = "\n".join(
        f"| {g:g} | {a:.2f} | {b:.2f} |" for g, a, b in zip(gaps, loss3, loss2, strict=True)
    )
    paper_rows = "\n".join(
        f"- {n}: 3D needs L = {a:.0f} um, focal-plane reading L = {b:.1f} um"
        for n, (a, b) in lengths.items()
    )
    figures = [
        Figure("spindle_path.png", "spindle path (model), paper's offset, PID pipette trace"),
        Figure("approach_snapshots.png", "lattice during the approach, coloured by |u|"),
    ]
    sections = [
        (
            f"Calibration used ({Path(cal_source).name} only)"
            if cal.evaluations > 1
            else f"Constants used ({cal.message}; their fit on {Path(cal_source).name})",
            f"{cal.params}\n\nRMSE {cal.metrics.rmse_nN * UN:.3f} uN\n\n"
            + identifiability_table({"nmsd": cal}),
        ),
        (
            "Cytoplasm loss against mouth-to-spindle distance (spindle length "
            f"{spindle_length_um:g} um aspirated too)",
            "| distance (um) | 3D loss (%) | focal-plane loss (%) |\n|---|---|---|\n" + loss_rows,
        ),
        ("Aspirated length implied by the paper's percentages", paper_rows),
    ]
    return figures, sections
