"""Post-processing a VOF run: the cell's shape, path and speed, phase volumes, flow profiles.

**Axis ratio** from the second moments of the cell indicator ``c = alpha_zp + alpha_cytoplasm``
over the cells (centres x_k, volumes V_k, weights w_k = c_k V_k)::

    x_c = sum w_k x_k / sum w_k,      M = sum w_k (x_k - x_c)(x_k - x_c)^T / sum w_k
    ratio = sqrt(lambda_min(M) / lambda_max(M))          (minor / major, as Table 4 prints)

exact for a uniform ellipse (M has eigenvalues a^2/4 and b^2/4). The centroid path x_c(t) gives
the speed by central differences; the phase volumes ``sum alpha_i V_k`` against t = 0 give the
volume (mass) errors. Snapshots are drawn off-screen (matplotlib Agg) from the block structure;
the time series opens in ParaView through the case's ``case.foam``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.foamfile import read_internal_field
from oocyte_fe.microchannel.vof.geometry import Layout


def time_directories(case: Path) -> list[tuple[float, Path]]:
    """The written time folders of a (reconstructed) case, in time order, t = 0 included."""
    found = []
    for d in Path(case).iterdir():
        try:
            found.append((float(d.name), d))
        except ValueError:
            continue
    return sorted((t, d) for t, d in found if (d / "U").exists())


def shape_moments(points: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, float]:
    """Centroid (2,) and minor/major axis ratio of a weighted 2-D point set (module docstring)."""
    w = np.clip(np.asarray(weights, dtype=float), 0.0, None)
    total = w.sum()
    if total <= 0:
        raise InputError("post-processing", "cell indicator", "a cell present in the domain")
    centre = (w[:, None] * points).sum(axis=0) / total
    d = points - centre
    m = (w[:, None, None] * d[:, :, None] * d[:, None, :]).sum(axis=0) / total
    lo, hi = np.linalg.eigvalsh(m)
    return centre, float(np.sqrt(max(lo, 0.0) / hi))


@dataclass(frozen=True)
class CellHistory:
    """The cell over time: t (s), centroid (um), speed (um/s), ratio, phase volume errors."""

    time: np.ndarray
    centroid: np.ndarray  # (n, 2)
    speed: np.ndarray
    ratio: np.ndarray
    volume_error: dict[str, np.ndarray]  # relative to t = 0, per phase

    def at_x(self, x: float) -> tuple[float, float]:
        """(time, ratio) when the centroid crosses ``x`` (um), linear in between writes; nan when
        it never does."""
        cx = self.centroid[:, 0]
        above = np.nonzero(cx >= x)[0]
        if len(above) == 0 or above[0] == 0:
            return float("nan"), float("nan")
        i = above[0]
        f = (x - cx[i - 1]) / (cx[i] - cx[i - 1])
        return (
            float(self.time[i - 1] + f * (self.time[i] - self.time[i - 1])),
            float(self.ratio[i - 1] + f * (self.ratio[i] - self.ratio[i - 1])),
        )

    def near_x(self, x: float, half_window: float) -> float:
        """The ratio at centroid position ``x`` (um) from a straight line fitted to the ratio
        against the centroid's x over ``|x_c - x| <= half_window``: the per-step ratio jitters
        by several per cent as the interface crosses the grid, a least-squares line through
        the window averages that out. nan when fewer than 3 points lie in the window."""
        cx = self.centroid[:, 0]
        sel = np.abs(cx - x) <= half_window
        if sel.sum() < 3:
            return float("nan")
        slope, intercept = np.polyfit(cx[sel] - x, self.ratio[sel], 1)
        return float(intercept)


def cell_history(
    case: Path, layout: Layout, cell_phases: Sequence[str], all_phases: Sequence[str]
) -> CellHistory:
    """Read every written time of ``case`` and follow the cell made of ``cell_phases``."""
    centres = layout.cell_centres()
    volume = layout.dx**3  # um^3, one cell thick
    n = layout.n_cells
    times, centroids, ratios = [], [], []
    volumes: dict[str, list[float]] = {p: [] for p in all_phases}
    for t, folder in time_directories(case):
        alpha = {p: read_internal_field(folder / f"alpha.{p}", n) for p in all_phases}
        indicator = sum(alpha[p] for p in cell_phases)
        centre, ratio = shape_moments(centres, indicator)
        times.append(t)
        centroids.append(centre)
        ratios.append(ratio)
        for p in all_phases:
            volumes[p].append(float(alpha[p].sum() * volume))
    time = np.array(times)
    centroid = np.array(centroids)
    speed = np.gradient(centroid[:, 0], time) if len(time) > 1 else np.zeros(len(time))
    errors = {p: np.array(v) / v[0] - 1.0 for p, v in volumes.items() if v[0] > 0}
    return CellHistory(time, centroid, speed, np.array(ratios), errors)


def moment_trace(case: Path, cell_phases: Sequence[str]) -> CellHistory:
    """The cell's centroid (um) and axis ratio at every time step, from the integrals
    ``sum_k alpha_k V_k f_k`` (f = 1, x, y, x^2, y^2, xy) the solver wrote per phase
    (:func:`.casewriter.moment_functions`), summed over ``cell_phases``::

        x_c = S_x / S_1,   M = [[S_xx, S_xy], [S_xy, S_yy]] / S_1 - x_c x_c^T

    the same moments as :func:`shape_moments` on the written fields (no volume errors)."""
    sums = None
    for phase in cell_phases:
        folder = Path(case) / "postProcessing" / f"moments_{phase}"
        files = sorted(folder.glob("*/volFieldValue*.dat"))
        if not files:
            raise InputError(folder, "volFieldValue.dat", "the solver's per-step cell moments")
        rows = np.vstack([np.loadtxt(f, comments="#", ndmin=2) for f in files])
        rows = rows[np.unique(rows[:, 0], return_index=True)[1]]
        sums = rows if sums is None else _add_moments(sums, rows)
    assert sums is not None
    t, one, x, y, xx, yy, xy = sums.T
    cx, cy = x / one, y / one
    mxx, myy, mxy = xx / one - cx**2, yy / one - cy**2, xy / one - cx * cy
    half = 0.5 * (mxx + myy)
    root = np.sqrt((0.5 * (mxx - myy)) ** 2 + mxy**2)
    ratio = np.sqrt(np.clip(half - root, 0.0, None) / (half + root))
    centroid = np.column_stack([cx, cy]) * 1e6
    speed = np.gradient(centroid[:, 0], t) if len(t) > 1 else np.zeros(len(t))
    return CellHistory(t, centroid, speed, ratio, {})


def _add_moments(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise sum of two phases' moment tables over their common times."""
    common, ia, ib = np.intersect1d(a[:, 0], b[:, 0], return_indices=True)
    out = a[ia].copy()
    out[:, 1:] += b[ib, 1:]
    return out


