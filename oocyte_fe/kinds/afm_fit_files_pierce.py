"""Pierce-through curves in ``afm_fit_files`` (``pierce``: true, or the groups it names): the
two layers' outputs, beside the one layer of the other groups' plain curves.

Each curve of a pierce group (``result.pierce``) is fitted by :func:`afm.pierce.fit_pierce`
(the ZP up to the force drop, the cytoplasm after it: ``F = F1 + E_cyt shape(x - x1)`` [nN],
E in kPa, x in um); a curve without a drop is a refused row ("no pierce detected").
:func:`afm.fit_files.fit_files` makes each group's material from its moduli (column
``E_kPa``: the ZP's for a pierce group); here a pierce group's cytoplasm statistics (column
``E_cytoplasm_kPa``, mean +- SD over the fits rated good) and elastic material are added,
and its two materials are named by layer: ``material_<group>_zp`` and
``material_<group>_cytoplasm``; a plain group keeps its one ``material_<group>``. A figure
per pierce-through curve shows both segments with their fits (:func:`afm.plotting.plot_fit`).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from afm import plotting
from afm.batch import BatchRow, GroupStats
from afm.curve_plots import curve_title, plot_name
from afm.fit import IndentationFit
from afm.fit_files import SOURCE, FitFilesResult, GroupMaterial
from afm.material_file import MaterialFile

LAYERS = ("ZP", "cytoplasm")
"""The layers of a pierce-through curve, in the order the probe meets them."""
ONE_LAYER = "one layer"
"""The layer column of a plain group (a curve fitted as one layer) in the moduli table."""


def layer_fit(row: BatchRow, layer: str) -> IndentationFit | None:
    """The fit of ``layer`` (``ZP`` or ``cytoplasm``) of a row."""
    return row.fit if layer == "ZP" else row.cytoplasm


def cytoplasm_stats(result: FitFilesResult) -> dict[str, GroupStats]:
    """Mean +- SD of the cytoplasm's E per pierce group (kPa; over the fits rated good, poor
    ones too with ``include_poor``), the pierce groups of ``result.stats``."""
    listed = result.batch.stats(result.include_poor)
    found = {s.group: s for s in listed if s.quantity == "E_cytoplasm_kPa"}
    empty = GroupStats("", "E_cytoplasm_kPa", 0, 0, float("nan"), float("nan"))
    return {g: found.get(g, replace(empty, group=g)) for g in result.stats if g in result.pierce}


def layer_materials(result: FitFilesResult, nu: float, model: str) -> list[GroupMaterial]:
    """Per pierce group, the ZP's material of ``result`` (elastic mean, or the creep
    record's) as ``<group>_zp`` and the cytoplasm's elastic material (its mean E [kPa],
    Poisson ratio ``nu``) as ``<group>_cytoplasm``; a layer with no fit rated good has none.
    A plain group keeps its material of ``result``, named by the group."""
    cytoplasm = cytoplasm_stats(result)
    used = "good or poor" if result.include_poor else "good"
    out = []
    for made in result.materials:
        if made.group not in result.pierce:
            out.append(made)
            continue
        name = f"{made.group}_zp"
        zp = made.material
        if zp is not None:
            zp = replace(zp, name=name, source=f"{zp.source}; ZP of pierce-through curves")
        out.append(replace(made, group=name, material=zp))
        stats, name = cytoplasm[made.group], f"{made.group}_cytoplasm"
        source = (
            f"{SOURCE}: mean of {stats.n} {model} cytoplasm fits of pierce-through curves rated "
            f"{used} ({stats.mean_sd_text} kPa), elastic"
        )
        material = MaterialFile(name, source, stats.mean_kPa, nu) if stats.n else None
        out.append(GroupMaterial(name, material))
    return out


def moduli_rows(result: FitFilesResult) -> str:
    """Rows ``| group | layer | n | n_poor | E [kPa] |`` of the moduli table: both layers of a
    pierce group, the one layer of a plain group (:data:`ONE_LAYER`)."""
    cytoplasm = cytoplasm_stats(result)
    rows = []
    for group, zp in result.stats.items():
        pierced = group in cytoplasm
        layers = (("ZP", zp), ("cytoplasm", cytoplasm[group])) if pierced else ((ONE_LAYER, zp),)
        for layer, s in layers:
            value = f"{s.mean_sd_text} |" if s.n else "- |"
            rows.append(f"| {group} | {layer} | {s.n} | {s.n_poor} | {value}")
    return "\n".join(rows)


def strip_groups(result: FitFilesResult) -> dict[str, list[IndentationFit]]:
    """The fits of each group, for the strip plot of the moduli: a plain group's as
    ``<group>``, a pierce group's by layer as ``<group> ZP`` and ``<group> cytoplasm``."""
    strips = {}
    for g in result.stats:
        rows = [r for r in result.fitted if r.group == g]
        if g not in result.pierce:
            strips[g] = [r.fit for r in rows if r.fit is not None]
            continue
        for layer in LAYERS:
            strips[f"{g} {layer}"] = [f for r in rows if (f := layer_fit(r, layer))]
    return strips


def pierce_plot_name(row: BatchRow) -> str:
    """``<file stem>_pierce.png`` (``_curve<i>`` before it for a force-map curve)."""
    return plot_name(row).removesuffix(".png") + "_pierce.png"


def write_pierce_plots(result: FitFilesResult, folder: Path, which: str) -> set[str]:
    """A figure per fitted pierce-through curve in ``folder`` (``which``: ``all``, ``poor``
    or ``none``, as the curve plots): the force against the tip position (baseline removed)
    with the ZP fit up to the drop and the cytoplasm fit after it, and E(delta) of each;
    the names drawn."""
    drawn = set()
    for row in result.fitted:
        if row.cytoplasm is None or which == "none" or (which == "poor" and row.good):
            continue
        name = pierce_plot_name(row)
        title = f"{curve_title(row)}: ZP and cytoplasm"
        fits = [(layer, layer_fit(row, layer)) for layer in LAYERS]
        plotting.plot_fit(fits, folder / name, title)
        drawn.add(name)
    return drawn


def plot_line(row: BatchRow, plots: set[str]) -> str:
    """A fitted pierce-through row's entry in the report's list of curve plots: both moduli
    and ratings, linking the ZP's curve plot and the two-layer figure (those drawn)."""
    assert row.fit is not None and row.cytoplasm is not None
    name = Path(row.file).name + ("" if row.curve_index is None else f" curve {row.curve_index}")
    zp_plot, both = plot_name(row), pierce_plot_name(row)
    name = f"[{name}](curve_plots/{zp_plot})" if zp_plot in plots else name
    shown = f" ([both layers](curve_plots/{both}))" if both in plots else ""
    return (
        f"* {name}{shown}: ZP E = {row.fit.E_kPa:.4g} kPa, {row.fit.rating}; cytoplasm E = "
        f"{row.cytoplasm.E_kPa:.4g} kPa, {row.cytoplasm.rating}"
    )


def no_pierce(result: FitFilesResult) -> int:
    """Curves refused because no pierce (force drop) was detected (only the curves of the
    pierce groups are searched for one)."""
    return sum("no pierce detected" in r.error for r in result.batch.failures)
