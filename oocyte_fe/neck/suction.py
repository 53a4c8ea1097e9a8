"""The suction load: a pressure drop across the seal the oocyte makes with the pipette wall.

The oocyte plugs the pipette where it touches the wall; the fluid ahead of that seal is at the
pipette pressure, behind it at the dish pressure. The surface ahead of the seal's rear edge
``z_s`` (current configuration) carries the suction ``-dp`` [kPa] as a follower pressure, so the
net axial pull is ``dp * pi r_s^2`` with ``r_s`` the radius of the surface at ``z_s`` (the seed's
"external force calculated based on the penetration depth", Section 3.2). Before the oocyte
touches the wall there is no seal (the 10 um annular gap leaks) and no suction force.

A point of the surface is "at the wall" when ``R_w(Z) - R < tol`` (um).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from skfem import Basis, FacetBasis

from oocyte_fe.fe.vectorized import FacetOperators
from oocyte_fe.neck.pipette import NeckedPipette


def seal_mask(
    pipette: NeckedPipette, tol_um: float, ramp_um: float | None = None
) -> Callable[[NDArray], NDArray]:
    """``where(x)``: the share (0..1) of the suction on each surface point in the configuration
    ``x`` (2, ...): 1 ahead of the seal's rear edge, 0 behind it, a linear ramp of ``ramp_um``
    (default ``4 tol_um``) across it; all 0 without contact.

    The load must be continuous in ``x`` for Newton to converge (a step mask makes the iterate
    cycle between two masks). So "at the wall" is graded, ``w = clip(1 - gap / tol, 0, 1)``,
    the rear edge is the ``w``-weighted soft minimum of Z,
    ``z_s = -s ln(sum w_i exp(-z_i / s) / sum w_i)`` with ``s = ramp / 4``, and the whole mask
    fades in with ``min(1, sum w_i)`` as the seal forms.
    """
    ramp = 4.0 * tol_um if ramp_um is None else ramp_um
    soft = ramp / 4.0

    def where(x: NDArray) -> NDArray:
        r, z = x[0], x[1]
        w = np.clip(1.0 - (pipette.wall_radius(z) - r) / tol_um, 0.0, 1.0)
        total = float(w.sum())
        if total <= 0.0:
            return np.zeros(r.shape)
        z0 = float(z[w > 0].min())
        z_seal = z0 - soft * np.log(np.sum(w * np.exp(-(z - z0) / soft)) / total)
        return min(1.0, total) * np.clip((z - z_seal) / ramp + 0.5, 0.0, 1.0)

    return where


def axial_dofs(basis: Basis) -> NDArray:
    """All ``u_Z`` dofs of a vector basis (their force entries sum to the net axial force)."""
    return basis.get_dofs(elements=np.arange(basis.mesh.nelements)).all("u^2")


def axial_suction_force(
    fb: FacetBasis,
    z_dofs: NDArray,
    u: NDArray,
    dp_kPa: float,
    mask: NDArray,
) -> float:
    """Net axial force [nN] of the suction ``-dp`` on the surface weighted by ``mask`` (its
    values at the quadrature points of ``fb``, as the solver applied it), ``sum_i f_Z,i``
    (axisymmetric, ring sums included); positive pulls the oocyte towards +Z."""
    f = FacetOperators.of(fb).pressure_force(u, -dp_kPa * mask, axisym=True)
    return float(f[z_dofs].sum())
