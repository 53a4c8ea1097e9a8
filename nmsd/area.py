"""Optional area preservation of the lattice cells (not in seed 000; off by default).

The 8-neighbour square lattice of :mod:`nmsd.lattice` is compressible: at small strain its
links give the 2D moduli (per unit area, ``h`` the grid spacing, ``k1/l0`` the link spring
constant of eq 3)

    C11 = (1 + 1/sqrt 2) k1/h,   C12 = C66 = k1/(sqrt 2 h)

so a uniaxial stretch along a grid axis contracts it sideways by ``C12/C11 = 0.414`` (2D
Poisson ratio, a plane-strain ``nu = 0.29``), far from the incompressible continuum. A device
of mass-spring tissue models restores volume: each cell c (a grid square, or a triangle of a
square that lost a corner at the rim) stores

    E_c = 1/2 kappa A0_c (A_c / A0_c - 1)^2

``A_c`` its current area (shoelace over its corners, counter-clockwise), ``A0_c`` its rest
area (um^2), ``kappa`` (nN/um, an energy per area) the area stiffness. The cell pressure
``p_c = kappa (A_c/A0_c - 1)`` (nN/um) acts on the corners as ``dE/dx_k = p_c dA_c/dx_k``.
At small strain this adds ``kappa`` to C11 and C12 (a 2D Lame lambda): the 2D bulk modulus
grows by ``kappa``, the shear moduli do not change. One area per square cell is the Q1-P0
constraint count (one pressure per quadrilateral, about one per node against two DOFs): the
lattice does not lock as triangles with their own areas would.

``kappa`` is given relative to the link stiffness, ``kappa = area_stiffness * k1 / h``
(``area_stiffness`` dimensionless, ``h`` the shortest rest link), so a calibration that
rescales ``k1`` keeps the ratio of bulk to shear stiffness, i.e. the lattice's Poisson ratio:

    nu_2D = C12/C11 = (1/sqrt 2 + a) / (1 + 1/sqrt 2 + a),   nu (plane strain) = nu_2D / (1 + nu_2D)

(:func:`area_stiffness_for_poisson` inverts it). The cubic term ``k2`` of the links is not
mirrored: at large strain the links stiffen and the ratio falls. Units: um, nN.
The compiled version of the same force and tangent is in :func:`nmsd.assembly.assemble`.
"""

from __future__ import annotations

import math

import numpy as np

from oocyte_fe.errors import InputError

LINK_POISSON_2D = 1.0 / (1.0 + math.sqrt(2.0))
"""2D Poisson ratio C12/C11 of the square lattice with axial and diagonal links (0.414)."""


def poisson_ratio(area_stiffness: float) -> float:
    """Plane-strain Poisson ratio of the small-strain lattice along a grid axis."""
    r = 1.0 / math.sqrt(2.0)
    nu_2d = (r + area_stiffness) / (1.0 + r + area_stiffness)
    return nu_2d / (1.0 + nu_2d)


def area_stiffness_for_poisson(nu: float) -> float:
    """``area_stiffness`` (kappa h / k1) giving the plane-strain Poisson ratio ``nu``.

    ``nu`` between the bare lattice's 0.293 and 0.5 (exclusive); 0.5 needs an infinite term.
    """
    nu_min = LINK_POISSON_2D / (1.0 + LINK_POISSON_2D)
    if not (nu_min <= nu < 0.5):
        raise InputError(
            "area_stiffness_for_poisson", "nu", f"a Poisson ratio in [{nu_min:.4f}, 0.5)", got=nu
        )
    r = 1.0 / math.sqrt(2.0)
    nu_2d = nu / (1.0 - nu)
    return max(0.0, (nu_2d * (1.0 + r) - r) / (1.0 - nu_2d))


def area_kappa(area_stiffness: float, k1: float, spacing_um: float) -> float:
    """kappa = area_stiffness k1 / h, nN/um."""
    return area_stiffness * k1 / spacing_um


def corners(cells: np.ndarray, c: int) -> np.ndarray:
    """Node indices of cell ``c`` (3 or 4, counter-clockwise; -1 pads a triangle)."""
    row = cells[c]
    return row[row >= 0]


def cell_areas(positions: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Signed (counter-clockwise positive) areas of the cells, um^2 (shoelace)."""
    areas = np.zeros(len(cells))
    for c in range(len(cells)):
        k = corners(cells, c)
        x, y = positions[k, 0], positions[k, 1]
        areas[c] = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    return areas


def area_energy(
    positions: np.ndarray, cells: np.ndarray, rest_area: np.ndarray, kappa: float
) -> float:
    """Total area energy sum_c 1/2 kappa A0 (A/A0 - 1)^2, nN um."""
    a = cell_areas(positions, cells)
    return float(np.sum(0.5 * kappa * rest_area * (a / rest_area - 1.0) ** 2))


def area_force(
    positions: np.ndarray, cells: np.ndarray, rest_area: np.ndarray, kappa: float
) -> tuple[np.ndarray, np.ndarray]:
    """Gradient dE/dx (n, 2) in nN (the internal force term of the residual) and the dense
    tangent d2E/dx2 (2n, 2n) in nN/um. Reference for the compiled assembly.

    With ``g_k = dA/dx_k = (y_k+1 - y_k-1)/2``, ``dA/dy_k = (x_k-1 - x_k+1)/2``:
    ``dE/dx = p g``, ``d2E/dx2 = kappa/A0 g g^T + p d2A/dx2``, where
    ``d2A/(dx_k dy_l) = (delta_l,k+1 - delta_l,k-1)/2`` is the only second derivative.
    """
    n = len(positions)
    grad = np.zeros(2 * n)
    tangent = np.zeros((2 * n, 2 * n))
    for c in range(len(cells)):
        k = corners(cells, c)
        m = len(k)
        x, y = positions[k, 0], positions[k, 1]
        area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
        p = kappa * (area / rest_area[c] - 1.0)
        dofs = np.empty(2 * m, dtype=int)
        dofs[0::2], dofs[1::2] = 2 * k, 2 * k + 1
        g = np.empty(2 * m)
        g[0::2] = 0.5 * (np.roll(y, -1) - np.roll(y, 1))
        g[1::2] = 0.5 * (np.roll(x, 1) - np.roll(x, -1))
        h = np.zeros((2 * m, 2 * m))
        for a in range(m):
            h[2 * a, 2 * ((a + 1) % m) + 1] += 0.5
            h[2 * a, 2 * ((a - 1) % m) + 1] -= 0.5
        h = h + h.T
        grad[dofs] += p * g
        tangent[np.ix_(dofs, dofs)] += kappa / rest_area[c] * np.outer(g, g) + p * h
    return grad.reshape(n, 2), tangent
