"""Small structured meshes for FE verification (exact geometry maps, no gmsh needed)."""

from __future__ import annotations

import numpy as np
from skfem import MeshTri


def quarter_annulus(a: float, b: float, n_r: int, n_t: int) -> MeshTri:
    """Quarter annulus ``a <= r <= b`` in the first quadrant: x = r sin(t), y = r cos(t).

    Boundaries: ``inner``, ``outer``, ``axis`` (x = 0), ``symmetry`` (y = 0); one subdomain
    ``solid``. Axisymmetric it is half a thick spherical shell; plane strain a quarter tube.
    """
    m = MeshTri.init_tensor(np.linspace(a, b, n_r + 1), np.linspace(0.0, np.pi / 2, n_t + 1))
    r, t = m.p
    m = MeshTri(np.array([r * np.sin(t), r * np.cos(t)]), m.t)
    tol = 1e-9 * b
    h = (b - a) / n_r
    return m.with_boundaries(
        {
            "inner": lambda x: np.hypot(*x) < a + 0.1 * h,
            "outer": lambda x: np.hypot(*x) > b * np.cos(np.pi / 4 / n_t) - 0.1 * h,
            "axis": lambda x: np.abs(x[0]) < tol,
            "symmetry": lambda x: np.abs(x[1]) < tol,
        }
    ).with_subdomains({"solid": lambda x: np.ones(x.shape[1], dtype=bool)})


def rectangle(width: float, height: float, nx: int, ny: int, grade: float = 1.0) -> MeshTri:
    """Rectangle [0, width] x [0, height]; ``grade > 1`` clusters elements towards (0, height).

    Boundaries ``left``, ``right``, ``bottom``, ``top``; subdomain ``solid``.
    """
    s = np.linspace(0.0, 1.0, nx + 1) ** grade
    y = 1.0 - np.linspace(0.0, 1.0, ny + 1) ** grade
    m = MeshTri.init_tensor(width * s, height * np.sort(y))
    tol = 1e-9 * max(width, height)
    return m.with_boundaries(
        {
            "left": lambda x: np.abs(x[0]) < tol,
            "right": lambda x: np.abs(x[0] - width) < tol,
            "bottom": lambda x: np.abs(x[1]) < tol,
            "top": lambda x: np.abs(x[1] - height) < tol,
        }
    ).with_subdomains({"solid": lambda x: np.ones(x.shape[1], dtype=bool)})
