"""Figures for the microchannel cases (matplotlib off-screen, pyvista off-screen)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from oocyte_fe.microchannel.duct_fe import DuctFlow
from oocyte_fe.microchannel.rheology_fit import ViscosityFit

PA_S = 1e3  # kPa s -> Pa s, for axis labels in the paper's units


def _finish(fig: plt.Figure, ax: plt.Axes, file: Path, which: str = "major") -> Path:
    """Grid, legend, layout; save at 130 dpi and close."""
    ax.grid(True, which=which, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(file, dpi=130)
    plt.close(fig)
    return file


def plot_viscosity_fits(
    shear_rate: np.ndarray,
    viscosity: np.ndarray,
    fits: Sequence[ViscosityFit],
    file: Path,
    data_label: str,
) -> Path:
    """Log-log flow curve: data (kPa s stored, shown in Pa s, labelled ``data_label``) and
    every fitted model."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.loglog(shear_rate, viscosity * PA_S, "ko", label=data_label)
    g = np.logspace(np.log10(shear_rate.min()) - 0.5, np.log10(shear_rate.max()) + 0.5, 200)
    for fit in fits:
        ax.loglog(g, fit.rheology.viscosity(g) * PA_S, label=f"{fit.model.name}, R² = {fit.r2:.4f}")
    ax.set_xlabel("shear rate (1/s)")
    ax.set_ylabel("viscosity (Pa s)")
    return _finish(fig, ax, file, which="both")


def plot_profiles(
    curves: Mapping[str, tuple[np.ndarray, np.ndarray]], xlabel: str, file: Path
) -> Path:
    """Velocity profiles, each normalised by its own mean velocity: name -> (x/size, u/U)."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for name, (x, u) in curves.items():
        style = "o" if "FE" in name else "-"
        ax.plot(x, u, style, label=name, ms=4)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("u / U (mean velocity)")
    return _finish(fig, ax, file)


def plot_convergence(studies: Mapping[str, tuple[np.ndarray, np.ndarray]], file: Path) -> Path:
    """Relative flow-rate error against element size: name -> (h / size, |error|)."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for name, (h, err) in studies.items():
        ax.loglog(h, err, "o-", label=name)
    ax.set_xlabel("element size / section size")
    ax.set_ylabel("|Q_FE / Q_exact - 1|")
    return _finish(fig, ax, file, which="both")


def plot_junction_ratio(
    pressure_hpa: np.ndarray,
    experiment: np.ndarray,
    vof: np.ndarray,
    model: np.ndarray,
    fit_pressures_hpa: Sequence[float],
    file: Path,
) -> Path:
    """Axis ratio against driving pressure: experiment, paper's VOF and the reduced model."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(pressure_hpa, experiment, "ks", label="experiment (Table 4)")
    ax.plot(pressure_hpa, vof, "b^--", label="three-phase VOF (Table 4)")
    ax.plot(pressure_hpa, model, "r-o", label="reduced model (Kelvin-Voigt capsule)")
    fitted = np.isin(pressure_hpa, fit_pressures_hpa)
    ax.plot(
        pressure_hpa[fitted],
        model[fitted],
        "o",
        mfc="none",
        mec="k",
        ms=12,
        label="pressures used in the fit",
    )
    ax.set_xlabel("driving pressure (hPa)")
    ax.set_ylabel("axis ratio minor/major")
    return _finish(fig, ax, file)


def plot_duct_velocity(flow: DuctFlow, file: Path, title: str) -> Path:
    """The FE velocity (um/s) on a plane section, warped by its value, rendered off-screen
    (pyvista); the colour bar stands at the right, clear of the drawing."""
    import pyvista as pv

    mesh = flow.mesh
    u = flow.u[flow.basis.nodal_dofs[0]]
    points = np.column_stack([mesh.p[0], mesh.p[1], np.zeros(mesh.p.shape[1])])
    faces = np.column_stack([np.full(mesh.t.shape[1], 3), mesh.t.T]).ravel()
    grid = pv.PolyData(points, faces)
    label = "axial velocity (µm/s)"
    grid[label] = u
    span = max(np.ptp(mesh.p[0]), np.ptp(mesh.p[1]))
    warped = grid.warp_by_scalar(label, factor=0.4 * span / max(u.max(), 1e-300))
    plotter = pv.Plotter(off_screen=True, window_size=(900, 600))
    plotter.set_background("white")
    plotter.add_mesh(
        warped,
        scalars=label,
        cmap="viridis",
        show_edges=True,
        edge_color="gray",
        line_width=0.3,
        scalar_bar_args={
            "title": label,
            "vertical": True,
            "position_x": 0.82,
            "position_y": 0.15,
            "height": 0.65,
            "fmt": "%.3g",
            "color": "black",
            "title_font_size": 14,
            "label_font_size": 12,
        },
    )
    plotter.add_text(title, position="upper_edge", font_size=10, color="black")
    plotter.view_isometric()
    plotter.camera.zoom(0.9)
    plotter.screenshot(str(file))
    plotter.close()
    return file


def plot_rtdc_moduli(rows: Sequence[tuple[float, float, float, float]], file: Path) -> Path:
    """RT-DC's table against the one-way FE: E_table / E against the deformation, one line per
    cell radius. ``rows``: (radius um, E kPa, deformation, E_table kPa)."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for a in sorted({r[0] for r in rows}):
        pts = sorted((d, lut / E) for aa, E, d, lut in rows if aa == a and np.isfinite(lut))
        if pts:
            ax.semilogx(*zip(*pts, strict=True), "o-", label=f"a = {a:g} um")
    ax.axhline(1.0, color="k", lw=0.8, label="E put in")
    ax.set_xlabel("deformation 1 - circularity")
    ax.set_ylabel("E from LE-2D-FEM-19 / E put in")
    return _finish(fig, ax, file, which="both")
