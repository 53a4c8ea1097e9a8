"""Sweep figures: metric histograms, metric-against-parameter scatter, sensitivity bars."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Patch

from oocyte_fe.sweep.statistics import Sensitivity, Summary


def _grid(n: int, cols: int = 3) -> tuple[int, int]:
    cols = min(cols, n)
    return math.ceil(n / cols), cols


def plot_histograms(
    path: Path, metrics: dict[str, np.ndarray], summaries: dict[str, Summary]
) -> None:
    """One histogram per metric with the mean and the 5-95 % band."""
    rows, cols = _grid(len(metrics))
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3 * rows), squeeze=False)
    for ax, (name, y) in zip(axes.flat, metrics.items(), strict=False):
        s = summaries[name]
        y = y[np.isfinite(y)]
        ax.hist(y, bins=max(5, min(30, len(y) // 3)), color="0.6", edgecolor="0.3")
        if s.n:
            ax.axvline(s.mean, color="C3", label=f"mean {s.mean:.4g}")
            ax.axvspan(s.p05, s.p95, color="C0", alpha=0.15, label="5-95 %")
            ax.legend(fontsize=7)
        ax.set_xlabel(name, fontsize=8)
        ax.set_ylabel("samples", fontsize=8)
    for ax in list(axes.flat)[len(metrics) :]:
        ax.set_visible(False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_scatter(path: Path, params: dict[str, np.ndarray], metrics: dict[str, np.ndarray]) -> None:
    """Each metric (rows) against each parameter (columns), one dot per finished sample;
    a column shares its parameter axis, a row its metric axis (labelled at the edges)."""
    rows, cols = len(metrics), len(params)
    fig, axes = plt.subplots(
        rows,
        cols,
        figsize=(3.2 * cols + 0.5, 2.6 * rows + 0.3),
        squeeze=False,
        sharex="col",
        sharey="row",
    )
    for i, (mname, y) in enumerate(metrics.items()):
        for j, (pname, x) in enumerate(params.items()):
            ax = axes[i, j]
            ax.plot(x, y, "o", ms=3, alpha=0.7)
            if i == rows - 1:
                ax.set_xlabel(pname, fontsize=8)
            if j == 0:
                ax.set_ylabel(mname, fontsize=8)
            ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sensitivity(path: Path, indices: dict[str, Sensitivity], names: list[str]) -> None:
    """Grouped bars: for each metric, the index of every parameter with its 95 % interval;
    an index whose interval reaches zero is drawn hatched and pale."""
    metrics = list(indices)
    width = 0.8 / len(names)
    fig, ax = plt.subplots(figsize=(max(5.0, 1.2 * len(metrics) * len(names) ** 0.5), 3.6))
    base = np.arange(len(metrics))
    for j, pname in enumerate(names):
        val = [indices[m].index[pname] for m in metrics]
        err = [indices[m].conf[pname] for m in metrics]
        err_arg = None if np.all(np.isnan(err)) else np.nan_to_num(err)
        bars = ax.bar(base + j * width, val, width, yerr=err_arg, capsize=2, color=f"C{j}")
        for bar, m in zip(bars, metrics, strict=True):
            if indices[m].spans_zero(pname):
                bar.set_hatch("//")
                bar.set_alpha(0.45)
    ax.set_xticks(base + 0.4 - width / 2, metrics, rotation=30, ha="right", fontsize=7)
    method = next(iter(indices.values())).method
    ax.set_ylabel("S1 (first order)" if method == "rbd_fast" else f"{method} index")
    ax.axhline(0, color="0.3", lw=0.5, label="_nolegend_")
    ax.set_xlabel("metric (hatched: 95 % interval reaches zero)", fontsize=8)
    ax.legend(handles=[Patch(color=f"C{j}", label=n) for j, n in enumerate(names)], fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
