"""Momentum balance of a control volume around the cell: does the flow conserve momentum?

A box of whole mesh cells around the cell, its faces in the medium. Its momentum changes by
the forces on its faces and the momentum carried through them (per unit depth, kPa um =
nN/um)::

    d/dt sum_box rho u dA  =  sum_faces [ sigma n  -  rho u (u . n) ] ds
    sigma = -p I + mu (grad u + grad u^T),     rho = alpha rho_cell + (1 - alpha) rho_medium

discretised as the solver's faces see it on the uniform lattice (:func:`.traction.lattice`):
p, rho, mu and the flux velocity on a face the mean of its two cells, the normal derivative
across the face the difference of its two cells over dx, the tangential one the mean of the
two cells' central differences, the convected velocity the upwind cell's value plus half a
cell of its central gradient (the cases' ``linearUpwind grad(U)``; with the plain face mean
the budget misses by 0.5-2 % more); the left-hand side from two consecutive steps,
``(P(t2) - P(t1)) / dt``, the faces at ``t2`` (implicit Euler, as the solver). A run that
satisfies its discrete momentum equation balances this to the interpolation error of the
face values; a residual of the momentum equation inside the box (e.g. pressure correctors
without the momentum predictor: each one Jacobi sweep of the viscous momentum equation,
docs/microchannel.md) shows as a miss. The miss is reported relative to the load on the
box's faces, ``sum |t + p_m n| ds`` (``p_m`` the faces' mean pressure, which exerts no net
force).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.convection import linear_upwind
from oocyte_fe.microchannel.vof.foamfile import read_internal_field
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.traction import _on_lattice, lattice

BOX_MARGIN_CELLS = 1  # the box: the cell (alpha > 1e-3) and one more row of cells around it


@dataclass(frozen=True)
class BoxBalance:
    """The box's momentum budget (per unit depth, nN/um) between two steps."""

    force: np.ndarray  # sum sigma n ds over the faces
    outflow: np.ndarray  # sum rho u (u . n) ds
    momentum_rate: np.ndarray  # (P(t2) - P(t1)) / dt
    load: float  # sum |t + p_m n| ds
    box_um: tuple[float, float, float, float]  # x0, x1, y0, y1 of the box's faces

    @property
    def imbalance_pct(self) -> float:
        """``|F - outflow - dP/dt| / load`` in per cent."""
        miss = self.force - self.outflow - self.momentum_rate
        return 100.0 * float(np.linalg.norm(miss)) / self.load


@dataclass(frozen=True)
class MixtureFields:
    """The fields of one written time on the lattice (NaN off the fluid), and the mixture's
    density and viscosity (``alpha`` weighted, the cell's from the solver's ``nu1``)."""

    alpha: np.ndarray
    p: np.ndarray  # kPa
    ux: np.ndarray  # um/s
    uy: np.ndarray
    rho: np.ndarray  # nN s^2/um^4
    mu: np.ndarray  # kPa s


def mixture_fields(
    folder: Path, layout: Layout, cell: str, rho_cell: float, rho_medium: float, mu_medium: float
) -> MixtureFields:
    """:class:`MixtureFields` of the time ``folder`` (densities nN s^2/um^4, mu kPa s)."""
    x, y, i, j = lattice(layout)
    n, shape = layout.n_cells, (len(y), len(x))

    def grid(name: str, scale: float = 1.0) -> np.ndarray:
        return _on_lattice(read_internal_field(folder / name, n) * scale, i, j, shape)

    alpha = grid(f"alpha.{cell}")
    u = read_internal_field(folder / "U", n) * 1e6  # m/s -> um/s
    ux, uy = (_on_lattice(u[:, k], i, j, shape) for k in (0, 1))
    # the cell's kinematic viscosity, as the solver wrote it (m^2/s), for the mixture's mu
    nu_path = folder / "nu1"
    mu_cell = grid("nu1", 1e12) * rho_cell if nu_path.exists() else np.zeros_like(alpha)
    return MixtureFields(
        alpha,
        grid("p", 1e-3),  # Pa -> kPa
        ux,
        uy,
        alpha * rho_cell + (1.0 - alpha) * rho_medium,
        alpha * mu_cell + (1.0 - alpha) * mu_medium,
    )


def cell_box(alpha: np.ndarray, margin: int = BOX_MARGIN_CELLS) -> tuple[int, int, int, int]:
    """Lattice index range (i0, i1, j0, j1), inclusive, of the cells with alpha > 1e-3 grown
    by ``margin`` cells on every side."""
    jj, ii = np.nonzero(np.nan_to_num(alpha) > 1e-3)
    if len(ii) == 0:
        raise InputError("control volume", "alpha", "a cell in the domain")
    return ii.min() - margin, ii.max() + margin, jj.min() - margin, jj.max() + margin


