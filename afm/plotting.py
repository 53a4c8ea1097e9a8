"""Figures of fits (off-screen, matplotlib Agg): curve with fit, E(delta), moduli per group
(strip plot, histogram), modulus maps, J(t) and G(t), ramps F(t) with Ting's fit."""

from __future__ import annotations

import textwrap
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from afm.batch import BatchResult
from afm.creep import CreepFit
from afm.curve_plots import x_label
from afm.fit import IndentationFit
from afm.viscoelastic import RampFit


def _save(fig: plt.Figure, path: str | Path, tight: bool = True) -> Path:
    """Save at 120 dpi and close; ``tight``: fit the layout to the labels first (a quarter of
    a small figure's cost; a figure drawn many times sets its margins once instead)."""
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


FIT_MARGINS = {"left": 0.065, "right": 0.98, "bottom": 0.145, "top": 0.91, "wspace": 0.2}
"""Margins of :func:`plot_fit`'s two panels (10 x 4 in): ``tight_layout``'s for a curve with
four-digit force ticks, a little wider on the left."""


def plot_fit(fits: Sequence[tuple[str, IndentationFit]], path: str | Path, title: str = "") -> Path:
    """Force against tip position with each fitted model, and E(delta) pointwise beside it."""
    fig, (ax_f, ax_e) = plt.subplots(1, 2, figsize=(10, 4))
    for i, (label, fit) in enumerate(fits):
        data_c, fit_c = f"C{2 * i}", f"C{2 * i + 1}"
        ax_f.plot(fit.tip_position_um, fit.force_nN, ".", ms=2, c=data_c, label=f"{label} data")
        ax_f.plot(
            fit.tip_position_um,
            fit.fitted_force_nN,
            "-",
            c=fit_c,
            lw=1.5,
            label=f"{label}: E = {fit.E_kPa:.3g} kPa",
        )
        ax_f.axvline(
            fit.contact_point_um,
            ls=":",
            c=fit_c,
            label=f"{label} contact x0 = {fit.contact_point_um:.4g} um",
        )
        delta, modulus = fit.pointwise_modulus(0.1 * float(fit.indentation_um.max()))
        ax_e.plot(delta, modulus, ".", ms=2, c=data_c, label=f"{label} E(delta)")
        ax_e.axhline(fit.E_kPa, ls="--", lw=1, c=fit_c, label=f"{label} fitted E")
    ax_f.set(xlabel=x_label(fits[0][1].height_channel), ylabel="force [nN]", title=title)
    ax_f.legend(fontsize=7)
    ax_e.set(xlabel="indentation delta [um]", ylabel="E(delta) = F / shape(delta) [kPa]")
    ax_e.set_title("pointwise modulus (flat where the model holds)", fontsize=9)
    ax_e.legend(fontsize=7)
    fig.subplots_adjust(**FIT_MARGINS)  # one per curve of a batch: fixed, not tight_layout
    return _save(fig, path, tight=False)


def plot_batch(result: BatchResult, folder: str | Path) -> list[Path]:
    """One figure per fitted curve of a batch (:func:`plot_fit`), ``<curve name>.png`` in
    ``folder`` (``<file>_curve<i>.png`` for force-map curves); curves that failed have no
    figure (their error is in the batch table)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for row in result.rows:
        if row.error or row.fit is None:
            continue
        fits = [("ZP", row.fit)] + ([("cytoplasm", row.cytoplasm)] if row.cytoplasm else [])
        name = Path(row.file).stem
        title = Path(row.file).name
        if row.curve_index is not None:
            name += f"_curve{row.curve_index:04d}"
            title += f" curve {row.curve_index}"
        paths.append(plot_fit(fits, folder / f"{name}.png", title=title))
    return paths


def grid_coordinates(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(grid lines, index of each value): positions of a map cluster where the gaps between
    sorted values exceed a quarter of the largest gap (the spacing; smaller gaps are the
    stage's jitter around a grid line); each grid line is its cluster's mean."""
    order = np.argsort(values, kind="stable")
    gaps = np.diff(values[order])
    step = gaps > 0.25 * gaps.max() if gaps.size and gaps.max() > 0 else np.zeros(gaps.size, bool)
    cluster = np.concatenate(([0], np.cumsum(step)))
    index = np.empty(values.size, dtype=int)
    index[order] = cluster
    lines = np.array([values[index == c].mean() for c in range(int(cluster[-1]) + 1)])
    return lines, index


