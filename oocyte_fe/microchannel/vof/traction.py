"""The traction of the flow on the cell's surface, from one written time of a VOF run.

The surface is the ``alpha = 0.5`` contour of the cell's fraction (alpha = 1 inside), a
closed polygon on the cell-centre lattice (contourpy). On each edge (midpoint x_e, length
ds_e, outward unit normal n_e) the traction of the OUTER phase (the medium, Newtonian mu)::

    t = sigma n,     sigma = -p I + mu (grad U + grad U^T)

with grad U (central differences on the lattice) interpolated bilinearly at
``x_e + offset n_e``, ``offset`` (default 1.5 dx) outside the contour, where the fraction has
fallen to the medium's (a VOF interface is about two cells wide). The medium's pressure is
read outside the interface too, at ``h`` and ``2 h`` (``pressure_offset_cells``), and
extrapolated linearly back to the contour, ``p_e = 2 p(x_e + h n_e) - p(x_e + 2 h n_e)`` (read
at ``h`` alone where the gap to the wall is narrower than ``2 h``; any probe off the fluid
moves closer, in half cells, down to half a cell): read
at ``h`` only, a pressure gradient G along x would give the net force ``-G pi r (r + h)`` on a
disk of radius r instead of ``-G pi r^2`` (18 % more at h = 12.5, r = 70 um). g = 0, so p =
p_rgh. A closed polygon has ``sum n_e ds_e = 0`` exactly, so the pressure's reference level
drops out of the net force ``F = sum t_e ds_e`` (per unit depth, kPa um = nN/um).

**Momentum check.** The cell is a material volume of one liquid: the net force on it is the
rate of change of its momentum, ``F = M d^2 x_c/dt^2`` (M = rho_cell x area, per unit depth;
x_c its centroid from the per-step moments, :func:`.post.moment_trace`, the acceleration of a
quadratic fitted over a window around the written time). :func:`momentum_balance` returns
both and their difference relative to ``sum |t_e| ds_e`` (the gross load).

Internal units: um, kPa, s; the OpenFOAM fields are SI (p in Pa for ``interIsoFoam``,
kinematic in ``nu`` only, so the medium's dynamic viscosity is passed in).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import contourpy
import numpy as np
from scipy.interpolate import RegularGridInterpolator

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.foamfile import read_internal_field
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.post import CellHistory

CSV_HEADER = "arc_angle_deg,x_um,y_um,t_x_kPa,t_y_kPa"


@dataclass(frozen=True)
class Traction:
    """The traction on the cell's surface at one time: per edge of the contour."""

    time: float  # s
    angle: np.ndarray  # deg, of the edge midpoint about the centroid, from +x, counter-clockwise
    points: np.ndarray  # (n, 2) edge midpoints, um
    normals: np.ndarray  # (n, 2) outward unit normals
    lengths: np.ndarray  # (n,) edge lengths, um
    traction: np.ndarray  # (n, 2) kPa
    centroid: np.ndarray  # (2,) um

    @property
    def force(self) -> np.ndarray:
        """Net force per unit depth ``sum t ds`` (kPa um = nN/um)."""
        return (self.traction * self.lengths[:, None]).sum(axis=0)

    @property
    def gross(self) -> float:
        """``sum |t + p_m n| ds`` (kPa um), p_m the mean pressure on the contour (the
        reference level, which exerts no net force): the scale of the load."""
        ds = self.lengths
        p_mean = -float(np.sum(np.einsum("ij,ij->i", self.traction, self.normals) * ds) / ds.sum())
        load = self.traction + p_mean * self.normals
        return float((np.linalg.norm(load, axis=1) * ds).sum())

    def write_csv(self, path: Path) -> Path:
        """CSV, one row per edge in angle order: arc_angle_deg, x_um, y_um, t_x_kPa, t_y_kPa."""
        order = np.argsort(self.angle)
        rows = np.column_stack([self.angle, self.points, self.traction])[order]
        np.savetxt(path, rows, delimiter=",", header=CSV_HEADER, comments="", fmt="%.9g")
        return path


