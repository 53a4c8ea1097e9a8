"""The force of the flow on the cell from its diffuse interface, and the cell's momentum budget.

In a VOF solution the cell's surface is a band about two cells wide. Multiplying the momentum
equation ``d(rho u)/dt + div(rho u u) = div sigma`` by the cell's fraction ``alpha`` (which is
carried by the flow, ``d alpha/dt + u . grad alpha = 0``) and integrating over the domain
(``alpha = 0`` away from the cell) gives, per unit depth (nN/um)::

    d/dt sum alpha rho u dA  =  F,     F = -sum sigma . grad(alpha) dA
    sigma = -p I + mu (grad u + grad u^T - 2/3 div(u) I),   rho, mu the mixture's (alpha weighted)

``F`` is the net force of the medium on the cell whatever the stress inside the band (the
traction is continuous across a sharp interface), so, unlike the traction read on the
``alpha = 0.5`` contour (:mod:`.traction`), it needs no probe outside the band. Discretised on
the uniform lattice as the solver discretises the stress (``interFoam``'s
``-fvm::laplacian(mu, U) - fvc::div(mu dev2(grad(U)^T))``, Gauss linear): the pressure and the
transposed part ``mu (grad u^T - 2/3 tr(grad u) I)`` at the cells with central differences,
the Laplacian part ``mu grad u`` on the faces, ``mu_f (u_R - u_L) / dx`` with
``mu_f = (mu_L + mu_R) / 2``, its force ``-mu_f (u_R - u_L) (alpha_R - alpha_L)`` shared
half and half by the face's two cells (next to a wall with the wall's conditions). With the
Laplacian part also at the cells (the mixture's mu times central differences, the form
before 2026-12-04) the budget missed by 1.6-1.8 % at 600 hPa on 12.5 um where this form
closes to 0.4 % (docs/elastic_cell_in_flow.md). The left side from two consecutive steps
``(P(t2) - P(t1)) / dt`` and ``F`` at ``t2`` (implicit Euler, as the solver); the solver takes
the transposed part explicitly, from the step's starting velocity, which the budget also
reports (``start`` of :func:`band_force`): the transposed part alternates from step to step
where the cell's viscous number is large (finer meshes), and taken at ``t1`` it closes the
budget to 0.04-0.54 % at 600 hPa on 6.25-3.125 um, where at ``t2`` it misses by 0.6-2.4 %.
What the upwind-biased convection leaves in the budget on the lattice (``D``,
:mod:`.convection`) is reported beside (:attr:`CellBalance.scheme_imbalance_pct`).
The miss is reported against the load ``sum |(sigma + p_m I) . grad alpha| dA`` (``p_m``
the band's mean pressure, which exerts no net force on a closed surface).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.control_volume import MixtureFields, mixture_fields
from oocyte_fe.microchannel.vof.convection import convection_remainder
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.walls import face_pairs, walled


@dataclass(frozen=True)
class CellBalance:
    """The cell's momentum budget between two steps (per unit depth, nN/um)."""

    force: np.ndarray  # -sum sigma . grad(alpha) dA at t2
    momentum_rate: np.ndarray  # d/dt sum alpha rho u dA
    load: float  # sum |(sigma + p_m I) . grad alpha| dA
    force_explicit: np.ndarray  # the same with the transposed part at t1 (the solver's)
    convection: np.ndarray  # D: the convection's remainder on the lattice (.convection)

    @property
    def imbalance_pct(self) -> float:
        """``|F - dP/dt| / load`` in per cent."""
        return 100.0 * float(np.linalg.norm(self.force - self.momentum_rate)) / self.load

    @property
    def explicit_imbalance_pct(self) -> float:
        """The same with the transposed part of the viscous stress taken at the step's start,
        as the solver integrates it (explicitly), in per cent."""
        return 100.0 * float(np.linalg.norm(self.force_explicit - self.momentum_rate)) / self.load

    @property
    def scheme_imbalance_pct(self) -> float:
        """``|F_explicit + D - dP/dt| / load`` in per cent: the budget of the explicit force
        with the remainder ``D`` of the solver's upwind-biased convection
        (:mod:`.convection`), which the continuum identity does not see."""
        miss = self.force_explicit + self.convection - self.momentum_rate
        return 100.0 * float(np.linalg.norm(miss)) / self.load


