"""Single-phase slit flow on the VOF solver, for verification against the closed forms.

A planar slit of half-height h and length L (um) is fed a plane-Poiseuille profile of mean
velocity U at x = 0 and left at p = 0 at x = L; every cell holds the first phase. Once steady,
the pressure gradient ``G = -dp/dx`` is fitted on the centre line over the second half of the
slit (the inlet profile of a shear-thinning fluid redevelops within about h), and the flow
rate per unit depth ``q = 2 h U`` is compared with the exact ``q(G)`` (Poiseuille for a
Newtonian fluid, the Rabinowitsch integral otherwise). A second, inert phase with the same
properties is carried because the solver needs two.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import Numerics, Phase, VofSetup, write_case
from oocyte_fe.microchannel.vof.geometry import Layout, slit_layout
from oocyte_fe.microchannel.vof.monitor import SolverMonitor
from oocyte_fe.microchannel.vof.post import centreline_gradient, column_profile, time_directories
from oocyte_fe.microchannel.vof.runner import OpenFoam, run_solver, run_utility

PA_PER_M = 1e-9  # Pa/m -> kPa/um


@dataclass(frozen=True)
class SlitResult:
    """Steady slit flow: G (kPa/um), q (um^2/s), centre-column profile y (um), u (um/s)."""

    layout: Layout
    pressure_gradient: float
    flow_rate: float
    y: np.ndarray
    u: np.ndarray
    steady_change: float  # relative change of G between the last two writes


def slit_flow(
    foam: OpenFoam,
    directory: Path,
    rheology: Rheology,
    density: float,
    half_height: float,
    length: float,
    dx: float,
    velocity: float,
    numerics: Numerics,
    nice: int = 0,
    ranks: int = 1,
) -> SlitResult:
    """Write, mesh and run the slit (``ranks`` > 1: decomposed, MPI); return the steady G, q
    and the velocity profile."""
    layout = slit_layout(length, half_height, dx, velocity)
    phases = (Phase("medium", rheology, density), Phase("inert", rheology, density))
    case = write_case(VofSetup(layout, phases, (), numerics), directory, ranks)
    run_utility(foam, case, ["blockMesh"], nice)
    monitor = SolverMonitor(numerics.end_time, numerics.time_step, dx * 1e-6, 1.5 * velocity * 1e-6)
    run_solver(foam, case, monitor, ranks=ranks, nice=nice)
    times = time_directories(case)
    window = (0.5 * length, length - 2 * dx)
    gradients = [centreline_gradient(folder, layout, window) for _, folder in times[-2:]]
    y, u = column_profile(times[-1][1], layout, 0.75 * length)
    return SlitResult(
        layout,
        gradients[-1] * PA_PER_M,
        2.0 * half_height * velocity,
        y,
        u * 1e6,
        abs(gradients[-1] / gradients[0] - 1.0),
    )
