"""Figures of the tracking benchmark: OTB precision and success plots, a trajectory (Agg).

Matplotlib is imported by the first figure, not with this module: ``oocyte-fe track`` starts
tracking without it (about 0.6 s of start-up).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from oocyte_fe.tracking import metrics

if TYPE_CHECKING:
    from oocyte_fe.tracking.benchmark import BenchmarkResult


def _pyplot():
    """``matplotlib.pyplot`` on the Agg backend, imported on first use."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def pooled(result: BenchmarkResult) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per tracker: centre errors (px) and overlaps of all frames of all sequences."""
    out = {}
    for name in result.trackers:
        chosen = result.select(name)
        out[name] = (
            np.concatenate([s.errors_px for s in chosen]),
            np.concatenate([s.overlaps for s in chosen]),
        )
    return out


def plot_precision_success(
    path: Path, curves: dict[str, tuple[np.ndarray, np.ndarray]], title: str = ""
) -> None:
    """Precision-threshold curve (as seed 000, Fig. 11) and success plot per tracker, from
    its centre errors (px) and overlaps."""
    plt = _pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for name, (e, o) in curves.items():
        p = metrics.precision_curve(e)
        s = metrics.success_curve(o)
        ax1.plot(metrics.PRECISION_THRESHOLDS_PX, p, label=f"{name} [{p[20]:.3f}]")
        ax2.plot(metrics.SUCCESS_THRESHOLDS, s, label=f"{name} [AUC {np.mean(s):.3f}]")
    ax1.axvline(20, color="0.7", lw=0.8, label="20 px threshold")
    ax1.set(xlabel="centre error threshold (px)", ylabel="precision", ylim=(0, 1.02))
    ax2.set(xlabel="overlap threshold (IoU)", ylabel="success rate", ylim=(0, 1.02))
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_trajectory(
    path: Path, centres_um: np.ndarray, truth_um: np.ndarray | None = None, label: str = ""
) -> None:
    """Tracked centre path (um, image axes: y down) and the ground truth if given."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5, 5))
    if truth_um is not None:
        ax.plot(truth_um[:, 0], truth_um[:, 1], color="0.5", lw=2, label="ground truth")
    ax.plot(centres_um[:, 0], centres_um[:, 1], color="C3", lw=1, label=label or "tracked")
    ax.invert_yaxis()
    ax.set(xlabel="x (um)", ylabel="y (um)", aspect="equal")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_loop_distances(path: Path, distances_um: dict[str, list[float]]) -> None:
    """Final tip-to-spindle distance (um) per removal method: each virtual cell as a point,
    the mean as a bar (seed 000, Section III.D)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    names = list(distances_um)
    for i, name in enumerate(names):
        values = np.asarray(distances_um[name], dtype=float)
        ax.bar(i, values.mean(), color="C0", alpha=0.4, label="mean" if i == 0 else "_nolegend_")
        ax.plot(np.full(values.size, i), values, "o", color="C3", ms=4,
                label="virtual cell" if i == 0 else "_nolegend_")  # fmt: skip
    ax.set_xticks(range(len(names)), [n.replace("_", " ") for n in names])
    ax.set(xlabel="removal method", ylabel="tip-to-spindle distance (um)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
