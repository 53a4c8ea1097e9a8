"""The viscoelastic ramp fits in the report of ``afm_fit_files``: the ``ve_`` columns of
``fits.csv``, the F(t) figures (per curve and per group), the metrics and the report section."""

from __future__ import annotations

import csv
import re
from collections.abc import Callable
from pathlib import Path

from afm import plotting
from afm.fit_files import FitFilesResult, ramp_material
from afm.ramp_files import RAMP_COLUMNS, RampFilesResult, terms_text
from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs
from oocyte_fe.runner.registry import Figure

Output = Callable[[str], Path]
"""``ctx.output``: the path of a result file of the case."""


def file_stem(group: str) -> str:
    """``group`` as part of a file name: characters other than letters, digits, ``-`` and
    ``_`` become ``_`` (a group name can never reach outside the result folder)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", group) or "_"


def add_ramp_columns(path: Path, ramps: RampFilesResult, links: dict[str, str]) -> None:
    """Add the ramp fits' columns (:data:`afm.ramp_files.RAMP_COLUMNS`) to ``fits.csv``, on
    the row of the same file and curve; ``links``: curve source -> its F(t) figure."""
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    by_curve = {
        (r.file, "" if r.curve_index is None else str(r.curve_index)): r for r in ramps.rows
    }
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, [*(rows[0] if rows else {}), *RAMP_COLUMNS])
        writer.writeheader()
        for row in rows:
            ramp = by_curve.get((row["file"], row["curve_index"]))
            values = ramp.columns() if ramp else dict.fromkeys(RAMP_COLUMNS, "")
            values["ve_plot"] = links.get(ramp.source, "") if ramp else ""
            writer.writerow(row | values)


def ramp_figure_name(group: str) -> str:
    """File name of a group's ramp-fit figure."""
    return f"ramp_{file_stem(group)}.png"


def ramp_figures(ramps: RampFilesResult, output: Output, which: str) -> dict[str, str]:
    """F(t) of every curve's own ramp fit (``curve_plots/<name>_ramp_fit.png``; ``which``:
    all, poor or none, as the curve plots); curve source -> the figure's path in the results."""
    links = {}
    for row in ramps.rows:
        if row.fit is None or which == "none" or (which == "poor" and row.fit.quality == "good"):
            continue
        stem = Path(row.file).stem + (
            "" if row.curve_index is None else f"_curve{row.curve_index:04d}"
        )
        name = f"curve_plots/{stem}_ramp_fit.png"
        title = f"{row.file}: {row.fit.relaxation} ramp fit, {row.fit.quality}"
        plotting.plot_ramp_fit(row.fit, output(name), title)
        links[row.source] = name
    return links


def group_figures(ramps: RampFilesResult, output: Output) -> list[Figure]:
    """F(t) against Ting's fit, residual below, of each group's (joint) ramp fit."""
    figures = []
    for g in ramps.groups:
        name = ramp_figure_name(g.group)
        title = (
            f"{g.group}: {g.fit.relaxation} ramp fit of {len(g.fit.ramps)} curves, {g.fit.quality}"
        )
        plotting.plot_ramp_fit(g.fit, output(name), title)
        figures.append(Figure(name, f"Ramp fit of group {g.group}: F(t), model, residual"))
    return figures


def ramp_metrics(result: FitFilesResult) -> dict[str, float]:
    """The ramp fits' metrics: how many were fitted, and the first group's (joint) fit."""
    ramps = result.ramps
    if ramps is None:
        return {}
    metrics = {"n_ramps_fitted": float(sum(1 for r in ramps.rows if r.fit is not None))}
    if not ramps.groups:
        return metrics
    fit = ramps.groups[0].fit
    par = fit.parameters
    metrics["ve_E0_kPa"] = fit.E0_kPa
    if fit.relaxation == "power_law":
        return metrics | {"ve_beta": float(par["beta"])}
    metrics["ve_E_inf_kPa"] = float(par["E_inf_kPa"])  # type: ignore[arg-type]
    for i, (e, t) in enumerate(zip(fit.amplitudes_kPa[1:], fit.theta, strict=True), start=1):
        metrics[f"ve_E{i}_kPa"], metrics[f"ve_tau{i}_s"] = e, t
    return metrics


def ramp_section(result: FitFilesResult, inp: FitFilesInputs) -> str:
    """The report's section on the viscoelastic ramp fits."""
    ramps, options = result.ramps, inp.viscoelastic
    assert ramps is not None and options is not None
    groups = "\n".join(
        f"| {g.group} | {len(g.fit.ramps)} | "
        + ", ".join(f"{v:.3g}" for v in sorted(g.speeds_um_per_s))
        + f" | {g.fit.relaxation} | {g.fit.E0_kPa:.4g} | {terms_text(g.fit)} | {g.fit.quality} "
        f"| [F(t)]({ramp_figure_name(g.group)}) |"
        for g in ramps.groups
    )
    offsets = [abs(r.drag_offset_nN) for r in ramps.rows if r.drag_offset_nN is not None]
    creep_too = [g.group for g in ramps.groups if g.group in inp.creep]
    one_speed = [g.group for g in ramps.groups if g.n_speeds == 1]
    tip = ", ".join(f"{k} {v:g}" for k, v in inp.geometry.items()) or "default geometry"
    notes = [
        f"Ting's method with {inp.model} ({tip}), "
        f"nu = {inp.nu:g}; relaxation {options.relaxation}"
        + (f" ({options.terms} terms)" if options.relaxation == "prony" else "")
        + f"; retract {'fitted where present' if options.use_retract else 'not fitted'}; "
        + ("a group's curves fitted together" if options.joint_speeds else "no joint fits")
        + ". Per curve: the `ve_` columns of `fits.csv`.",
        "**Viscous drag**: the approach's baseline is removed from the retract too; a drag on "
        "the cantilever changes sign with the direction of travel and shows as the retract's "
        "offset out of contact (`ve_drag_offset_nN`; about twice the drag force). Largest here: "
        + (f"{max(offsets):.3g} nN." if offsets else "n/a (no retract out of contact).")
        + " An offset comparable to the fit's residual biases the retract and the long times: "
        "fit with use_retract = false, or correct the baseline first (docs/afm.md).",
    ]
    if one_speed:
        notes.append(
            f"Groups with one ramp speed ({', '.join(one_speed)}): times shorter than about 3 "
            "sampling steps or longer than the time in contact are not resolved (flagged)."
        )
    if creep_too:
        notes.append(
            f"Groups with a creep record too ({', '.join(creep_too)}): the creep record gives "
            "the material file; the ramp fit is reported only."
        )
    skipped = [
        g.group
        for g in ramps.groups
        if g.group not in inp.creep and not ramp_material(g, inp.include_poor)
    ]
    if skipped:
        notes.append(
            f"No material from the ramp fit of {', '.join(skipped)} (a power law, or rated "
            "poor without include_poor): elastic from the mean E."
        )
    return (
        "\n\n".join(notes)
        + "\n\n| group | curves | speeds [um/s] | relaxation | E0 [kPa] | terms | rating | figure |"
        "\n|---|---|---|---|---|---|---|---|\n" + (groups or "| none | | | | | | | |")
    )