def _edges(centres: np.ndarray) -> np.ndarray:
    """Pixel edges around sorted grid coordinates (half the spacing beyond the ends)."""
    if centres.size == 1:
        return centres[0] + np.array([-0.5, 0.5])
    mid = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate(([2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]))


def _plain_log_ticks(axis: matplotlib.axis.Axis, low: float, high: float) -> None:
    """Log-axis ticks labelled as plain numbers (0.5, 2, 100): at every integer multiple of
    the power of ten within one decade, at 1, 2, 5 per decade over at most 3 decades, at the
    powers of ten beyond."""
    if high <= 10.0 * low:
        subs: tuple[float, ...] = tuple(float(m) for m in range(1, 10))
    else:
        subs = (1.0, 2.0, 5.0) if high <= 1e3 * low else (1.0,)
    axis.set_major_locator(matplotlib.ticker.LogLocator(subs=subs))
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def _log_colorbar(fig: plt.Figure, mappable, ax: plt.Axes, label: str) -> None:
    """A colour bar with plain-number ticks (:func:`_plain_log_ticks`)."""
    bar = fig.colorbar(mappable, ax=ax, label=label)
    _plain_log_ticks(bar.ax.yaxis, mappable.norm.vmin, mappable.norm.vmax)


def modulus_map_figure(result: BatchResult, file: str | Path) -> plt.Figure:
    """Young's modulus of one force-map file on the map's own grid (log colour scale, kPa).

    Each curve fills its grid pixel (:func:`grid_coordinates`; pixel edges halfway between
    the grid lines, um);
    curves rated poor carry a black ring, refused curves are grey pixels.
    """
    rows = result.map_rows(file)
    if not rows:
        raise ValueError(f"{file}: no force-map curves in this batch")
    xy = np.array([r.map_position_um for r in rows])
    xs, ix = grid_coordinates(xy[:, 0])
    ys, iy = grid_coordinates(xy[:, 1])
    grid = np.full((ys.size, xs.size), np.nan)
    for r, i, j in zip(rows, ix, iy, strict=True):
        if r.fit is not None and not r.error and r.fit.E_kPa > 0:
            grid[j, i] = r.fit.E_kPa
    fig, ax = plt.subplots(figsize=(6.2, 5.2))
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="lightgrey")
    finite = grid[np.isfinite(grid)]
    norm = matplotlib.colors.LogNorm(finite.min(), finite.max()) if finite.size else None
    mesh = ax.pcolormesh(_edges(xs), _edges(ys), np.ma.masked_invalid(grid), cmap=cmap, norm=norm)
    if finite.size:
        _log_colorbar(fig, mesh, ax, "E [kPa]")
    poor = np.array([r.fit is not None and not r.error and not r.good for r in rows])
    if poor.any():
        ax.scatter(
            xy[poor, 0], xy[poor, 1], s=40, facecolors="none", edgecolors="k", label="rated poor"
        )
    refused = np.array([r.fit is None or bool(r.error) for r in rows])
    if refused.any():
        ax.scatter([], [], marker="s", c="lightgrey", label="refused")
    if poor.any() or refused.any():
        ax.legend(fontsize=7, loc="upper right", framealpha=0.8)
    ax.set(xlabel="x [um]", ylabel="y [um]")
    ax.set_title(
        "\n".join(textwrap.wrap(f"{Path(file).name}: modulus map ({len(rows)} curves)", 60)),
        fontsize=9,
    )
    ax.set_aspect("equal")
    fig.tight_layout()
    return fig


