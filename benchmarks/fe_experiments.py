"""Wall time of two FE experiments through the one driver (issue 27, "Speed").

* the aspiration template's layered oocyte (140 um, 15 um ZP, pipette a = 10 um), refined to
  about 20 000 unknowns, 50 output frames of suction 0-200 Pa;
* the plates template's layered oocyte compressed to 30 % of its diameter (12 frames).

Goal of the issue: each under 20 s on one idle core. Printed: unknowns, steps, Newton
iterations, wall and CPU seconds, and each time's ratio to the goal and to the first run in
the same process of the aspiration at a coarse mesh (the baseline: its cost per unknown and
step). Mesh building is left out (the mesh cache is warmed first). Run on one core:
``OMP_NUM_THREADS=1 python benchmarks/fe_experiments.py``.
"""

from __future__ import annotations

import copy
import time

from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.driver import cell_mesh
from oocyte_fe.experiment.templates import TEMPLATES

GOAL_S = 20.0


def aspiration(refine_um: float, frames: int) -> Experiment:
    spec = copy.deepcopy(TEMPLATES["aspiration"])
    spec["cell"]["refine_size_um"] = refine_um
    spec["time"]["frames"] = frames
    return Experiment.model_validate(spec)


def timed(exp: Experiment) -> tuple[float, float, object]:
    cell_mesh(exp)  # warm the mesh cache: the benchmark times the solve
    wall, cpu = time.perf_counter(), time.process_time()
    result = run_experiment(exp)
    return time.perf_counter() - wall, time.process_time() - cpu, result


def main() -> None:
    runs = {
        "aspiration, coarse (baseline)": aspiration(2.0, 10),
        "aspiration, ~20k unknowns, 50 frames": aspiration(0.55, 50),
        "plates to 30 %": Experiment.model_validate(TEMPLATES["plates"]),
    }
    base = None
    print(f"{'experiment':40s} {'unknowns':>9s} {'steps':>6s} {'Newton':>7s} {'wall s':>7s} "
          f"{'cpu s':>7s} {'/goal':>6s} {'us/(dof step)':>14s} {'/base':>6s}")  # fmt: skip
    for name, exp in runs.items():
        wall, cpu, r = timed(exp)
        per = 1e6 * cpu / (r.n_dofs * len(r.steps))
        base = base or per
        print(
            f"{name:40s} {r.n_dofs:9d} {len(r.steps):6d} {r.newton_iterations:7d} "
            f"{wall:7.2f} {cpu:7.2f} {wall / GOAL_S:6.2f} {per:14.2f} {per / base:6.2f}"
            + ("" if r.success else f"  FAILED: {r.reason}")
        )


if __name__ == "__main__":
    main()