def box_balance(
    folder_1: Path,
    folder_2: Path,
    layout: Layout,
    cell: str,
    rho_cell: float,
    rho_medium: float,
    mu_medium: float,
    margin: int = BOX_MARGIN_CELLS,
) -> BoxBalance:
    """:class:`BoxBalance` between the consecutive steps written in ``folder_1`` and
    ``folder_2`` (module docstring): densities nN s^2/um^4, ``mu_medium`` kPa s. The box is
    the cell's extent at ``folder_2`` grown by ``margin`` cells; every face must lie in the
    fluid and outside the cell."""
    dt = float(folder_2.name) - float(folder_1.name)
    if dt <= 0:
        raise InputError(folder_2, "time", f"a time after {folder_1.name}", folder_2.name)
    args = (layout, cell, rho_cell, rho_medium, mu_medium)
    f1, f2 = mixture_fields(folder_1, *args), mixture_fields(folder_2, *args)
    i0, i1, j0, j1 = cell_box(f2.alpha, margin)
    dx = layout.dx
    ny, nx = f2.alpha.shape
    if i0 < 1 or j0 < 1 or i1 > nx - 2 or j1 > ny - 2:
        raise InputError(folder_2, "control volume", "a box inside the lattice", (i0, i1, j0, j1))
    inside = (slice(j0, j1 + 1), slice(i0, i1 + 1))
    rate = (
        np.array(
            [
                np.sum((f2.rho * u2)[inside] - (f1.rho * u1)[inside])
                for u2, u1 in ((f2.ux, f1.ux), (f2.uy, f1.uy))
            ]
        )
        * dx
        * dx
        / dt
    )
    if not np.all(np.isfinite(rate)):
        raise InputError(folder_2, "control volume", "a box of fluid cells only (a wall cut it)")
    t_faces, flux, normals, p_faces = [], [], [], []
    for side in _sides(i0, i1, j0, j1):
        t, q, p = _face_terms(f2, dx, *side)
        t_faces.append(t)
        flux.append(q)
        p_faces.append(p)
        normals.append(np.tile(side[-1], (len(p), 1)))
    t, q, p, n = (
        np.vstack(a) if a[0].ndim == 2 else np.concatenate(a)
        for a in (t_faces, flux, p_faces, normals)
    )
    if not np.all(np.isfinite(t)) or not np.all(np.isfinite(q)):
        raise InputError(folder_2, "control volume", "a box of fluid cells only (a wall cut it)")
    x, y, _, _ = lattice(layout)
    box = (x[i0] - dx / 2, x[i1] + dx / 2, y[j0] - dx / 2, y[j1] + dx / 2)
    load = float(np.sum(np.linalg.norm(t + p.mean() * n, axis=1)) * dx)
    return BoxBalance(t.sum(axis=0) * dx, q.sum(axis=0) * dx, rate, load, box)


def _sides(i0: int, i1: int, j0: int, j1: int) -> list[tuple]:
    """The four sides: (cells inside, cells outside, outward normal) as index arrays."""
    js, is_ = np.arange(j0, j1 + 1), np.arange(i0, i1 + 1)
    return [
        ((js, np.full_like(js, i1)), (js, np.full_like(js, i1 + 1)), np.array([1.0, 0.0])),
        ((js, np.full_like(js, i0)), (js, np.full_like(js, i0 - 1)), np.array([-1.0, 0.0])),
        ((np.full_like(is_, j1), is_), (np.full_like(is_, j1 + 1), is_), np.array([0.0, 1.0])),
        ((np.full_like(is_, j0), is_), (np.full_like(is_, j0 - 1), is_), np.array([0.0, -1.0])),
    ]


def _face_terms(f: MixtureFields, dx: float, inner: tuple, outer: tuple, n: np.ndarray) -> tuple:
    """Traction (k, 2), momentum outflow (k, 2) per unit face length, and face pressure (k,)."""
    if np.any(f.alpha[inner] > 1e-3) or np.any(f.alpha[outer] > 1e-3):
        raise InputError("control volume", "box", "faces outside the cell (alpha <= 1e-3)")

    def face(q: np.ndarray) -> np.ndarray:
        return 0.5 * (q[inner] + q[outer])

    cell_grads = {name: np.gradient(u, dx)[::-1] for name, u in (("ux", f.ux), ("uy", f.uy))}
    grads = {name: (face(g[0]), face(g[1])) for name, g in cell_grads.items()}  # (d/dx, d/dy)
    normal_x = n[0] != 0.0  # a face normal to x: d/dx across it, d/dy along it
    s = n[0] if normal_x else n[1]
    across = {k: s * (u[outer] - u[inner]) / dx for k, u in (("ux", f.ux), ("uy", f.uy))}
    if normal_x:
        dux_dx, duy_dx = across["ux"], across["uy"]
        dux_dy, duy_dy = grads["ux"][1], grads["uy"][1]
    else:
        dux_dy, duy_dy = across["ux"], across["uy"]
        dux_dx, duy_dx = grads["ux"][0], grads["uy"][0]
    p, mu, rho = face(f.p), face(f.mu), face(f.rho)
    sxx = -p + 2.0 * mu * dux_dx
    syy = -p + 2.0 * mu * duy_dy
    sxy = mu * (dux_dy + duy_dx)
    t = np.column_stack([sxx * n[0] + sxy * n[1], sxy * n[0] + syy * n[1]])
    un = face(f.ux) * n[0] + face(f.uy) * n[1]  # the face flux: linear interpolation
    convected = []
    for name, u in (("ux", f.ux), ("uy", f.uy)):
        d_dx, d_dy = cell_grads[name]
        slope = d_dx * n[0] + d_dy * n[1]  # along the outward normal, per cell
        convected.append(linear_upwind(u[inner], u[outer], slope[inner], slope[outer], un, dx))
    return t, np.column_stack([rho * un * convected[0], rho * un * convected[1]]), p
