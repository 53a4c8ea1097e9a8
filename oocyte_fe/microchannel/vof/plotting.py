"""Figures of the VOF runs (matplotlib, off-screen); imported by the case kind only."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from oocyte_fe.microchannel.vof.post import CellHistory


def plot_ratio_histories(
    labels: Sequence[str], histories: Sequence[CellHistory], path: Path
) -> Path:
    """Axis ratio b/a against time (ms), one line per run."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, h in zip(labels, histories, strict=True):
        ax.plot(h.time * 1e3, h.ratio, marker=".", label=label)
    ax.set(xlabel="time (ms)", ylabel="axis ratio b/a")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_vof_ratio(
    p_table: np.ndarray,
    experiment: np.ndarray,
    paper: np.ndarray,
    p_vof: np.ndarray,
    vof: np.ndarray,
    p_kv: np.ndarray,
    kelvin_voigt: np.ndarray,
    path: Path,
) -> Path:
    """Axis ratio against pressure (hPa): experiment, paper's VOF, this VOF, reduced model."""
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(p_table, experiment, "ko", label="experiment (Table 4)")
    ax.plot(p_table, paper, "s--", color="0.5", label="paper VOF (Table 4)")
    order = np.argsort(p_vof)
    ax.plot(np.asarray(p_vof)[order], np.asarray(vof)[order], "D-", label="VOF here (OpenFOAM)")
    ax.plot(p_kv, kelvin_voigt, "^:", label="Kelvin-Voigt estimate")
    ax.set(xlabel="driving pressure (hPa)", ylabel="axis ratio b/a")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
