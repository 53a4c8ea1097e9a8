"""Figures of the NMSD model (off-screen matplotlib)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import Normalize

from nmsd.lattice import Lattice
from nmsd.pipette import Pipette


def plot_force_curves(
    path: Path,
    displacement_um: np.ndarray,
    measured_uN: np.ndarray,
    curves: dict[str, tuple[np.ndarray, np.ndarray]],
) -> None:
    """Force (uN) against displacement (um): data and model curves ``label: (d_um, f_uN)``."""
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(displacement_um, measured_uN, "ko", label="measured (Table II)")
    for label, (d, force) in curves.items():
        ax.plot(d, force, "-", label=label)
    ax.set_xlabel("pipette displacement (um)")
    ax.set_ylabel("force (uN)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_snapshots(
    path: Path, lattice: Lattice, pipette: Pipette, snapshots: dict[float, np.ndarray]
) -> None:
    """Lattice at several pipette advances (um), links drawn, nodes coloured by their
    displacement magnitude |u| (um) on one colour scale shared by every panel (0 to the
    largest |u| of all panels; 0 to 1 um when nothing has moved yet)."""
    keys = sorted(snapshots)
    moved = {k: np.linalg.norm(snapshots[k] - lattice.nodes, axis=1) for k in keys}
    top = max(float(u.max()) for u in moved.values())
    norm = Normalize(vmin=0.0, vmax=top if top > 0 else 1.0)
    fig, axes = plt.subplots(
        1, len(keys), figsize=(3.2 * len(keys) + 1.0, 3.6), squeeze=False, sharey=True
    )
    for ax, key in zip(axes[0], keys, strict=True):
        x = snapshots[key]
        seg = x[lattice.edges]
        ax.plot(seg[:, :, 0].T, seg[:, :, 1].T, color="0.75", lw=0.5)
        sc = ax.scatter(x[:, 0], x[:, 1], c=moved[key], s=8, cmap="viridis", norm=norm)
        ax.fill(*pipette.outline(key).T, color="tab:red", alpha=0.4)
        ax.set_title(f"pipette advance {key:.3g} µm", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlim(-1.2 * lattice.radius, 1.5 * lattice.radius)
        ax.set_ylim(-1.2 * lattice.radius, 1.2 * lattice.radius)
        ax.set_xlabel("x (µm)")
    axes[0, 0].set_ylabel("y (µm)")
    fig.colorbar(sc, ax=list(axes[0]), shrink=0.8, label="|u| (µm), one scale for all panels")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def plot_spindle(
    path: Path, spindle_path: np.ndarray, paper_final: np.ndarray, pid_position: np.ndarray
) -> None:
    """Spindle path and PID pipette trace in the paper frame (um)."""
    fig, ax = plt.subplots(figsize=(5, 5))
    ax.plot(*spindle_path.T, "b.-", ms=3, label="spindle (model)")
    ax.plot(*spindle_path[0], "bs", label="spindle start")
    ax.plot(*paper_final, "r*", ms=12, label="paper prediction")
    ax.plot(*pid_position.T, "g-", lw=1, label="pipette (PID)")
    ax.set_xlabel("X, into the cell (um)")
    ax.set_ylabel("Y (um)")
    ax.set_aspect("equal")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
