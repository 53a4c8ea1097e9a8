"""Figures of fits (off-screen, matplotlib Agg): curve with fit, E(delta), histogram, J(t), G(t)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from afm.batch import BatchResult
from afm.creep import CreepFit
from afm.fit import IndentationFit


def _save(fig: plt.Figure, path: str | Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


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
        ax_f.axvline(fit.contact_point_um, ls=":", c="grey")
        delta, modulus = fit.pointwise_modulus(0.1 * float(fit.indentation_um.max()))
        ax_e.plot(delta, modulus, ".", ms=2, c=data_c, label=label)
        ax_e.axhline(fit.E_kPa, ls="--", lw=1, c=fit_c)
    ax_f.set(xlabel="tip position x = piezo - F/k [um]", ylabel="force [nN]", title=title)
    ax_f.legend(fontsize=7)
    ax_e.set(xlabel="indentation delta [um]", ylabel="E(delta) = F / shape(delta) [kPa]")
    ax_e.set_title("pointwise modulus (flat where the model holds)", fontsize=9)
    ax_e.legend(fontsize=7)
    return _save(fig, path)


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


def plot_modulus_map(result: BatchResult, file: str | Path, path: str | Path) -> Path:
    """Young's modulus at each map position of one force-map file (log colour scale, kPa).

    Curves without a fit are drawn as grey crosses; positions are the instrument's (um).
    """
    rows = result.map_rows(file)
    if not rows:
        raise ValueError(f"{file}: no force-map curves in this batch")
    xy = np.array([r.map_position_um for r in rows])
    fitted = np.array([r.fit is not None for r in rows])
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    if fitted.any():
        moduli = np.array([r.fit.E_kPa for r in rows if r.fit is not None])
        positive = moduli[moduli > 0]
        norm = matplotlib.colors.LogNorm(positive.min(), positive.max()) if positive.size else None
        points = ax.scatter(
            xy[fitted, 0], xy[fitted, 1], c=moduli, s=120, marker="s", cmap="viridis", norm=norm
        )
        fig.colorbar(points, ax=ax, label="E [kPa]")
    if (~fitted).any():
        ax.scatter(xy[~fitted, 0], xy[~fitted, 1], c="grey", marker="x", s=60, label="no fit")
        ax.legend(fontsize=7)
    ax.set(xlabel="x [um]", ylabel="y [um]", title=f"{Path(file).name}: modulus map")
    ax.set_aspect("equal", adjustable="datalim")
    return _save(fig, path)


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


def plot_creep(
    fit: CreepFit, path: str | Path, truth: Callable[[np.ndarray], np.ndarray] | None = None
) -> Path:
    """J(t) data and Prony fit; G(t) from the exact conversion against 1/J(t) (and ``truth``)."""
    t = fit.time_s
    tt = np.logspace(np.log10(max(t[1], 1e-4)), np.log10(t[-1]), 200)
    fig, (ax_j, ax_g) = plt.subplots(1, 2, figsize=(10, 4))
    ax_j.plot(t, fit.compliance_per_kPa, ".", ms=2, alpha=0.4, label="Lee-Radok J(t) from data")
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