def plot_modulus_map(result: BatchResult, file: str | Path, path: str | Path) -> Path:
    """:func:`modulus_map_figure` written to ``path``."""
    return _save(modulus_map_figure(result, file), path)


def strip_figure(
    fits: Mapping[str, Sequence[IndentationFit]], include_poor: bool = False
) -> plt.Figure:
    """Moduli per group as a strip plot on a log axis: one column of points per group
    (jittered sideways), fits rated poor as open circles, and the group's mean +- SD over
    the fits that enter statistics (good ones; poor too with ``include_poor``) as a bar."""
    fig, ax = plt.subplots(figsize=(3.2 + 1.2 * len(fits), 4.2))
    rng = np.random.default_rng(0)
    for i, group_fits in enumerate(fits.values()):
        moduli = np.array([f.E_kPa for f in group_fits])
        good = np.array([f.quality == "good" for f in group_fits])
        jitter = i + rng.uniform(-0.2, 0.2, moduli.size)
        ax.scatter(jitter[good], moduli[good], s=12, c=f"C{i}", label=None)
        ax.scatter(
            jitter[~good], moduli[~good], s=16, facecolors="none", edgecolors=f"C{i}", label=None
        )
        used = moduli[good | include_poor]
        used = used[used > 0]
        if used.size:
            mean = float(used.mean())
            ax.hlines(mean, i - 0.3, i + 0.3, colors="k", lw=2)
            if used.size > 1:
                sd = float(used.std(ddof=1))
                ax.vlines(i + 0.32, max(mean - sd, used.min() / 2), mean + sd, colors="k", lw=1)
    ax.scatter([], [], s=12, c="grey", label="rated good")
    ax.scatter([], [], s=16, facecolors="none", edgecolors="grey", label="rated poor")
    ax.hlines([], 0, 0, colors="k", lw=2, label="mean (+- SD)")
    ax.set_yscale("log")
    positive = [f.E_kPa for v in fits.values() for f in v if f.E_kPa > 0]
    if positive:
        _plain_log_ticks(ax.yaxis, min(positive), max(positive))
    labels = [
        f"{g}\n({sum(f.quality == 'good' for f in v)} of {len(v)} good)" for g, v in fits.items()
    ]
    ax.set_xticks(range(len(fits)), labels)
    ax.set_xlim(-0.6, len(fits) - 0.4)
    ax.set(xlabel="group", ylabel="Young's modulus E [kPa]")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))  # beside the points
    fig.tight_layout()
    return fig


def plot_strip(
    fits: Mapping[str, Sequence[IndentationFit]], path: str | Path, include_poor: bool = False
) -> Path:
    """:func:`strip_figure` written to ``path``."""
    return _save(strip_figure(fits, include_poor), path)


