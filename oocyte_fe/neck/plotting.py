"""Figures of the neck passage: histories, force balance, wall contact pressure, periphery,
and off-screen sections (pyvista) in the oocyte's frame."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from oocyte_fe.neck.passage import PassageResult
from oocyte_fe.plotting import plot_section


def plot_history(result: PassageResult, path: Path, reference_kPa: float) -> Path:
    """Advance and required suction against time; the axial force balance."""
    t = result.series("time_s")
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].plot(t, result.series("centroid_advance_um"), label="centroid")
    ax[0].plot(t, result.series("front_pole_um"), "--", label="front pole")
    ax[0].set(xlabel="time (s)", ylabel="advance (um)", title="aspiration advance")
    ax[0].legend()
    ax[1].plot(
        result.series("centroid_advance_um"),
        1e3 * result.series("suction_kPa"),
        label="quasi-static passage",
    )
    ax[1].axhline(1e3 * reference_kPa, color="k", ls=":", label=f"seed: {1e3 * reference_kPa:g} Pa")
    ax[1].set(xlabel="centroid advance (um)", ylabel="suction (Pa)", title="suction needed")
    ax[1].legend()
    w = result.series("centroid_advance_um")
    for key, label in [
        ("suction_force_nN", "suction"),
        ("wall_normal_nN", "wall: normal"),
        ("wall_friction_nN", "wall: friction"),
        ("push_force_nN", "rear cap push"),
    ]:
        ax[2].plot(w, result.series(key), label=label)
    ax[2].set(xlabel="centroid advance (um)", ylabel="axial force (nN)", title="force balance")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_wall_pressure(result: PassageResult, path: Path, frames: list[int]) -> Path:
    """Contact pressure against the current axial position at chosen frames, wall radius."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for k in frames:
        z, lam = result.wall_profiles[k]
        order = np.argsort(z)
        on = lam[order] > 0
        ax.plot(
            z[order][on], 1e3 * lam[order][on], ".", ms=3, label=f"t = {result.frames[k].t:.2f} s"
        )
    ax.axvline(result.pipette.z_neck_um, color="k", ls=":", label="neck start")
    ax.axvline(
        result.pipette.z_neck_um - result.pipette.taper_length_um,
        color="grey",
        ls=":",
        label="taper start",
    )
    ax.set(xlabel="Z along the pipette (um)", ylabel="contact pressure (Pa)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_periphery(
    polar_deg: np.ndarray, rows: dict[str, np.ndarray], path: Path, band: tuple[float, float]
) -> Path:
    """Deformation at the five material points for several runs, with the paper's range."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for label, values in rows.items():
        ax.plot(polar_deg, values, "o-", label=label)
    ax.axhspan(*band, color="0.85", label="seed 001: 8-18 um")
    ax.set(xlabel="polar angle from the front pole (deg)", ylabel="deformation (um)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_state(result: PassageResult, k: int, path: Path, title: str) -> Path:
    """Section at frame ``k`` in the oocyte's frame (centroid advance removed, pipette moved
    back by it), coloured by the displacement magnitude relative to the centroid."""
    body = result.problem.body
    frame = result.frames[k]
    w = result.history["centroid_advance_um"][k]
    u = body.vertex_displacement(frame.x) - np.array([[0.0], [w]])
    wall = np.asarray(result.pipette.profile()) - np.array([0.0, w])
    return plot_section(path, body.mesh, u, mirror=True, obstacles=[wall], title=title)
