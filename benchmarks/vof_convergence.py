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
* ``cell``: 1 x 24 with Newtonian cell phases (at Table 3's eta_inf, at dt and dt/2; and at
  46 Pa s, near rigid): does the number depend on the cell's viscosity?
* ``alpha``: 1 x 24 with 2 alpha sub-cycles, and with interface compression cAlpha = 0.5.
* ``dt``: 1 x 24 at dt, dt/2 and dt/4 (the limit dt -> 0 of 1 - b/a at x = 0, the factor by
  which its differences shrink and the observed order, :mod:`.vof.extrapolation`, are
  printed after the table), and 1 x 48 at dt/2.
* ``compression``: 1 x 24 with interface compression cAlpha = 0.5 at dt and dt/2.
* ``parity``: 1 x 3 and 1 x 24 on meshes with an even and an odd number of cells across the
  channel (dx = 12.5, 11.9, 10.4, 10 um): the dx = 10 um outlier.

    nice -n 10 python benchmarks/vof_convergence.py --study chosen   # 1 x 24, dt, dt/2: 4 CPU-min
    nice -n 10 python benchmarks/vof_convergence.py --study correctors parity
    nice -n 10 python benchmarks/vof_convergence.py --study dt   # ~10 CPU-min

(``MULESCorr``/``nAlphaCorr``, semi-implicit MULES, are not read by v1912's multiphaseInterFoam:
``benchmarks/vof_alpha_keywords.py`` shows it.)
"""

from __future__ import annotations

import argparse
import resource
import tempfile
from pathlib import Path

from oocyte_fe.errors import SolverError
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import Numerics, Phase
from oocyte_fe.microchannel.vof.extrapolation import richardson
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
    """Each study: (label, dx um, dt s, Numerics keywords; ``cell``: Newtonian viscosities of
    the ZP and the cytoplasm in Pa s in place of the capped Carreau phases)."""
    fast = {"pressure_rel_tol": 0.05}  # the correctors before the last: GAMG to 5 %
    c24 = {"correctors": 24, **fast}
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
        "cell": [
            ("1 x 24, Newtonian eta_inf", 12.5, 1e-6, {**c24, "cell": (3.371, 1.368)}),
            ("1 x 24, Newtonian eta_inf", 12.5, 5e-7, {**c24, "cell": (3.371, 1.368)}),
            ("1 x 24, Newtonian 46 Pa s", 12.5, 1e-6, {**c24, "cell": (46.0, 46.0)}),
        ],
        "alpha": [
            ("1 x 24, 2 alpha sub-cycles", 12.5, 1e-6, {**c24, "alpha_subcycles": 2}),
            ("1 x 24, cAlpha 0.5", 12.5, 1e-6, {**c24, "compression": 0.5}),
        ],
        "dt": [
            *[("1 x 24", 12.5, 1e-6 / k, c24) for k in (1, 2, 4)],
            ("1 x 48", 12.5, 5e-7, {**c24, "correctors": 48}),
        ],
        "compression": [
            ("1 x 24, cAlpha 0.5", 12.5, dt, {**c24, "compression": 0.5}) for dt in (1e-6, 5e-7)
        ],
        "parity": [
            (f"1 x {n}, {round(250 / dx)} cells across", dx, 1e-6, kw)
            for n, kw in ((3, {}), (24, c24))
            for dx in (12.5, 250 / 21, 250 / 24, 10.0)
        ],
    }


def _phases(cell: tuple[float, float] | None) -> tuple[Phase, Phase, Phase]:
    medium, zp, cytoplasm = seed_phases()
    if cell is None:
        return medium, zp, cytoplasm
    newtonian = [Rheology.of("newtonian", mu=mu * 1e-3) for mu in cell]  # Pa s -> kPa s
    return (
        medium,
        Phase(zp.name, newtonian[0], zp.density),
        Phase(cytoplasm.name, newtonian[1], cytoplasm.density),
    )


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
    at_junction: dict[tuple[str, float], float] = {}  # (label, dt): 1 - b/a at x = 0
    with tempfile.TemporaryDirectory() as tmp:
        for k, (label, dx, dt, spec) in enumerate(run for s in args.study for run in table[s]):
            kw = dict(spec)
            cell = kw.pop("cell", None)
            numerics = Numerics(time_step=dt, end_time=end, write_interval=end / args.writes, **kw)
            sweeps = numerics.outer_correctors * numerics.correctors * 1e-6 / dt
            setup = junction_setup(JunctionGeometry(), dx, *_phases(cell), u, u, numerics)
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
            at_junction[(label, dt)] = 1 - run.history.at_x(0.0)[1]
    series = [at_junction.get(("1 x 24", 1e-6 / k)) for k in (1, 2, 4)]
    if all(v is not None for v in series):
        ex = richardson(series)  # type: ignore[arg-type]
        print(
            f"\n1 x 24, 1 - b/a at x = 0 over dt, dt/2, dt/4: {series[0]:.5f}, {series[1]:.5f}, "
            f"{series[2]:.5f}; changes {100 * (series[1] / series[0] - 1):+.1f} %, "
            f"{100 * (series[2] / series[1] - 1):+.1f} %; differences shrink by q = "
            f"{ex.factor:.3f} per halving (observed order {ex.order:.2f}; nan: alternating); "
            f"limit dt -> 0 {ex.limit:.5f} (b/a {1 - ex.limit:.5f})"
        )


if __name__ == "__main__":
    main()
