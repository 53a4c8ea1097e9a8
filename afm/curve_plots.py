"""One figure per curve of a batch, fast: one matplotlib figure reused for every curve.

A fitted curve's PNG has three panels: the force against the indentation ``delta = x - x0``
around contact (the baseline shown over half the indentation depth before contact, not the
whole approach), with the fitted model; the residual ``F - F_fit`` below it; and the
pointwise modulus E(delta) = F / shape(delta) beside them (flat where the model holds). The
title names the curve (file, index and map position) and its rating with the reasons. Only
the baseline is thinned to at most ``MAX_BASELINE_POINTS`` points: every contact point is
drawn, in the force, residual and E(delta) panels. A refused curve's PNG shows the recorded
force against the tip position with the reason it was refused.

Drawing into the same figure (new line data, no layout pass) costs a fraction of building a
figure per curve; several processes draw in parallel.
"""

from __future__ import annotations

import textwrap
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from afm.batch import BatchResult, BatchRow
from afm.curve import ForceCurve
from afm.fit import IndentationFit

MAX_BASELINE_POINTS = 300
"""Baseline points drawn at most (every n-th); contact points are all drawn."""
BASELINE_SHOWN = 0.5
"""Baseline shown before contact, as a fraction of the largest indentation."""
DPI = 80
MIN_JOBS_PER_WORKER = 10
"""Fewer plots than this per process are drawn in this process (start-up costs more)."""
TICKS = 4
"""At most this many tick intervals per axis (tick labels are most of a figure's drawing time)."""
HEIGHT_LABELS = {
    "piezo": "piezo - F/k",
    "height (piezo)": "piezo height - F/k",
    "height (measured)": "measured height - F/k",
    "tip position": "recorded tip position",
}
"""How the tip position x was obtained, by the curve's height channel."""


def plot_name(row: BatchRow) -> str:
    """``<file stem>.png``, or ``<file stem>_curve<i>.png`` for a curve of a force map."""
    index = row.curve_index
    return Path(row.file).stem + ("" if index is None else f"_curve{index:04d}") + ".png"


def curve_title(row: BatchRow) -> str:
    """The curve's name: file, and for a force-map curve its index and map position."""
    title = Path(row.file).name
    if row.curve_index is not None:
        title += f", curve {row.curve_index}"
    if row.map_position_um is not None:
        x, y = row.map_position_um
        title += f" at ({x:.4g}, {y:.4g}) um"
    return title


def x_label(height_channel: str) -> str:
    """Axis label of the tip position for a curve's height channel."""
    return f"tip position x = {HEIGHT_LABELS.get(height_channel, height_channel + ' - F/k')} [um]"


def _wrap(text: str, width: int = 110, lines: int = 3) -> str:
    return "\n".join(textwrap.wrap(text, width)[:lines])