def lattice(layout: Layout) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The cell-centre lattice covering the layout: x (nx,), y (ny,) in um, and the lattice
    index (i, j) of every OpenFOAM cell (blocks share one square spacing dx)."""
    c = layout.cell_centres()
    dx = layout.dx
    x0, y0 = c[:, 0].min(), c[:, 1].min()
    i = np.rint((c[:, 0] - x0) / dx).astype(int)
    j = np.rint((c[:, 1] - y0) / dx).astype(int)
    x = x0 + dx * np.arange(i.max() + 1)
    y = y0 + dx * np.arange(j.max() + 1)
    return x, y, i, j


def _on_lattice(values: np.ndarray, i: np.ndarray, j: np.ndarray, shape: tuple) -> np.ndarray:
    grid = np.full(shape, np.nan)
    grid[j, i] = values
    return grid


def surface_traction(
    folder: Path,
    layout: Layout,
    cell: str,
    mu_medium: float,
    offset_cells: float = 1.5,
    pressure_offset_cells: float = 0.0,
    extrapolate_pressure: bool = False,
) -> Traction:
    """The traction on the cell (module docstring) from the fields of the time ``folder``;
    ``mu_medium`` the medium's viscosity (kPa s); the pressure read ``pressure_offset_cells``
    outside the contour, or, with ``extrapolate_pressure``, extrapolated to it from there and
    twice as far."""
    x, y, i, j = lattice(layout)
    n, shape = layout.n_cells, (len(y), len(x))
    alpha = _on_lattice(read_internal_field(folder / f"alpha.{cell}", n), i, j, shape)
    p = _on_lattice(read_internal_field(folder / "p", n) * 1e-3, i, j, shape)  # Pa -> kPa
    u = read_internal_field(folder / "U", n) * 1e6  # m/s -> um/s
    ux, uy = (_on_lattice(u[:, k], i, j, shape) for k in (0, 1))
    ring = cell_contour(alpha, x, y, folder, cell)
    mids, normals, lengths = edges(ring)

    def at(field: np.ndarray, offset: float) -> np.ndarray:
        """``field`` at ``offset`` cells outside each edge; where that probe (or its
        stencil) is off the fluid (a gap narrower than the offset), the nearest offset in
        half cells that is in it, down to half a cell."""
        f = RegularGridInterpolator((y, x), field, bounds_error=False, fill_value=np.nan)
        values = f((mids + offset * layout.dx * normals)[:, ::-1])
        for closer in np.arange(offset - 0.5, 0.25, -0.5):
            gap = ~np.isfinite(values)
            if not gap.any():
                break
            values[gap] = f((mids[gap] + closer * layout.dx * normals[gap])[:, ::-1])
        return values

    h = pressure_offset_cells
    pp = at(p, h)
    if extrapolate_pressure:
        far = 2.0 * pp - RegularGridInterpolator((y, x), p, bounds_error=False, fill_value=np.nan)(
            (mids + 2.0 * h * layout.dx * normals)[:, ::-1]
        )
        pp = np.where(np.isfinite(far), far, pp)  # no room for 2 h: read at h
    # gradients on the lattice (1/s), central differences, taken in the medium
    dux_dy, dux_dx = np.gradient(ux, layout.dx)
    duy_dy, duy_dx = np.gradient(uy, layout.dx)
    gxx, gxy, gyx, gyy = (at(g, offset_cells) for g in (dux_dx, dux_dy, duy_dx, duy_dy))
    if not np.all(np.isfinite(np.concatenate([pp, gxx, gxy, gyx, gyy]))):
        raise InputError(folder, "U, p", "the fluid all around the cell (probe off the mesh)")
    sxx = -pp + 2.0 * mu_medium * gxx
    syy = -pp + 2.0 * mu_medium * gyy
    sxy = mu_medium * (gxy + gyx)
    t = np.column_stack(
        [sxx * normals[:, 0] + sxy * normals[:, 1], sxy * normals[:, 0] + syy * normals[:, 1]]
    )
    centroid, angle = polar(ring, mids)
    return Traction(float(folder.name), angle, mids, normals, lengths, t, centroid)


def cell_contour(
    alpha: np.ndarray, x: np.ndarray, y: np.ndarray, folder: Path, cell: str
) -> np.ndarray:
    """The cell's ``alpha = 0.5`` contour on the lattice ``(x, y)`` (um): the longest closed
    line, counter-clockwise, without repeated points, as a closed ring (first point last);
    ``folder`` and ``cell`` name the field in the error when there is none."""
    lines = contourpy.contour_generator(x, y, np.nan_to_num(alpha, nan=0.0)).lines(0.5)
    closed = [ln for ln in lines if len(ln) > 3 and np.allclose(ln[0], ln[-1])]
    if not closed:
        raise InputError(folder, f"alpha.{cell}", "a closed alpha = 0.5 contour of the cell")
    ring = max(closed, key=len)
    if signed_area(ring) < 0:
        ring = ring[::-1]  # counter-clockwise: the outward normal is (dy, -dx)/ds
    keep = np.concatenate([[True], np.linalg.norm(np.diff(ring, axis=0), axis=1) > 1e-9])
    return ring[keep]  # repeated points (a contour through a lattice point): no empty edges


def edges(ring: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Midpoints (n, 2), outward unit normals (n, 2) and lengths (n,) of a closed
    counter-clockwise ring's edges."""
    edge = np.diff(ring, axis=0)
    lengths = np.linalg.norm(edge, axis=1)
    normals = np.column_stack([edge[:, 1], -edge[:, 0]]) / lengths[:, None]
    return 0.5 * (ring[1:] + ring[:-1]), normals, lengths


