"""Mesh and time-step convergence of the VOF junction's axis ratio (issue 20, verification 4).

The quick/Table 4 junction (2-D, three phases, seed_phases: eta0 capped at 46 Pa s) at one
pressure, run until the cell has moved ``--travel`` um, on meshes of ratio 2 (default 25, 12.5,
6.25 um); each reports the ratio b/a when the centroid crosses ``--x`` (um; 0 = the junction
centre), the deformation 1 - b/a there, CPU-seconds and the cell's volume error. With three
meshes: the observed order ``p = log2((f_4h - f_2h)/(f_2h - f_h))`` and the Richardson estimate
``f_h + (f_h - f_2h)/(2^p - 1)`` of the deformation; ``--outer``/``--dt`` repeat the finest
two meshes with another PIMPLE or time-step setting.

    nice -n 10 python benchmarks/vof_convergence.py                  # 300 hPa, 3 meshes
    nice -n 10 python benchmarks/vof_convergence.py --outer 3 --correctors 2
"""

from __future__ import annotations

import argparse
import math
import resource
import tempfile
from pathlib import Path

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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pressure", type=float, default=300.0, help="hPa")
    ap.add_argument("--dx", type=float, nargs="+", default=[25.0, 12.5, 6.25], help="um")
    ap.add_argument("--travel", type=float, default=560.0, help="um of travel at the mean U")
    ap.add_argument(
        "--x", type=float, nargs="+", default=[-200.0, 0.0], help="centroid positions, um"
    )
    ap.add_argument("--dt", type=float, default=1e-6, help="s")
    ap.add_argument("--outer", type=int, default=1)
    ap.add_argument("--correctors", type=int, default=3)
    ap.add_argument("--writes", type=int, default=40)
    args = ap.parse_args()

    foam = find_openfoam()
    u = mean_velocity(args.pressure)
    end = args.travel / u
    numerics = Numerics(
        time_step=args.dt,
        end_time=end,
        write_interval=end / args.writes,
        outer_correctors=args.outer,
        correctors=args.correctors,
    )
    print(
        f"p = {args.pressure:g} hPa, U = {u * 1e-6:.4f} m/s, {end * 1e3:.3f} ms, "
        f"dt = {args.dt:g} s, PIMPLE {args.outer} outer x {args.correctors},"
        f" 1 - b/a when the centroid crosses x = {args.x} um"
    )
    cols = " | ".join(f"1 - b/a at {x:g}" for x in args.x)
    print(
        f"| dx (um) | cells | steps | 1 - b/a at t = 0 | {cols} "
        "| CPU s | CPU s per ms | volume error |"
    )
    print("|---" * (7 + len(args.x)) + "|")
    deformation = []
    with tempfile.TemporaryDirectory() as tmp:
        for dx in args.dx:
            setup = junction_setup(JunctionGeometry(), dx, *seed_phases(), u, u, numerics)
            cpu0 = _cpu_children()
            run = run_junction(foam, Path(tmp) / f"dx{dx:g}", setup, nice=10)
            cpu = _cpu_children() - cpu0
            values = [1.0 - run.history.at_x(x)[1] for x in args.x]
            err = max(abs(e[-1]) for e in run.history.volume_error.values())
            deformation.append(values)
            cells = " | ".join(f"{v:.4f}" for v in values)
            print(
                f"| {dx:g} | {run.n_cells} | {run.steps} | {1 - run.history.ratio[0]:.4f} "
                f"| {cells} | {cpu:.0f} | {cpu / (end * 1e3):.0f} | {err:.1e} |",
                flush=True,
            )
    for k, x in enumerate(args.x):
        if len(deformation) >= 3:
            print(f"x = {x:g} um: {_richardson(*[d[k] for d in deformation[-3:]])}")


def _richardson(f4: float, f2: float, f1: float) -> str:
    """Observed order and Richardson estimate from three meshes h, 2h, 4h (f_4h, f_2h, f_h)."""
    if (f4 - f2) * (f2 - f1) <= 0:
        return "non-monotone over the meshes: no observed order"
    p = math.log2((f4 - f2) / (f2 - f1))
    rich = f1 + (f1 - f2) / (2**p - 1)
    return (
        f"observed order p = {p:.2f}; Richardson 1 - b/a = {rich:.4f} "
        f"(finest {f1:.4f}: {100 * (f1 / rich - 1):+.1f} %)"
    )


if __name__ == "__main__":
    main()
