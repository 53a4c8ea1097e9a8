"""The oocyte at the junction (seed 001, Model II): set up, run and measure one pressure.

Two models. ``three_phase_mules`` (the seed's reading, ``multiphaseInterFoam``): the culture
medium (Newtonian), the zona pellucida (ZP) shell and the cytoplasm core (both Carreau,
zero-shear viscosity capped, :func:`.rheology.cap_zero_shear`). ``liquid_cell_isoadvector``
(``interIsoFoam``): the medium and the whole cell as ONE phase of one such curve. The
driving pressure ``p`` sets the mean velocity of each inlet through the device's calibrated
hydraulic resistance (:class:`~oocyte_fe.microchannel.channel.Channel`: ``U = p R^2/(8 mu L)``,
nearly all the resistance is in the tubing, so the box sets the flow rate, not the pressure at
the junction): inlet A carries ``U(p)``, inlet B ``b_ratio U(p)``, both as plane-Poiseuille
profiles. The cell starts at rest-shape 500 um before the junction centre. The measured axis
ratio is the one when the cell's centroid crosses the junction centre (x = 0): from the
solver's per-step moments, the value at x = 0 of a line fitted over the centroid positions
within +-``READ_WINDOW_UM`` (:meth:`.post.CellHistory.near_x`); and the smallest one over
the run.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import (
    Disk,
    Numerics,
    Outline,
    Phase,
    VofSetup,
    write_case,
)
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.isoadvector import INTER_ISO_FOAM
from oocyte_fe.microchannel.vof.monitor import Limits, SolverMonitor
from oocyte_fe.microchannel.vof.post import (
    CellHistory,
    cell_history,
    moment_trace,
    time_directories,
)
from oocyte_fe.microchannel.vof.rheology import cap_zero_shear
from oocyte_fe.microchannel.vof.runner import (
    OpenFoam,
    project_initial_flow,
    run_solver,
    run_utility,
)


@dataclass(frozen=True)
class JunctionRun:
    """One pressure: inputs (velocities in um/s) and the result."""

    case: Path
    velocity_a: float
    velocity_b: float
    n_cells: int
    steps: int
    wall_seconds: float
    history: CellHistory
    ratio_at_junction: float
    time_at_junction: float
    min_ratio: float
    max_courant: float = math.nan  # largest over the run (the solver's log)
    max_interface_courant: float = math.nan
    courant_while_read: float = math.nan  # largest until the centroid passes x = +READ_WINDOW_UM

    @property
    def seconds_per_ms(self) -> float:
        """Wall-clock seconds per simulated millisecond."""
        return self.wall_seconds / (self.history.time[-1] * 1e3)


def junction_setup(
    geometry: JunctionGeometry,
    dx: float,
    medium: Phase,
    zp: Phase,
    cytoplasm: Phase,
    velocity_a: float,
    velocity_b: float,
    numerics: Numerics,
) -> VofSetup:
    """The three-phase junction case: ZP disk (cell diameter) then cytoplasm disk inside."""
    layout = geometry.layout(dx, velocity_a, velocity_b)
    centre = geometry.cell_centre
    disks = (
        Disk(zp.name, centre, 0.5 * geometry.cell_diameter),
        Disk(cytoplasm.name, centre, 0.5 * geometry.cytoplasm_diameter),
    )
    num = replace(numerics, moments=(zp.name, cytoplasm.name))
    return VofSetup(layout, (medium, zp, cytoplasm), disks, num)


def liquid_cell_setup(
    geometry: JunctionGeometry,
    dx: float,
    medium: Phase,
    cell: Phase,
    velocity_a: float,
    velocity_b: float,
    numerics: Numerics,
    outline: np.ndarray | None = None,
) -> VofSetup:
    """The two-phase junction case (``interIsoFoam``): the whole cell (its diameter) as ONE
    phase of one viscosity curve in the medium (:mod:`.isoadvector`); with ``outline`` ((k, 2)
    um, about the cell's centre) the cell starts in that shape instead of the disk (the
    deform-recompute passes of :mod:`oocyte_fe.microchannel.elastic_iteration`)."""
    layout = geometry.layout(dx, velocity_a, velocity_b)
    if outline is None:
        disks = (Disk(cell.name, geometry.cell_centre, 0.5 * geometry.cell_diameter),)
    else:
        disks = (Outline(cell.name, np.asarray(outline) + np.array(geometry.cell_centre)),)
    return VofSetup(layout, (medium, cell), disks, replace(numerics, moments=(cell.name,)))


def run_junction(
    foam: OpenFoam,
    directory: Path,
    setup: VofSetup,
    ranks: int = 1,
    nice: int = 0,
    limits: Limits | None = None,
    progress: Callable[[str], None] | None = None,
) -> JunctionRun:
    """Write, mesh, run (stopping at a silent failure) and post-process one pressure."""
    layout, num = setup.layout, setup.numerics
    case = write_case(setup, directory, ranks)
    run_utility(foam, case, ["blockMesh"], nice)
    project_initial_flow(foam, case, num, nice)
    inlets = list(layout.inlets.values())
    u_ref = 1.5 * sum(i.velocity for i in inlets) * 1e-6  # m/s: fastest the inflow can drive
    monitor = SolverMonitor(
        num.end_time, num.time_step, layout.dx * 1e-6, u_ref, limits or Limits()
    )
    start = time.perf_counter()
    run_solver(foam, case, monitor, ranks=ranks, nice=nice, progress=progress, solver=num.solver)
    wall = time.perf_counter() - start
    names = [p.name for p in setup.phases]
    written = names[1:] if num.solver == INTER_ISO_FOAM else names  # 1 - alpha not written
    history = cell_history(case, layout, names[1:], written)
    for _, folder in time_directories(case)[1:-1]:  # face fluxes: only t = 0 and the last kept
        (folder / "phi").unlink(missing_ok=True)
    trace = moment_trace(case, num.moments) if num.moments else history
    t_j, r_j = trace.at_x(0.0)
    if num.moments:
        r_j = trace.near_x(0.0, READ_WINDOW_UM)
    t_read = trace.at_x(READ_WINDOW_UM)[0]  # the last state b/a at x = 0 is read from
    co_read = monitor.largest_courant_until(t_read if math.isfinite(t_read) else math.inf)
    return JunctionRun(
        case,
        inlets[0].velocity,
        inlets[1].velocity,
        layout.n_cells,
        monitor.steps,
        wall,
        history,
        r_j,
        t_j,
        float(min(trace.ratio.min(), history.ratio.min())),
        monitor.largest_courant,
        monitor.largest_interface_courant,
        co_read,
    )


READ_WINDOW_UM = 25.0  # b/a at x = 0: line through the per-step ratios within +-25 um
PA_S, KG_M3 = 1e-3, 1e-15  # Pa s -> kPa s, kg/m^3 -> nN s^2/um^4
VELOCITY_300_HPA = 0.7015e6  # um/s: mean velocity of the calibrated device at 300 hPa


def seed_phases(cap_pa_s: float = 46.0) -> tuple[Phase, Phase, Phase]:
    """Medium, ZP and cytoplasm as the cases read Table 3 (densities 1008/1047/1020 kg/m^3;
    medium 1.66e-3 Pa s; ZP eta0/eta_inf 4617.93/3.371 Pa s, cytoplasm 59.89/1.368 Pa s,
    Carreau lambda = 661 s, n = 0.047 from our Table 2 fit), eta0 capped at ``cap_pa_s``; for
    benchmarks and examples (the cases build theirs from case.toml)."""
    carreau = {"time_constant": 661.0, "n": 0.047}
    cell = [
        Phase(
            name,
            cap_zero_shear(
                Rheology.of("carreau", eta0=eta0 * PA_S, eta_inf=eta_inf * PA_S, **carreau),
                cap_pa_s * PA_S,
            ),
            rho * KG_M3,
        )
        for name, eta0, eta_inf, rho in (
            ("zp", 4617.93, 3.371, 1047.0),
            ("cytoplasm", 59.89, 1.368, 1020.0),
        )
    ]
    medium = Phase("medium", Rheology.of("newtonian", mu=1.66e-3 * PA_S), 1008.0 * KG_M3)
    return medium, cell[0], cell[1]


def mean_velocity(pressure_hpa: float) -> float:
    """Mean inlet velocity (um/s) at a box pressure (hPa): ``U = p R^2/(8 mu L)`` of the
    calibrated device, linear in p (0.7015 m/s at 300 hPa)."""
    return VELOCITY_300_HPA * pressure_hpa / 300.0