def polar(ring: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ring's area centroid (um) and the polar angle of ``points`` about it (deg, from
    +x, counter-clockwise, in [0, 360))."""
    centroid = polygon_centroid(ring, signed_area(ring))
    d = points - centroid
    return centroid, np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 360.0


def signed_area(ring: np.ndarray) -> float:
    """The area of a closed ring (first point last), positive counter-clockwise (um^2)."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))


def polygon_centroid(ring: np.ndarray, area: float) -> np.ndarray:
    """The area centroid (um) of a closed ring (first point last) of signed ``area``
    (:func:`signed_area`)."""
    x, y = ring[:, 0], ring[:, 1]
    cross = x[:-1] * y[1:] - x[1:] * y[:-1]
    return np.array([np.sum((x[:-1] + x[1:]) * cross), np.sum((y[:-1] + y[1:]) * cross)]) / (
        6.0 * area
    )


@dataclass(frozen=True)
class MomentumBalance:
    """Net traction force against the cell's momentum rate (per unit depth, kPa um)."""

    force: np.ndarray
    momentum_rate: np.ndarray
    gross: float

    @property
    def imbalance_pct(self) -> float:
        """``|F - M a| / sum |t| ds`` in per cent."""
        return 100.0 * float(np.linalg.norm(self.force - self.momentum_rate)) / self.gross


def momentum_balance(
    traction: Traction,
    trace: CellHistory,
    cell_volume: float,
    density: float,
    window: float,
) -> MomentumBalance:
    """:class:`MomentumBalance` at the traction's time: M = ``density`` (nN s^2/um^4) x
    ``cell_volume`` (um^2 per unit depth), the centroid's acceleration (um/s^2) from a
    quadratic fitted to the per-step ``trace`` over ``window`` (s) centred there."""
    t0 = traction.time
    sel = np.abs(trace.time - t0) <= 0.5 * window
    if sel.sum() < 5:
        raise InputError("momentum_balance", "window", "at least 5 steps of the trace", window)
    acc = np.array(
        [2.0 * np.polyfit(trace.time[sel] - t0, trace.centroid[sel, k], 2)[0] for k in (0, 1)]
    )
    return MomentumBalance(traction.force, density * cell_volume * acc, traction.gross)
