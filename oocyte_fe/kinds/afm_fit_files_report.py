"""Report of the case kind ``afm_fit_files``: ``fits.csv``, figures, material files, Markdown.

The kind fits (:func:`afm.fit_files.fit_files`) and hands the result here; this module only
writes it: the table (:func:`afm.batch.write_batch_table`), the figures (through
:mod:`afm.curve_plots` and :mod:`afm.plotting`), the material files of each group (TOML, ANSYS,
FEBio) and the report sections. Moduli in kPa, lengths in um.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

from afm import plotting
from afm.batch import COLUMNS, BatchRow, write_batch_table
from afm.curve_plots import plot_curves, plot_name
from afm.fe_export import ansys_prony_block, febio_material
from afm.fit_files import FitFilesResult, GroupMaterial, tip_text
from afm.material_file import write_material
from afm.ramp_files import RAMP_COLUMNS
from oocyte_fe.kinds.afm_fit_files_args import pierce_setting
from oocyte_fe.kinds.afm_fit_files_correction import CORRECTION_COLUMNS, correction_text
from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs
from oocyte_fe.kinds.afm_fit_files_pierce import (
    ONE_LAYER,
    layer_materials,
    moduli_rows,
    no_pierce,
    plot_line,
    strip_groups,
    write_pierce_plots,
)
from oocyte_fe.kinds.afm_fit_files_ramps import (
    add_ramp_columns,
    file_stem,
    group_figures,
    ramp_figure_name,
    ramp_figures,
    ramp_section,
)
from oocyte_fe.runner.registry import Figure

Output = Callable[[str], Path]
"""``ctx.output``: the path of a result file of the case."""

ANALYSES = {
    "default": "afm.fit.fit_indentation: baseline line (offset and tilt) fitted before contact "
    "and removed; every point of the fit window weighted equally; contact point free",
    "nanite": "afm.nanite_pipeline.fit_nanite_default, nanite's default: constant offset, "
    "free baseline in the fit, residuals within 1 um of contact weighted down",
}
"""What each ``analysis`` does, for the report and ``fits.csv``."""

WHY_NOT_NANITE = (
    "The default analysis weights every point equally, where nanite weights the residuals "
    "within 1 um of the contact point down (by |x - x0| / 1 um): nanite's fit can then settle "
    "on a contact point up the rise, where its model misses the start of contact (up to 9x "
    "higher E on some instrument files; docs/afm.md, 'The default analysis against nanite'). "
    'Set analysis = "nanite" to reproduce a nanite/PyJibe analysis.'
)


PIERCE_TEXT = (
    " Pierce-through curves ({setting}): the ZP fitted up to the force drop (its fit range "
    "the one given), the cytoplasm after it (afm.pierce.fit_pierce: F = F1 + E_cyt shape(x - "
    "x1)); each layer rated on its own, a curve rated good when both are; a curve without a "
    "drop is refused (no pierce detected).{others}"
)
"""The moduli section's note on pierce-through curves (``setting``: ``pierce = ...`` as
written; ``others``: what the other groups are)."""


def fit_range_text(inp: FitFilesInputs) -> str:
    """The fit range of ``inp`` in words (``whole approach`` for nanite's analysis)."""
    if inp.analysis == "nanite":
        return "whole approach"
    parts = []
    if inp.max_indentation_um is not None:
        parts.append(f"to {inp.max_indentation_um:g} um past contact")
    if inp.max_force_fraction is not None:
        parts.append(f"to {inp.max_force_fraction:g} of the peak force")
    if len(parts) == 2:  # afm.fit.fit_window: the window ends where the first of them ends
        return f"{parts[0]} or {parts[1]}, whichever ends first"
    return "".join(parts) or "whole approach"


def _reason(row: BatchRow) -> str:
    """A refused row's error without the file name it starts with (the list names it)."""
    return re.sub(rf"^{re.escape(row.file)}( \(curve \d+\))?: ", "", row.error)


def write_fits(
    result: FitFilesResult, inp: FitFilesInputs, output: Output, case_dir: Path, workers: int
) -> tuple[list[Figure], set[str]]:
    """Curve plots (``curve_plots/``, as ``inp.curve_plots`` asks), ``fits.csv`` linking them,
    the strip plot of the moduli per group and a modulus map per force-map file; the figures
    for the report and the names of the curve plots drawn."""
    batch = result.batch
    plot_dir = output("curve_plots/.keep").parent
    plots = {p.name for p in plot_curves(batch, plot_dir, workers=workers, which=inp.curve_plots)}
    plots |= write_pierce_plots(result, plot_dir, inp.curve_plots)
    links = {
        i: f"curve_plots/{plot_name(r)}" for i, r in enumerate(batch.rows) if plot_name(r) in plots
    }
    write_batch_table(batch, output("fits.csv"), case_dir, links, inp.analysis, fit_range_text(inp))
    figures = []
    if result.ramps is not None:
        links = ramp_figures(result.ramps, output, inp.curve_plots)
        add_ramp_columns(output("fits.csv"), result.ramps, links)
        figures.extend(group_figures(result.ramps, output))
    if result.fitted:
        plotting.plot_strip(strip_groups(result), output("moduli.png"), inp.include_poor)
        figures.append(Figure("moduli.png", "Fitted Young's moduli per group (log axis)"))
    for file in sorted({r.file for r in batch.rows if r.map_position_um is not None}):
        name = f"modulus_map_{Path(file).stem}.png"
        plotting.plot_modulus_map(batch, file, output(name))
        figures.append(Figure(name, f"Modulus map of {Path(file).name}"))
    return figures, plots


def _pierce_text(inp: FitFilesInputs) -> str:
    """:data:`PIERCE_TEXT` for ``inp.pierce``: a list of groups also says the others' curves
    are plain (one layer)."""
    others = "" if inp.pierce is True else f" The other groups' curves are plain: {ONE_LAYER} each."
    return PIERCE_TEXT.format(setting=pierce_setting(inp), others=others)


def _material_row(made: GroupMaterial, output: Output) -> str:
    """Write the material files of one group (and its creep figure); its row of the table."""
    material, fit = made.material, made.creep
    if material is None:
        return f"| {made.group} | - | - | - | - | none: no fit rated good |"
    how, e_inf = "elastic (mean E)", "-"
    if made.ramp is not None:
        ramp = made.ramp.fit
        figure = ramp_figure_name(made.group)
        how = (
            f"ramp fit ({ramp.relaxation}, Ting) of {len(ramp.ramps)} curves: {ramp.quality}; "
            f"[F(t)]({figure})"
        )
        e_inf = f"{ramp.amplitudes_kPa[0]:.4g}"
    if fit is not None:
        figure = f"creep_{file_stem(made.group)}.png"
        plotting.plot_creep(fit, output(figure))
        how = (
            f"creep Prony fit, {fit.model} ({tip_text(fit)}): {fit.quality}; [J(t), G(t)]({figure})"
        )
        e_inf = f"{fit.E_inf_kPa:.4g}"
    stem = f"material_{file_stem(made.group)}"
    write_material(material, output(f"{stem}.toml"))
    output(f"{stem}_ansys.inp").write_text(ansys_prony_block(material))
    output(f"{stem}_febio.xml").write_text(febio_material(material))
    return (
        f"| {made.group} | {material.E_kPa:.4g} | {e_inf} | {material.nu:g} | {len(material.g)} "
        f"| {how} |"
    )


def write_materials(result: FitFilesResult, inp: FitFilesInputs, output: Output) -> list[str]:
    """``material_<group>.toml``, ``_ansys.inp`` and ``_febio.xml`` of every group with a
    material (and the creep figure of a group with a creep record); for a pierce group one
    per layer, ``<group>_zp`` and ``<group>_cytoplasm`` (:func:`layer_materials`); the rows
    of the report's material table."""
    return [_material_row(m, output) for m in layer_materials(result, inp.nu, inp.model)]


def sections(
    result: FitFilesResult,
    inp: FitFilesInputs,
    case_dir: Path,
    n_files: int,
    plots: set[str],
    material_rows: list[str],
) -> list[tuple[str, str]]:
    """The report's sections: the summary, moduli per group, the analysis, the refused curves,
    the material files, the columns of ``fits.csv`` and links to the curve plots."""
    rows = result.batch.rows
    used = "fits rated good or poor" if inp.include_poor else "fits rated good"
    if result.correction is not None:
        used += f", moduli corrected ({result.correction.name})"
    poor_left_out = "are left out (include_poor = true keeps them)"
    table = (
        "| group | layer | n | n_poor | E [kPa] |\n|---|---|---|---|---|\n" + moduli_rows(result)
        if result.pierce
        else "| group | n | n_poor | E [kPa] |\n|---|---|---|---|\n"
        + "\n".join(
            f"| {s.group} | {s.n} | {s.n_poor} | " + (f"{s.mean_sd_text} |" if s.n else "- |")
            for s in result.stats.values()
        )
    )
    failed = "\n".join(
        f"* `{Path(r.file).relative_to(case_dir).as_posix()}`"
        + ("" if r.curve_index is None else f" curve {r.curve_index}")
        + (f" ([plot](curve_plots/{plot_name(r)}))" if plot_name(r) in plots else "")
        + f": {_reason(r)}"
        for r in result.batch.failures
    )
    plot_links = "\n".join(
        plot_line(r, plots)
        if r.cytoplasm is not None
        else f"* [{Path(r.file).name}"
        + ("" if r.curve_index is None else f" curve {r.curve_index}")
        + f"](curve_plots/{plot_name(r)}): E = {r.fit.E_kPa:.4g} kPa, {r.fit.rating}"
        for r in result.fitted
        if plot_name(r) in plots
    )
    pierced = f" {no_pierce(result)} without a detectable pierce." if inp.pierce else ""
    contact = f", contact by {inp.contact_method}" if inp.analysis == "default" else ""
    analysis = f"**{inp.analysis}**: {ANALYSES[inp.analysis]}."
    if inp.analysis == "default":
        analysis += " " + WHY_NOT_NANITE
    return [
        ("Result", f"{result.summary} ({len(rows)} curves in {n_files} files)." + pierced),
        (
            "Moduli per group (mean +- SD, kPa)",
            f"Over the {used} ({inp.model}, nu = {inp.nu:g}, {inp.analysis} analysis"
            f"{contact}; fit range: {fit_range_text(inp)}); n_poor fits rated poor "
            f"{'are included' if inp.include_poor else poor_left_out}"
            "; SD n/a for n = 1. Every row is in `fits.csv`."
            + (_pierce_text(inp) if inp.pierce else "")
            + "\n\n"
            + table,
        ),
        ("Correction for the sample's shape", correction_text(result)),
        ("Analysis", analysis),
        ("Curves refused (skipped)", failed or "none"),
        (
            "Material files",
            "| group | E0 [kPa] | E_inf [kPa] | nu | Prony terms | from |\n"
            "|---|---|---|---|---|---|\n"
            + "\n".join(material_rows)
            + "\n\nEach as `material_<group>.toml` (read by the FE cases), "
            "`material_<group>_ansys.inp` and `material_<group>_febio.xml`; a creep fit's "
            "rating (and any Prony term the record does not determine) is written into their "
            "source line.",
        ),
        (
            "Columns of fits.csv",
            "\n".join(
                f"* `{k}`: {text}"
                for k, text in (
                    COLUMNS
                    | (CORRECTION_COLUMNS if result.correction else {})
                    | (RAMP_COLUMNS if result.ramps else {})
                ).items()
            ),
        ),
        ("Curve plots", plot_links or "none"),
    ] + ([("Viscoelastic ramp fits", ramp_section(result, inp))] if result.ramps else [])
