"""Parallel speed-up of the VOF junction on MPI ranks (issue 20): serial against N ranks.

The 2-D junction (three phases and PIMPLE 1 x 24 as the cases, eta0 capped at 46 Pa s) at one
pressure for a fixed number of steps, run serial and then decomposed (decomposePar, simple
split along x, ``mpirun -np N``, reconstructPar: all inside the timed solver call); prints
the wall time of
each, the speed-up and parallel efficiency, the CPU seconds, the largest difference of the
cell's axis ratio between the two (they must agree) and the load average before and after:
on a shared machine the speed-up is only meaningful when the load is below the core count.

    nice -n 10 python benchmarks/vof_speedup.py      # dx 5 um, 100 steps of 1 x 24: 2-3 min
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.vof.casewriter import Numerics
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import (
    junction_setup,
    mean_velocity,
    run_junction,
    seed_phases,
)
from oocyte_fe.microchannel.vof.runner import find_openfoam


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx", type=float, default=5.0, help="um")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--correctors", type=int, default=24, help="PIMPLE 1 x N, as the cases")
    ap.add_argument("--dt", type=float, default=1e-6, help="s")
    ap.add_argument("--pressure", type=float, default=300.0, help="hPa")
    ap.add_argument("--ranks", type=int, default=2)
    args = ap.parse_args()

    foam = find_openfoam()
    u = mean_velocity(args.pressure)
    end = args.steps * args.dt
    numerics = Numerics(
        time_step=args.dt,
        end_time=end,
        write_interval=end / 5,
        correctors=args.correctors,
        pressure_rel_tol=0.05,
    )
    setup = junction_setup(JunctionGeometry(), args.dx, *seed_phases(), u, u, numerics)
    print(f"2-D junction, dx = {args.dx:g} um ({setup.layout.n_cells} cells), {args.steps} steps")
    print(f"load average (1, 5, 15 min) before: {_load()}")
    runs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for ranks in (1, args.ranks):
            cpu0 = _cpu_children()
            run = run_junction(foam, Path(tmp) / f"r{ranks}", setup, ranks=ranks, nice=10)
            runs[ranks] = (run, _cpu_children() - cpu0)
            print(
                f"{ranks} rank(s): wall {run.wall_seconds:.1f} s, CPU {runs[ranks][1]:.1f} s, "
                f"load now {_load()}",
                flush=True,
            )
    serial, parallel = runs[1][0], runs[args.ranks][0]
    speedup = serial.wall_seconds / parallel.wall_seconds
    diff = float(np.max(np.abs(serial.history.ratio - parallel.history.ratio)))
    print(
        f"speed-up {speedup:.2f} on {args.ranks} ranks (efficiency {speedup / args.ranks:.0%}); "
        f"max ratio difference {diff:.1e}"
    )


if __name__ == "__main__":
    main()
