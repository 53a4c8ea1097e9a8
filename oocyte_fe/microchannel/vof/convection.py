"""The momentum convection as the solver discretises it, and its part in the cell's budget.

The cases convect momentum with ``div(rhoPhi,U) Gauss linearUpwind grad(U)``: the velocity
carried through a face is the upwind cell's value continued by half a cell of its central
gradient (uniform lattice, spacing ``dx``, um)::

    u_f = u_L + (dx/2) (du/dn)_L    if the flux goes from L to R
    u_f = u_R - (dx/2) (du/dn)_R    otherwise

In the continuum the convection drops out of the cell's budget: with ``alpha`` carried by the
flow, ``d/dt sum alpha rho u dA = -sum sigma . grad(alpha) dA`` (:mod:`.diffuse_force`). On
the lattice it does not quite: the solver's step ``(rho u)_2 - (rho u)_1 = dt (-C + div
sigma)`` (``C`` the convection above, ``fvm::div(rhoPhi, U)``: the mass flux ``rhoPhi`` of
the step's start, the face values of its end) summed with the cell's fraction ``alpha_2`` leaves::

    d/dt sum alpha rho u dA  =  F  +  D
    D = -sum alpha_2 C dA  +  sum (alpha_2 - alpha_1) rho_1 u_1 dA / dt      (nN/um)

``D`` the convection's remainder: zero in the continuum and for a velocity uniform over the
band; across a band two cells wide it is the part of the budget's miss that the force ``F``
cannot see. Measured on the cases' runs (200-900 hPa, 12.5 and 6.25 um): with it the budget
of the FE's load closes to 0.07-0.47 % where it missed by 0.38-1.07 %
(docs/elastic_cell_in_flow.md). The mass flux through a face is
taken as the mean of its two cells' normal velocity times their mean density at the step's
start (the solver's ``rhoPhi`` from its own face fluxes and isoAdvector's, which are not read).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from oocyte_fe.microchannel.vof.walls import face_pairs, walled

if TYPE_CHECKING:  # the box's module uses the face values here
    from oocyte_fe.microchannel.vof.control_volume import MixtureFields


def linear_upwind(
    u_lo: np.ndarray,
    u_hi: np.ndarray,
    slope_lo: np.ndarray,
    slope_hi: np.ndarray,
    flux: np.ndarray,
    dx: float,
) -> np.ndarray:
    """The face value of ``linearUpwind grad(U)`` (module docstring) between cells ``lo`` and
    ``hi`` (``hi`` on the side the face's normal points to); ``slope_*`` the cells' central
    derivative along that normal (1/s for u in um/s, dx in um), ``flux`` > 0 from lo to hi."""
    return np.where(flux > 0.0, u_lo + 0.5 * dx * slope_lo, u_hi - 0.5 * dx * slope_hi)


def convection(
    f: MixtureFields, dx: float, carrier: MixtureFields
) -> tuple[np.ndarray, np.ndarray]:
    """Each lattice cell's net outflow of momentum ``C dA = sum_faces rho_f (v_f . n) u_f ds``
    (x and y components, nN/um per unit depth): ``u_f`` the face values of ``f`` (module
    docstring), the mass flux ``rho_f v_f . n`` that of ``carrier`` (the step's start, as the
    solver's ``rhoPhi``); faces next to a wall carry nothing."""
    fluid = np.isfinite(f.alpha)
    ux, uy = walled(f.ux, fluid, 0.0), walled(f.uy, fluid, 0.0)
    vx, vy = walled(carrier.ux, fluid, 0.0), walled(carrier.uy, fluid, 0.0)
    rho = walled(carrier.rho, fluid, None)
    d_dy = {k: np.gradient(u, dx, axis=0) for k, u in (("x", ux), ("y", uy))}
    d_dx = {k: np.gradient(u, dx, axis=1) for k, u in (("x", ux), ("y", uy))}
    out = [np.zeros_like(ux), np.zeros_like(ux)]
    for axis, normal, slopes in ((0, vy, d_dy), (1, vx, d_dx)):  # faces normal to y, to x
        lo, hi = face_pairs(axis)
        un = np.where(fluid[lo] & fluid[hi], 0.5 * (normal[lo] + normal[hi]), 0.0)
        rho_f = 0.5 * (rho[lo] + rho[hi])
        for k, (u, slope) in enumerate(((ux, slopes["x"]), (uy, slopes["y"]))):
            u_f = linear_upwind(u[lo], u[hi], slope[lo], slope[hi], un, dx)
            q = rho_f * un * u_f * dx  # out of lo, into hi
            out[k][lo] += q
            out[k][hi] -= q
    return out[0], out[1]


def convection_remainder(f1: MixtureFields, f2: MixtureFields, dx: float, dt: float) -> np.ndarray:
    """``D`` of the module docstring (nN/um) for the step from the fields ``f1`` to ``f2``
    (``dt`` s, lattice spacing ``dx`` um)."""
    cx, cy = convection(f2, dx, carrier=f1)
    alpha_2 = np.nan_to_num(f2.alpha)
    d_alpha = np.nan_to_num(f2.alpha - f1.alpha)
    carried = [np.nansum(d_alpha * f1.rho * u) * dx * dx / dt for u in (f1.ux, f1.uy)]
    return np.array([carried[0] - np.sum(alpha_2 * cx), carried[1] - np.sum(alpha_2 * cy)])