def _face_laplacian(
    alpha: np.ndarray, ux: np.ndarray, uy: np.ndarray, mu: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each cell's half of its faces' ``-mu_f (u_R - u_L) (alpha_R - alpha_L)`` (x and y
    components, nN/um per unit depth; mu kPa s, u um/s): the Laplacian part of the viscous
    force on the faces, ``mu_f`` the mean of the two cells' mu."""
    out = [np.zeros_like(alpha), np.zeros_like(alpha)]
    for axis in (0, 1):
        lo, hi = face_pairs(axis)
        mu_f = 0.5 * (mu[lo] + mu[hi])
        d_alpha = alpha[hi] - alpha[lo]
        for k, u in enumerate((ux, uy)):
            half = -0.5 * mu_f * (u[hi] - u[lo]) * d_alpha
            out[k][lo] += half
            out[k][hi] += half
    return out[0], out[1]


@dataclass(frozen=True)
class BandForce:
    """The diffuse interface's force cell by cell of its band (per unit depth)."""

    rows: np.ndarray  # (m,) lattice row (y index) of each band cell
    cols: np.ndarray  # (m,) lattice column (x index)
    force: np.ndarray  # (m, 2) -sigma . grad(alpha) dx^2, nN/um
    grad: np.ndarray  # (m, 2) grad(alpha) dx^2, um
    p_mean: float  # the band's mean pressure (weighted by |grad alpha|), kPa

    @property
    def total(self) -> np.ndarray:
        """``F = -sum sigma . grad(alpha) dA`` (nN/um)."""
        return self.force.sum(axis=0)

    @property
    def load(self) -> np.ndarray:
        """Each cell's ``-(sigma + p_m I) . grad(alpha) dA`` (nN/um): its force less the band's
        mean pressure, which exerts no net force on a closed band."""
        return self.force - self.p_mean * self.grad


def band_force(f: MixtureFields, dx: float, start: MixtureFields | None = None) -> BandForce:
    """:class:`BandForce` of the fields ``f`` on a lattice of spacing ``dx`` (um), over the
    fluid cells where ``grad alpha`` is not zero; next to a wall the central differences take
    the wall's conditions (alpha, p: zero normal gradient; U = 0). ``start``: the fields of
    the step before, whose velocity then gives the transposed part of the viscous stress (the
    solver's explicit term, ``fvc::div(mu dev2(grad(U)^T))`` of the step's starting U)."""
    fluid = np.isfinite(f.alpha) & np.isfinite(f.p) & np.isfinite(f.ux) & np.isfinite(f.uy)
    if not fluid.any():
        raise InputError("diffuse force", "alpha, p, U", "fluid cells on the lattice")
    alpha = walled(f.alpha, fluid, None)
    p = walled(f.p, fluid, None)
    mu = walled(f.mu, fluid, None)
    da_dy, da_dx = np.gradient(alpha, dx)
    ux, uy = walled(f.ux, fluid, 0.0), walled(f.uy, fluid, 0.0)
    if start is not None:  # the transposed part from the step's starting velocity
        ux0, uy0 = walled(start.ux, fluid, 0.0), walled(start.uy, fluid, 0.0)
    else:
        ux0, uy0 = ux, uy
    dux_dy, dux_dx = np.gradient(ux0, dx)
    duy_dy, duy_dx = np.gradient(uy0, dx)
    div = dux_dx + duy_dy
    # pressure and the transposed part at the cells (central differences)
    sxx, syy = mu * (dux_dx - 2.0 * div / 3.0) - p, mu * (duy_dy - 2.0 * div / 3.0) - p
    tx = -(sxx * da_dx + mu * duy_dx * da_dy)
    ty = -(mu * dux_dy * da_dx + syy * da_dy)
    # the Laplacian part on the faces, each face's force shared by its two cells
    lx, ly = _face_laplacian(alpha, ux, uy, mu)
    tx, ty = tx + lx / dx**2, ty + ly / dx**2  # (nN/um) / area: times area below
    band = fluid & ((da_dx != 0.0) | (da_dy != 0.0) | (lx != 0.0) | (ly != 0.0))
    if not band.any():
        raise InputError("diffuse force", "alpha", "a cell (an interface band) in the fluid")
    tx, ty = tx[band], ty[band]
    gx, gy = da_dx[band], da_dy[band]
    p_mean = float(np.sum(p[band] * np.hypot(gx, gy)) / np.sum(np.hypot(gx, gy)))
    rows, cols = np.nonzero(band)
    area = dx * dx
    return BandForce(
        rows, cols, np.column_stack([tx, ty]) * area, np.column_stack([gx, gy]) * area, p_mean
    )


def diffuse_force(f: MixtureFields, dx: float) -> tuple[np.ndarray, float]:
    """``F = -sum sigma . grad(alpha) dx^2`` (nN/um) and the load (module docstring) of the
    fields ``f`` on a lattice of spacing ``dx`` (um) (:func:`band_force`)."""
    band = band_force(f, dx)
    return band.total, float(np.linalg.norm(band.load, axis=1).sum())


def cell_balance(
    folder_1: Path,
    folder_2: Path,
    layout: Layout,
    cell: str,
    rho_cell: float,
    rho_medium: float,
    mu_medium: float,
) -> CellBalance:
    """:class:`CellBalance` between the consecutive steps written in ``folder_1`` and
    ``folder_2``: densities nN s^2/um^4, ``mu_medium`` kPa s."""
    dt = float(folder_2.name) - float(folder_1.name)
    if dt <= 0:
        raise InputError(folder_2, "time", f"a time after {folder_1.name}", folder_2.name)
    args = (layout, cell, rho_cell, rho_medium, mu_medium)
    f1, f2 = mixture_fields(folder_1, *args), mixture_fields(folder_2, *args)

    def momentum(f: MixtureFields) -> np.ndarray:
        w = np.nan_to_num(f.alpha * f.rho, nan=0.0)
        return np.array([np.nansum(w * f.ux), np.nansum(w * f.uy)]) * layout.dx**2

    force, load = diffuse_force(f2, layout.dx)
    explicit = band_force(f2, layout.dx, start=f1).total
    remainder = convection_remainder(f1, f2, layout.dx, dt)
    return CellBalance(force, (momentum(f2) - momentum(f1)) / dt, load, explicit, remainder)
