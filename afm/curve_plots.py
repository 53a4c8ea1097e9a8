"""One figure per curve of a batch, fast: a single matplotlib figure reused for every curve.

Each PNG shows force against tip position with the fitted model and the contact point, and the
pointwise modulus E(delta) = F / shape(delta) beside it (flat where the model holds), as
:func:`afm.plotting.plot_fit`. Drawing into the same figure (new line data, no layout pass)
costs a fraction of building a figure per curve; curves longer than ``MAX_PLOT_POINTS`` are
drawn with every n-th point (the fit used them all).
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from afm.batch import BatchResult, BatchRow
from afm.fit import IndentationFit

MAX_PLOT_POINTS = 600
DPI = 80
MIN_JOBS_PER_WORKER = 10
"""Fewer plots than this per process are drawn in this process (start-up costs more)."""
TICKS = 4
"""At most this many tick intervals per axis (tick labels are most of a figure's drawing time)."""


def plot_name(row: BatchRow) -> str:
    """``<file stem>.png``, or ``<file stem>_curve<i>.png`` for a curve of a force map."""
    index = row.curve_index
    return Path(row.file).stem + ("" if index is None else f"_curve{index:04d}") + ".png"


class CurveFigure:
    """A reusable two-panel figure; :meth:`draw` writes one fit to one PNG."""

    def __init__(self) -> None:
        self.fig, (self.ax_f, self.ax_e) = plt.subplots(1, 2, figsize=(9, 3.6))
        self.fig.subplots_adjust(left=0.08, right=0.98, bottom=0.15, top=0.88, wspace=0.28)
        (self.data,) = self.ax_f.plot([], [], ".", ms=2, c="C0", label="data")
        (self.model,) = self.ax_f.plot([], [], "-", lw=1.5, c="C1", label="fit")
        self.contact = self.ax_f.axvline(0.0, ls=":", c="grey", label="contact")
        (self.pointwise,) = self.ax_e.plot([], [], ".", ms=2, c="C0", label="E(delta)")
        self.mean = self.ax_e.axhline(0.0, ls="--", lw=1, c="C1", label="fitted E")
        self.ax_f.set(xlabel="tip position x = piezo - F/k [um]", ylabel="force [nN]")
        self.ax_e.set(xlabel="indentation delta [um]", ylabel="E(delta) [kPa]")
        self.ax_e.set_title("pointwise modulus (flat where the model holds)", fontsize=9)
        self.legend = self.ax_f.legend(fontsize=7, loc="upper left")
        self.ax_e.legend(fontsize=7, loc="upper right")
        for ax in (self.ax_f, self.ax_e):
            ax.locator_params(nbins=TICKS)

    def draw(self, fit: IndentationFit, path: str | Path, title: str = "") -> Path:
        step = max(1, fit.tip_position_um.size // MAX_PLOT_POINTS)
        x, f = fit.tip_position_um[::step], fit.force_nN[::step]
        self.data.set_data(x, f)
        self.model.set_data(x, fit.fitted_force_nN[::step])
        self.contact.set_xdata([fit.contact_point_um, fit.contact_point_um])
        delta, modulus = fit.pointwise_modulus(0.1 * float(fit.indentation_um.max()))
        self.pointwise.set_data(delta[::step], modulus[::step])
        self.mean.set_ydata([fit.E_kPa, fit.E_kPa])
        self.model.set_label(f"fit: E = {fit.E_kPa:.3g} kPa ({fit.quality})")
        self.legend.get_texts()[1].set_text(self.model.get_label())
        for ax in (self.ax_f, self.ax_e):
            ax.relim()
            ax.autoscale_view()
        if modulus.size:
            low, high = np.percentile(modulus, [2, 98])
            pad = 0.1 * max(high - low, abs(fit.E_kPa))
            self.ax_e.set_ylim(min(low, fit.E_kPa) - pad, max(high, fit.E_kPa) + pad)
        self.ax_f.set_title(title, fontsize=9)
        self.fig.savefig(path, dpi=DPI, pil_kwargs={"compress_level": 1})
        return Path(path)

    def close(self) -> None:
        plt.close(self.fig)


def _draw_all(jobs: list[tuple[IndentationFit, Path, str]]) -> list[Path]:
    figure = CurveFigure()
    try:
        return [figure.draw(fit, path, title) for fit, path, title in jobs]
    finally:
        figure.close()


def plot_curves(result: BatchResult, folder: str | Path, workers: int = 1) -> list[Path]:
    """A PNG per fitted curve of ``result`` in ``folder`` (:func:`plot_name`); failed curves
    have none (their error is in the table). ``workers`` > 1 draws in that many processes
    (each with its own figure), in order."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    jobs = [
        (row.fit, folder / plot_name(row), Path(row.file).name)
        for row in result.rows
        if row.fit is not None and not row.error
    ]
    workers = max(1, min(int(workers), len(jobs) // MIN_JOBS_PER_WORKER))
    if workers == 1:
        return _draw_all(jobs)
    chunks = [jobs[i::workers] for i in range(workers)]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        drawn = list(pool.map(_draw_all, chunks))
    return [path for chunk in drawn for path in chunk]
