"""Optional zona pellucida ring in the lattice: stiffer links outside an inner radius.

Seed 000, Section II.C lists the zona pellucida length ``R_zp`` and its modulus ``E_zp`` among
the model's parameters, but the lattice of Section II.B.2 is one uniform material. Here a link
whose midpoint lies farther than ``zona_inner_radius_um`` (um) from the lattice centre (the
origin) belongs to the ZP ring and its spring constants are scaled:

    k1_e = s_e k1,   k2_e = s_e k2,   s_e = zona_stiffness_ratio  if |(r_a + r_b)/2| > R_in
                                      s_e = 1                     otherwise

so its force law (eqs 3-5, :mod:`nmsd.spring`) is ``s_e f(dl)`` with the same critical strain
``dl_c``. ``zona_stiffness_ratio`` (dimensionless, > 0) reads as ``E_zp / E_cyto``; 1 (the
default) is the paper's uniform lattice. Dampers, masses and the area term are not scaled.
Reading of Table I (docs/cases/nmsd_vs_fe.md): ``R_zp`` = 83.597 um is the diameter inside the
ZP, so ``R_in`` = 41.80 um in the 57.81 um radius lattice.
"""

from __future__ import annotations

import numpy as np

from nmsd.lattice import Lattice
from nmsd.parameters import NmsdParameters
from oocyte_fe.errors import InputError


def link_midpoint_radius(lattice: Lattice) -> np.ndarray:
    """Distance of each link's reference midpoint from the lattice centre, um."""
    mid = 0.5 * (lattice.nodes[lattice.edges[:, 0]] + lattice.nodes[lattice.edges[:, 1]])
    return np.hypot(mid[:, 0], mid[:, 1])


def zona_link_factor(lattice: Lattice, params: NmsdParameters) -> np.ndarray:
    """Spring factor ``s_e`` of each link (m,): the ratio in the ZP ring, 1 inside.

    All ones when ``zona_stiffness_ratio`` is 1 (the radius is then not used). Otherwise the
    radius must lie inside the lattice with links on both sides of it.
    """
    factor = np.ones(len(lattice.edges))
    if params.zona_stiffness_ratio == 1.0:
        return factor
    radius = params.zona_inner_radius_um
    r_mid = link_midpoint_radius(lattice)
    ring = r_mid > radius
    if not 0.0 < radius < lattice.radius or ring.all() or not ring.any():
        raise InputError(
            params.source,
            "zona_inner_radius_um",
            f"a radius in (0, {lattice.radius:g}) um with links inside and outside it",
            got=radius,
        )
    factor[ring] = params.zona_stiffness_ratio
    return factor