def plot_histogram(
    values: Mapping[str, np.ndarray],
    path: str | Path,
    references: Mapping[str, tuple[float, float]] | None = None,
) -> Path:
    """Histogram of moduli per label; ``references`` (mean, SD) drawn as lines and bands."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, (label, vals) in enumerate(values.items()):
        color = f"C{i}"
        ax.hist(vals, bins=12, alpha=0.5, color=color, label=f"{label} (n = {len(vals)})")
        if references and label in references:
            mean, sd = references[label]
            ax.axvline(mean, color=color, ls="--", label=f"{label} paper {mean:g} +- {sd:g}")
            ax.axvspan(mean - sd, mean + sd, color=color, alpha=0.1)
    ax.set(xlabel="Young's modulus [kPa]", ylabel="curves")
    ax.legend(fontsize=7)
    return _save(fig, path)


MARKERS = 3000
"""Most data points a log-time plot draws (a 1e6-sample record took 2 s to draw)."""


def _log_spaced_rows(t: np.ndarray, most: int) -> np.ndarray:
    """Row indices of ``t`` (ascending, t[0] >= 0) at most ``most`` of them, evenly spread in
    log time (all rows when there are fewer)."""
    if t.size <= most:
        return np.arange(t.size)
    targets = np.logspace(np.log10(max(t[1], 1e-12)), np.log10(t[-1]), most - 1)
    return np.unique(np.concatenate([[0], np.searchsorted(t, targets).clip(0, t.size - 1)]))


def plot_creep(
    fit: CreepFit, path: str | Path, truth: Callable[[np.ndarray], np.ndarray] | None = None
) -> Path:
    """J(t) data and Prony fit; G(t) from the exact conversion against 1/J(t) (and ``truth``)."""
    t = fit.time_s
    tt = np.logspace(np.log10(max(t[1], 1e-4)), np.log10(t[-1]), 200)
    fig, (ax_j, ax_g) = plt.subplots(1, 2, figsize=(10, 4))
    shown = _log_spaced_rows(t, MARKERS)
    ax_j.plot(
        t[shown],
        fit.compliance_per_kPa[shown],
        ".",
        ms=2,
        alpha=0.4,
        label="Lee-Radok J(t) from data",
    )
    ax_j.plot(tt, fit.creep(tt), "-", label=f"creep Prony ({len(fit.creep.lambda_s)} terms)")
    ax_j.set(xscale="log", xlabel="t [s]", ylabel="J(t) [1/kPa]", title="shear creep compliance")
    ax_j.legend(fontsize=7)
    ax_g.plot(tt, fit.relaxation(tt), "-", label="G(t), exact conversion")
    ax_g.plot(tt, 1.0 / fit.creep(tt), "--", label="1/J(t) (what pointwise E(t) gives)")
    if truth is not None:
        ax_g.plot(tt, truth(tt), ":", c="k", label="G(t) used to make the data")
    ax_g.set(xscale="log", xlabel="t [s]", ylabel="G(t) [kPa]", title="shear relaxation modulus")
    ax_g.legend(fontsize=7)
    return _save(fig, path)


HOLD_SHOWN = 0.05
"""A hold at the farthest travel is shaded in a ramp plot when it lasts this fraction of it."""


def plot_ramp_fit(fit: RampFit, path: str | Path, title: str = "") -> Path:
    """Each ramp's force F(t) against the fitted model (Ting's method), residual below; one
    column per ramp (speed); a hold at the farthest travel shaded, the turn from approach to
    retract marked where the travel reverses."""
    n = len(fit.ramps)
    fig, axes = plt.subplots(
        2, n, figsize=(5 * n, 5), squeeze=False, sharex="col", height_ratios=(3, 1)
    )
    for i, (ramp, model) in enumerate(zip(fit.ramps, fit.fitted_force_nN, strict=True)):
        ax_f, ax_r = axes[0, i], axes[1, i]
        t = ramp.time_s
        ax_f.plot(t, ramp.force_nN, ".", ms=3, c="C0", label="data (baseline removed)")
        ax_f.plot(t, model, "-", c="C1", lw=1.5, label=f"{fit.relaxation} (Ting)")
        hold, turn = ramp.hold_start, ramp.turn
        if t[turn] - t[hold] > HOLD_SHOWN * (t[-1] - t[0]):
            ax_f.axvspan(t[hold], t[turn], color="0.92", label="hold (dwell) at farthest travel")
        if turn < t.size - 1:
            ax_f.axvline(t[turn], ls=":", c="0.5", lw=1, label="turn: approach | retract")
            ax_r.axvline(t[turn], ls=":", c="0.5", lw=1)
        ax_f.set(ylabel="force [nN]")
        ax_f.set_title(_wrap_title(Path(ramp.source).name), fontsize=9)
        ax_f.legend(fontsize=7)
        ax_r.plot(t, ramp.force_nN - model, ".", ms=2, c="C3")
        ax_r.axhline(0.0, c="0.5", lw=0.8)
        ax_r.set(xlabel="t [s]", ylabel="residual [nN]")
    if title:
        fig.suptitle(_wrap_title(title), fontsize=10)
    return _save(fig, path)


def _wrap_title(text: str) -> str:
    return "\n".join(textwrap.wrap(text, 90)[:3])
