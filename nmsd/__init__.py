"""Nonlinear mass-spring-damper (NMSD) oocyte: the reduced model of seed 000 (Section II.B-D).

A circular focal-plane lattice of point masses linked by cubic-then-linear springs (eqs 2-5)
with nodal strain-dependent damping (eq 6), pressed by a rigid micropipette (eq 1), calibrated
to the force-displacement data of Table II (eqs 7-8), used to predict the spindle offset and
to drive an incremental PID approach (eqs 9-10). Units: um, nN, kPa, s.
"""

from nmsd.errors import NmsdDivergence
from nmsd.lattice import Lattice, circular_lattice
from nmsd.parameters import NmsdParameters
from nmsd.pipette import Pipette
from nmsd.press import PressResult, simulate_press
from oocyte_fe.errors import InputError

__all__ = [
    "Lattice",
    "NmsdDivergence",
    "InputError",
    "NmsdParameters",
    "Pipette",
    "PressResult",
    "circular_lattice",
    "simulate_press",
]