def centreline_gradient(
    folder: Path, layout: Layout, x_range: tuple[float, float], field: str = "p"
) -> float:
    """-dp/dx (Pa/m) from a straight-line fit of ``field`` on the two cell rows next to y = 0
    between ``x_range`` (um); a one-block slit layout."""
    centres = layout.cell_centres()
    values = read_internal_field(folder / field, layout.n_cells)
    rows = np.abs(centres[:, 1]) < layout.dx
    sel = rows & (centres[:, 0] >= x_range[0]) & (centres[:, 0] <= x_range[1])
    slope = np.polyfit(centres[sel, 0] * 1e-6, values[sel], 1)[0]
    return float(-slope)


def column_profile(folder: Path, layout: Layout, x: float) -> tuple[np.ndarray, np.ndarray]:
    """(y in um, u_x in m/s) on the column of cells nearest ``x`` (um)."""
    centres = layout.cell_centres()
    u = read_internal_field(folder / "U", layout.n_cells)
    nearest = centres[np.argmin(np.abs(centres[:, 0] - x)), 0]
    column = np.abs(centres[:, 0] - nearest) < 1e-9
    order = np.argsort(centres[column, 1])
    return centres[column, 1][order], u[column, 0][order]


def flow_rate(folder: Path, layout: Layout, x: float) -> float:
    """Flow rate per unit depth (m^2/s) through the column of cells nearest ``x`` (um)."""
    _, u = column_profile(folder, layout, x)
    return float(u.sum() * layout.dx * 1e-6)


def snapshot(
    folder: Path, layout: Layout, phases: Sequence[str], path: Path, title: str = ""
) -> Path:
    """Draw the phase map (0: first phase, i: the i-th) of one time folder, off-screen."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = layout.n_cells
    index = sum(  # the first phase counts 0: its fraction is not needed (interIsoFoam: not written)
        i * read_internal_field(folder / f"alpha.{p}", n) for i, p in enumerate(phases) if i
    )
    fig, ax = plt.subplots(figsize=(8, 3.2))
    start = 0
    for b in layout.blocks:
        stop = start + b.nx * b.ny
        ax.imshow(
            index[start:stop].reshape(b.ny, b.nx),
            extent=(b.x0, b.x1, b.y0, b.y1),
            origin="lower",
            vmin=0,
            vmax=len(phases) - 1,
            cmap="viridis",
            interpolation="nearest",
        )
        start = stop
    xs = [v for b in layout.blocks for v in (b.x0, b.x1)]
    ys = [v for b in layout.blocks for v in (b.y0, b.y1)]
    ax.set(xlim=(min(xs), max(xs)), ylim=(min(ys), max(ys)), xlabel="x (um)", ylabel="y (um)")
    ax.set_aspect("equal")
    ax.set_title(title or f"t = {folder.name} s  ({', '.join(phases)} = 0..{len(phases) - 1})")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
