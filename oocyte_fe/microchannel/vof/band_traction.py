"""The diffuse interface's force put on the cell's outline as a traction: the FE cell's load.

The force of the medium on the cell is the band integral ``F = -sum sigma . grad(alpha) dA``
(:mod:`.diffuse_force`; it balances the cell's momentum rate within 0.1-0.8 % on 12.5 um,
where the traction read next to the smeared interface, :mod:`.traction`, misses by 3-9 %).
Each band cell's share ``f_c = -(sigma + p_m I) . grad(alpha) dA`` (nN/um; ``p_m`` the band's
mean pressure; each face's Laplacian part halved between its two cells) sits at the polar
angle ``theta_c`` about the centroid of the ``alpha = 0.5``
contour. The force per unit angle is the truncated Fourier series of these point forces::

    c_k = (1 / 2 pi) sum_c f_c exp(-i k theta_c),      |k| <= K
    F(theta) = sum_k c_k exp(i k theta)      (nN/um per rad),   t(theta) = F(theta) / R  (kPa)

``R`` the radius of the contour's area, ``K = floor(2 pi R / (4 dx))`` (harmonics of at least
four lattice spacings: the band resolves no finer), written at ``M = 4 K + 4`` equally spaced
angles on the contour (each row's length ``2 pi R / M``). Every harmonic up to ``K`` is the
band's own, none is smoothed (a Gaussian of one lattice spacing would take 6 % off the
``cos 2 theta`` mode that makes the ellipse at 12.5 um), and the rows' net force is
``2 pi c_0 = sum_c f_c`` exactly; the mean pressure's share ``-p_m sum grad(alpha) dA`` (zero
for a band away from walls) is added to ``c_0``, so ``sum t ds = F``: the FE cell takes the force
whose momentum budget is checked.

The solver takes the transposed part of the viscous stress, ``div(mu dev2(grad U^T))``,
explicitly, from the step's starting velocity; on the finer meshes it alternates from step to
step (0.3-2.4 % of the load between the two readings, docs/elastic_cell_in_flow.md). Given
``start``, the fields of the step before, the band's force takes that part from them as the
solver did, and balances the cell's momentum over that step
(:func:`.diffuse_force.cell_balance`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.control_volume import mixture_fields
from oocyte_fe.microchannel.vof.diffuse_force import band_force
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.traction import Traction, cell_contour, lattice, polar, signed_area

HARMONIC_CELLS = 4.0  # the shortest harmonic kept, in lattice spacings


@dataclass(frozen=True)
class Fluids:
    """What the mixture's stress needs besides the fields: the densities of the cell and the
    medium (nN s^2/um^4) and the medium's viscosity (kPa s; the cell's is the solver's
    ``nu1``)."""

    rho_cell: float
    rho_medium: float
    mu_medium: float


def band_traction(
    folder: Path, layout: Layout, fluids: Fluids, cell: str = "cell", start: Path | None = None
) -> Traction:
    """The band's force as a traction on the contour (module docstring) from the fields of the
    time ``folder``; ``start``: the time folder of the solver step before it (the transposed
    viscous part from its velocity)."""
    args = (layout, cell, fluids.rho_cell, fluids.rho_medium, fluids.mu_medium)
    f = mixture_fields(folder, *args)
    band = band_force(f, layout.dx, start=None if start is None else mixture_fields(start, *args))
    x, y, _, _ = lattice(layout)
    ring = cell_contour(f.alpha, x, y, folder, cell)
    centroid, at = polar(ring, np.column_stack([x[band.cols], y[band.rows]]))
    radius = np.sqrt(signed_area(ring) / np.pi)
    harmonics = int(2.0 * np.pi * radius / (HARMONIC_CELLS * layout.dx))
    if harmonics < 2:
        raise InputError(folder, f"alpha.{cell}", "a cell at least 3 lattice spacings across")
    k = np.arange(-harmonics, harmonics + 1)
    theta_c = np.radians(at)
    coeff = np.exp(-1j * np.outer(k, theta_c)) @ band.load / (2.0 * np.pi)  # (2K+1, 2)
    coeff[harmonics] += (band.total - band.load.sum(axis=0)) / (2.0 * np.pi)
    rows = 4 * harmonics + 4
    theta = 2.0 * np.pi * np.arange(rows) / rows
    per_angle = np.real(np.exp(1j * np.outer(theta, k)) @ coeff)  # (rows, 2) nN/um per rad
    _, ring_angle = polar(ring, ring[:-1])
    order = np.argsort(ring_angle)
    r_ring = np.linalg.norm(ring[:-1] - centroid, axis=1)[order]
    r = np.interp(np.degrees(theta), ring_angle[order], r_ring, period=360.0)
    u = np.column_stack([np.cos(theta), np.sin(theta)])  # the rows' normals: radial
    return Traction(
        float(folder.name),
        np.degrees(theta),
        centroid + r[:, None] * u,
        u,
        np.full(rows, 2.0 * np.pi * radius / rows),
        per_angle / radius,
        centroid,
    )
