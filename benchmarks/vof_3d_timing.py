"""One 3-D coarse timing run of the VOF junction (issue 20): cost per simulated ms in 3-D.

The planar junction (Fig. 6 as read here) extruded into a square duct 250 um deep
(:mod:`oocyte_fe.microchannel.vof.extrude`: spheres for the cell and its cytoplasm, duct
profiles at the inlets, walls front and back), three phases as the cases (eta0 capped at 46 Pa s),
a few fixed steps of dt; prints cells, steps, CPU-s per step and per simulated ms, wall time and
the load average. A timing run, not a validated 3-D result: the first steps start the flow from
rest, and at dx = 25 um the ZP shell (15 um) is below one cell.

    nice -n 10 python benchmarks/vof_3d_timing.py --dx 25 --steps 60
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.vof.casewriter import Numerics
from oocyte_fe.microchannel.vof.extrude import (
    extruded_centres,
    set_inlet_profiles,
    write_extruded_case,
)
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import junction_setup, mean_velocity, seed_phases
from oocyte_fe.microchannel.vof.monitor import SolverMonitor
from oocyte_fe.microchannel.vof.runner import find_openfoam, run_solver, run_utility


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx", type=float, default=25.0, help="um")
    ap.add_argument("--depth", type=float, default=250.0, help="um")
    ap.add_argument("--steps", type=int, default=60)
    ap.add_argument("--dt", type=float, default=1e-6, help="s")
    ap.add_argument("--pressure", type=float, default=300.0, help="hPa")
    ap.add_argument("--ranks", type=int, default=1)
    args = ap.parse_args()

    foam = find_openfoam()
    u = mean_velocity(args.pressure)
    end = args.steps * args.dt
    numerics = Numerics(time_step=args.dt, end_time=end, write_interval=end)
    setup = junction_setup(JunctionGeometry(), args.dx, *seed_phases(), u, u, numerics)
    with tempfile.TemporaryDirectory() as tmp:
        case = write_extruded_case(setup, Path(tmp) / "case3d", args.depth, args.ranks)
        run_utility(foam, case, ["blockMesh"], 10)
        centres = set_inlet_profiles(foam, case, setup.layout, args.depth)
        expected = extruded_centres(setup.layout, args.depth)
        order_error = float(np.max(np.abs(centres - expected)))
        monitor = SolverMonitor(end, args.dt, args.dx * 1e-6, 2.25 * 2 * u * 1e-6)
        cpu0, wall0 = _cpu_children(), time.perf_counter()
        run_solver(foam, case, monitor, ranks=args.ranks, nice=10)
        cpu, wall = _cpu_children() - cpu0, time.perf_counter() - wall0
    load = os.getloadavg()
    ms = end * 1e3
    print(f"3-D junction, dx = {args.dx:g} um, depth {args.depth:g} um, {args.pressure:g} hPa")
    print(f"cells {len(centres)}; cell order vs blockMesh: {order_error:.1e} um")
    print(f"steps {monitor.steps}, dt {args.dt:g} s, max Courant {monitor.courant:.3g}")
    print(
        f"CPU {cpu:.1f} s ({cpu / monitor.steps:.3f} s/step, "
        f"{cpu / ms:.0f} CPU-s per simulated ms); "
        f"wall {wall:.1f} s ({wall / ms:.0f} s per ms), {args.ranks} rank(s)"
    )
    print(f"load average (1, 5, 15 min): {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")


if __name__ == "__main__":
    main()
