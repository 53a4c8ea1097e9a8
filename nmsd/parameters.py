"""NMSD constants in one consistent unit system (um, nN, s), validated where they enter.

The spring law (eq 3) acts on the link strain ``dl = (l - l0) / l0`` (dimensionless), so
``k1`` and ``k2`` are forces (nN), as the paper's printed unit "N" implies, and the
constraint ``k2 >= 50 k1`` (eq 8) compares like with like. Damping (eq 6): ``d0`` in
nN s/um, ``d1`` in nN s/um^2, per node (``damping = "nodal"``, eq 6 as printed) or per link
(``"link"``, a Voigt dashpot along each link, Fig. 3); see :mod:`nmsd.damping`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

from nmsd.damping import READINGS
from oocyte_fe import checks
from oocyte_fe.errors import InputError

WATER_DENSITY = 1.0e-12
"""Cytoplasm density taken as water, 1000 kg/m^3, in nN s^2/um^4 (mass unit 1e-3 kg per um^3)."""


MAGNITUDES = {name: (*checks.QUANTITIES["force_nN"][:2], " nN") for name in ("k1", "k2")}
"""Physical bounds of the spring coefficients (forces, nN); the other constants are 0 or of a
magnitude in [checks.TINY, checks.HUGE] (a denormal or 1e308 is a typing slip, not a value)."""


@dataclass(frozen=True)
class NmsdParameters:
    """Spring, damper and mass constants of the lattice.

    k1: linear coefficient of the link force, nN (per unit strain).
    k2: cubic coefficient of the link force, nN (per unit strain cubed).
    dl_c: critical link strain above which the force continues linearly (eqs 4-5), > 0.
    d0: velocity damping per node (or per link), nN s/um.
    d1: displacement-velocity damping per node (or per link), nN s/um^2.
    node_mass: mass of each node, nN s^2/um (= 1e-3 kg); 0 makes the model first order.
    damping: "nodal" (eq 6 as printed) or "link" (Voigt dashpots along the links).
    area_stiffness: optional cell area term (not in seed 000), dimensionless: the cell
        energy 1/2 kappa A0 (A/A0 - 1)^2 with kappa = area_stiffness k1 / h (nN/um, h the
        lattice spacing); 0 (default) is the paper's model. See :mod:`nmsd.area`.
    zona_stiffness_ratio: optional ZP ring (not in the lattice of seed 000), dimensionless
        > 0: k1 and k2 of the links whose midpoint lies beyond ``zona_inner_radius_um`` are
        multiplied by it (E_zp / E_cyto); 1 (default) is the paper's uniform lattice.
    zona_inner_radius_um: inner radius of the ZP ring, um (used when the ratio is not 1;
        checked against the lattice in :func:`nmsd.zona.zona_link_factor`).
    """

    k1: float = 100.0
    k2: float = 5000.0
    dl_c: float = 0.3
    d0: float = 10.0
    d1: float = 0.1
    node_mass: float = 3.5e-9
    damping: str = "nodal"
    area_stiffness: float = 0.0
    zona_stiffness_ratio: float = 1.0
    zona_inner_radius_um: float = 0.0
    source: str = "NmsdParameters"

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name in ("source", "damping"):
                continue
            value = checks.number(self.source, f.name, getattr(self, f.name))  # not a bool
            low, high, unit = MAGNITUDES.get(f.name, (checks.TINY, checks.HUGE, ""))
            if value != 0 and not low <= abs(value) <= high:
                raise InputError(
                    self.source, f.name, f"0 or a magnitude in [{low:g}, {high:g}]{unit}", value
                )
        for name in ("k1", "k2", "d0", "d1", "area_stiffness", "zona_inner_radius_um"):
            if getattr(self, name) < 0:
                raise InputError(self.source, name, ">= 0", got=getattr(self, name))
        if self.zona_stiffness_ratio <= 0:
            raise InputError(
                self.source, "zona_stiffness_ratio", "a ratio > 0", got=self.zona_stiffness_ratio
            )
        if self.dl_c <= 0:
            raise InputError(self.source, "dl_c", "a critical strain > 0", got=self.dl_c)
        if self.node_mass < 0:
            raise InputError(self.source, "node_mass", "a mass >= 0", got=self.node_mass)
        if self.damping not in READINGS:
            raise InputError(self.source, "damping", f"one of {READINGS}", got=self.damping)
        if self.k1 + self.k2 <= 0:
            raise InputError(self.source, "k1/k2", "a positive spring stiffness")

    def with_values(self, **values: float) -> NmsdParameters:
        """A copy with some constants replaced (validated again)."""
        return replace(self, **values)


def node_mass_for(diameter_um: float, n_nodes: int, density: float = WATER_DENSITY) -> float:
    """Mass per node of a sphere of the given diameter shared by ``n_nodes``, nN s^2/um.

    ``m = density pi d^3 / 6 / n_nodes``.
    """
    diameter_um = checks.number("node_mass_for", "diameter_um", diameter_um, ge=1e-3, le=1e6)
    n_nodes = int(checks.number("node_mass_for", "n_nodes", n_nodes, ge=1, integer=True))
    density = checks.number("node_mass_for", "density", density, ge=1e-30, le=1e6)
    return density * math.pi * diameter_um**3 / 6.0 / n_nodes
