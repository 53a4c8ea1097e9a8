"""Figures of the NMSD-vs-FE cross-check (off-screen matplotlib)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from oocyte_fe.crosscheck.agreement import DisplacementAgreement


def plot_force_overlay(
    path: Path,
    curves: dict[str, tuple[np.ndarray, np.ndarray]],
    measured: tuple[np.ndarray, np.ndarray] | None = None,
    difference: tuple[np.ndarray, np.ndarray] | None = None,
) -> Path:
    """Force (uN) against pipette advance (um): ``label: (advance, force)`` curves, the
    measured points ``(d, f)`` and, in a lower panel, a difference curve ``(d, df)`` in uN."""
    rows = 2 if difference is not None else 1
    fig, axes = plt.subplots(
        rows, 1, figsize=(6.5, 5.5 if rows == 2 else 4), sharex=True, squeeze=False
    )
    ax = axes[0, 0]
    if measured is not None:
        ax.plot(*measured, "ko", ms=4, label="measured (Table II)")
    for label, (d, f) in curves.items():
        ax.plot(d, f, "-", marker=".", ms=3, label=label)
    ax.set_ylabel("force on the cell (uN)")
    ax.legend(fontsize=8)
    if difference is not None:
        axes[1, 0].plot(*difference, "r.-")
        axes[1, 0].axhline(0.0, color="0.5", lw=0.8)
        axes[1, 0].set_ylabel("NMSD - FE (uN)")
    axes[-1, 0].set_xlabel("pipette advance (um)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_displacement_arrows(
    path: Path,
    points_um: np.ndarray,
    agreement: DisplacementAgreement,
    u_fe_um: np.ndarray,
    u_nmsd_um: np.ndarray,
    advances_um: list[float],
    radius_um: float,
    pipettes: dict[float, np.ndarray],
    spindle: int = 0,
) -> Path:
    """Displacement arrows of both models (true scale, um) at the reference points, one panel
    per advance, the pipette outline (k, 2) drawn; a last panel holds the spindle paths."""
    n = len(advances_um)
    fig, axes = plt.subplots(1, n + 1, figsize=(4.2 * (n + 1), 4.4))
    circle = np.linspace(0, 2 * np.pi, 200)
    for ax, a in zip(axes[:-1], advances_um, strict=True):
        k = int(np.argmin(np.abs(agreement.advance_um - a)))
        ax.plot(
            radius_um * np.cos(circle),
            radius_um * np.sin(circle),
            color="0.6",
            lw=0.8,
            label="cell at rest",
        )
        for u, colour, label in ((u_fe_um[k], "tab:blue", "FE"), (u_nmsd_um[k], "tab:red", "NMSD")):
            ax.quiver(
                points_um[:, 0], points_um[:, 1], u[:, 0], u[:, 1], color=colour,
                angles="xy", scale_units="xy", scale=1.0, width=0.004, label=label,
            )  # fmt: skip
        ax.plot(*points_um[spindle], "k*", ms=10, label="spindle")
        outline = pipettes[a]
        ax.fill(outline[:, 0], outline[:, 1], color="0.85", zorder=0)
        ax.set_title(f"advance {a:g} um: max |e| {agreement.error_um[k].max():.1f} um", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlim(-1.15 * radius_um, 1.6 * radius_um)
        ax.set_ylim(-1.15 * radius_um, 1.15 * radius_um)
        ax.set_xlabel("x (um)")
        ax.set_ylabel("y (um)")
    axes[0].legend(fontsize=8, loc="lower left")
    ax = axes[-1]
    ax.plot(agreement.advance_um, np.linalg.norm(agreement.spindle_fe_um, axis=1), "b.-",
            label="|u| spindle, FE")  # fmt: skip
    ax.plot(agreement.advance_um, np.linalg.norm(agreement.spindle_nmsd_um, axis=1), "r.-",
            label="|u| spindle, NMSD")  # fmt: skip
    ax.plot(agreement.advance_um, agreement.spindle_error_um, "k.-", label="spindle error")
    ax.plot(agreement.advance_um, agreement.spindle_tolerance_um, "k--", label="goal")
    ax.plot(agreement.advance_um, agreement.error_um.max(axis=1), "m:", label="max error, grid")
    ax.set_xlabel("pipette advance (um)")
    ax.set_ylabel("displacement, error (um)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