def contact_view(fit: IndentationFit) -> np.ndarray:
    """Mask of the fit window's points drawn: every contact point, and the baseline points
    within ``BASELINE_SHOWN`` of the largest indentation before contact, thinned to at most
    ``MAX_BASELINE_POINTS``."""
    delta = fit.indentation_um
    depth = fit.max_indentation_um
    baseline = np.flatnonzero((delta <= 0) & (delta >= -BASELINE_SHOWN * depth))
    keep = delta > 0
    step = max(1, -(-baseline.size // MAX_BASELINE_POINTS))
    keep[baseline[::step]] = True
    return keep


class CurveFigure:
    """A reusable figure: :meth:`draw` writes one fit, :meth:`draw_refused` one refused curve."""

    def __init__(self) -> None:
        self.fig = plt.figure(figsize=(10, 4.6))
        grid = self.fig.add_gridspec(
            2, 2, height_ratios=(3, 1), left=0.07, right=0.98, bottom=0.11, top=0.82
        )
        grid.update(wspace=0.25, hspace=0.08)
        self.ax_f = self.fig.add_subplot(grid[0, 0])
        self.ax_r = self.fig.add_subplot(grid[1, 0], sharex=self.ax_f)
        self.ax_e = self.fig.add_subplot(grid[:, 1])
        (self.data,) = self.ax_f.plot([], [], ".", ms=2, c="C0", label="data")
        (self.model,) = self.ax_f.plot([], [], "-", lw=1.5, c="C1", label="fit")
        self.ax_f.axvline(0.0, ls=":", c="grey", label="contact x0")
        (self.residual,) = self.ax_r.plot([], [], ".", ms=2, c="C0")
        self.ax_r.axhline(0.0, lw=1, c="C1")
        (self.pointwise,) = self.ax_e.plot([], [], ".", ms=2, c="C0", label="E(delta)")
        (self.profile,) = self.ax_e.plot([], [], "s-", ms=4, c="C2", label="median by depth")
        self.mean = self.ax_e.axhline(0.0, ls="--", lw=1, c="C1", label="fitted E")
        self.ax_f.set_ylabel("force [nN]")
        self.ax_f.tick_params(labelbottom=False)
        self.ax_r.set_ylabel("F - fit [nN]")
        self.ax_e.set(xlabel="indentation delta [um]", ylabel="E(delta) = F / shape [kPa]")
        self.legend = self.ax_f.legend(fontsize=7, loc="upper left")
        self.ax_e.legend(fontsize=7, loc="best")
        self.title = self.fig.suptitle("", fontsize=9, x=0.01, ha="left", va="top", y=0.99)
        for ax in (self.ax_f, self.ax_r, self.ax_e):
            ax.locator_params(nbins=TICKS)

    def draw(self, fit: IndentationFit, path: str | Path, title: str = "") -> Path:
        """Write the fit's three panels (module docstring) to ``path``."""
        shown = contact_view(fit)
        delta = fit.indentation_um[shown]
        order = np.argsort(delta, kind="stable")
        delta = delta[order]
        force = (fit.force_nN - fit.offset_nN)[shown][order]
        model = (fit.fitted_force_nN - fit.offset_nN)[shown][order]
        self.data.set_data(delta, force)
        self.model.set_data(delta, model)
        self.residual.set_data(delta, force - model)
        d_e, modulus = fit.pointwise_modulus(0.1 * fit.max_indentation_um)
        self.pointwise.set_data(d_e, modulus)
        self.profile.set_data(*fit.modulus_profile)
        self.mean.set_ydata([fit.E_kPa, fit.E_kPa])
        self.model.set_label(f"fit: E = {fit.E_kPa:.4g} kPa")
        self.legend.get_texts()[1].set_text(self.model.get_label())
        self.ax_r.set_xlabel(
            f"indentation delta = x - x0 [um],  {x_label(fit.height_channel).removesuffix(' [um]')}"
        )
        for ax in (self.ax_f, self.ax_r, self.ax_e):
            ax.relim()
            ax.autoscale_view()
        if modulus.size:
            low, high = np.percentile(modulus, [2, 98])
            pad = 0.1 * max(high - low, abs(fit.E_kPa))
            self.ax_e.set_ylim(min(low, fit.E_kPa) - pad, max(high, fit.E_kPa) + pad)
        self.title.set_text(_wrap(f"{title}: E = {fit.E_kPa:.4g} kPa, {fit.rating}"))
        self.fig.savefig(path, dpi=DPI, pil_kwargs={"compress_level": 1})
        return Path(path)

    def close(self) -> None:
        plt.close(self.fig)


def draw_refused(curve: ForceCurve, reason: str, path: str | Path, title: str = "") -> Path:
    """The recorded force against the tip position of a curve that was refused, and why."""
    fig, ax = plt.subplots(figsize=(7, 4))
    step = max(1, curve.force_nN.size // (4 * MAX_BASELINE_POINTS))
    ax.plot(curve.tip_position_um[::step], curve.force_nN[::step], ".", ms=2, c="C3")
    ax.set(xlabel=x_label(curve.height_channel), ylabel="force as recorded [nN]")
    ax.locator_params(nbins=TICKS)
    reason = reason.removeprefix(f"{curve.source}: ")
    fig.suptitle(_wrap(f"{title}: REFUSED: {reason}", 90, 5), fontsize=8, x=0.01, ha="left")
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, pil_kwargs={"compress_level": 1})
    plt.close(fig)
    return Path(path)


Job = tuple[BatchRow, Path]


def _draw_all(jobs: list[Job]) -> list[Path]:
    figure = CurveFigure()
    paths = []
    try:
        for row, path in jobs:
            if row.fit is not None and not row.error:
                paths.append(figure.draw(row.fit, path, curve_title(row)))
            elif row.curve is not None:
                paths.append(draw_refused(row.curve, row.error, path, curve_title(row)))
    finally:
        figure.close()
    return paths


def plot_curves(
    result: BatchResult, folder: str | Path, workers: int = 1, which: str = "all"
) -> list[Path]:
    """A PNG per curve of ``result`` in ``folder`` (:func:`plot_name`): ``which`` = ``"all"``
    (every fitted and every refused curve that was read), ``"poor"`` (those rated poor and
    the refused ones) or ``"none"``. ``workers`` > 1 draws in that many processes (each with
    its own figure), in order."""
    if which not in ("all", "poor", "none"):
        raise ValueError(f"which: all, poor or none, not {which!r}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    if which == "none":
        return []
    jobs = [
        (row, folder / plot_name(row))
        for row in result.rows
        if (row.curve is not None or (row.fit is not None and not row.error))
        and (which == "all" or not row.good)
    ]
    workers = max(1, min(int(workers), len(jobs) // MIN_JOBS_PER_WORKER))
    if workers == 1:
        return _draw_all(jobs)
    chunks = [jobs[i::workers] for i in range(workers)]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        drawn = list(pool.map(_draw_all, chunks))
    return [path for chunk in drawn for path in chunk]
