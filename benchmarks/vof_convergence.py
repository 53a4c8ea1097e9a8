"""Why the VOF junction's deformation depended on dt, and the setting that converges (issue 20).

The quick/Table 4 junction (2-D, three phases, seed_phases: eta0 capped at 46 Pa s) at 300 hPa,
run until the cell has moved ``--travel`` um; each run prints the deformation 1 - b/a when the
cell's centroid crosses x = -300, -150 and 0 um (0 = the junction centre, where Table 4 is
read; the same position in every run, interpolated between writes), the time it gets to x = 0,
and the solver's CPU seconds. The studies (``--study``, several allowed):

* ``schemes``: the cases' old setting (PIMPLE 1 outer x 3 correctors, no momentum predictor)
  at dt and dt/2, with Crank-Nicolson 0.9 in place of Euler, and with the momentum predictor.
* ``correctors``: 1 x N at dt = 1e-6 s for N = 3 ... 48, and 1 x 3 at dt/2: without the
  momentum predictor each pressure corrector is one Jacobi sweep of the (very viscous)
  momentum equation, so what matters is the sweeps per unit time N/dt, not dt.
* ``chosen``: the chosen setting (1 x ``--correctors``) at dt and dt/2: its dt convergence.
* ``parity``: 1 x 3 on meshes with an even and an odd number of cells across the channel
  (dx = 12.5, 11.9, 10.4, 10 um): the dx = 10 um outlier.

    nice -n 10 python benchmarks/vof_convergence.py --study chosen   # 1 x 24, dt, dt/2: 4 CPU-min
    nice -n 10 python benchmarks/vof_convergence.py --study correctors parity
"""

from __future__ import annotations

import argparse
import resource
import tempfile
from pathlib import Path

from oocyte_fe.errors import SolverError
from oocyte_fe.microchannel.vof.casewriter import Numerics
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import (
    junction_setup,
    mean_velocity,
    run_junction,
    seed_phases,
)
from oocyte_fe.microchannel.vof.runner import find_openfoam

POSITIONS = (-300.0, -150.0, 0.0)  # um, centroid x where 1 - b/a is read


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def studies(correctors: int) -> dict[str, list[tuple[str, float, float, dict]]]:
    """Each study: (label, dx um, dt s, Numerics keywords)."""
    fast = {"pressure_rel_tol": 0.05}  # the correctors before the last: GAMG to 5 %
    return {
        "schemes": [
            ("1 x 3, Euler", 12.5, 1e-6, {}),
            ("1 x 3, Euler", 12.5, 5e-7, {}),
            ("1 x 3, Crank-Nicolson 0.9", 12.5, 1e-6, {"ddt": "CrankNicolson 0.9"}),
            ("1 x 3, momentum predictor", 12.5, 1e-6, {"momentum_predictor": True}),
        ],
        "correctors": [
            *[
                (f"1 x {n}", 12.5, 1e-6, {"correctors": n, **(fast if n >= 12 else {})})
                for n in (3, 6, 12, 24, 48)
            ],
            ("1 x 3", 12.5, 5e-7, {}),
        ],
        "chosen": [
            (f"1 x {correctors}", 12.5, dt, {"correctors": correctors, **fast})
            for dt in (1e-6, 5e-7)
        ],
        "parity": [
            (f"1 x 3, {round(250 / dx)} cells across", dx, 1e-6, {})
            for dx in (12.5, 250 / 21, 250 / 24, 10.0)
        ],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", nargs="+", default=["chosen"], choices=list(studies(24)))
    ap.add_argument("--correctors", type=int, default=24, help="the chosen setting: 1 x N")
    ap.add_argument("--pressure", type=float, default=300.0, help="hPa")
    ap.add_argument("--travel", type=float, default=560.0, help="um of travel at the mean U")
    ap.add_argument("--writes", type=int, default=40)
    args = ap.parse_args()

    foam = find_openfoam()
    u = mean_velocity(args.pressure)
    end = args.travel / u
    print(f"p = {args.pressure:g} hPa, U = {u * 1e-6:.4f} m/s, {end * 1e3:.3f} ms simulated")
    cols = " | ".join(f"1 - b/a at x = {x:g}" for x in POSITIONS)
    print(f"| run | dx (um) | dt (s) | sweeps per us | {cols} | t at x = 0 (ms) | CPU s |")
    print("|---" * (6 + len(POSITIONS)) + "|")
    table = studies(args.correctors)
    with tempfile.TemporaryDirectory() as tmp:
        for k, (label, dx, dt, kw) in enumerate(run for s in args.study for run in table[s]):
            numerics = Numerics(time_step=dt, end_time=end, write_interval=end / args.writes, **kw)
            sweeps = numerics.outer_correctors * numerics.correctors * 1e-6 / dt
            setup = junction_setup(JunctionGeometry(), dx, *seed_phases(), u, u, numerics)
            head = f"| {label} | {dx:.4g} | {dt:g} | {sweeps:g} |"
            cpu0 = _cpu_children()
            try:
                run = run_junction(foam, Path(tmp) / f"run{k}", setup, nice=10)
            except SolverError as exc:  # the momentum predictor diverges: say where
                why = str(exc).splitlines()[0].split(" (log:")[0].replace("|", "\\|")
                print(f"{head} {why} |", flush=True)
                continue
            cpu = _cpu_children() - cpu0
            values = " | ".join(f"{1 - run.history.at_x(x)[1]:.5f}" for x in POSITIONS)
            t0 = run.history.at_x(0.0)[0] * 1e3
            print(f"{head} {values} | {t0:.4f} | {cpu:.0f} |", flush=True)


if __name__ == "__main__":
    main()
