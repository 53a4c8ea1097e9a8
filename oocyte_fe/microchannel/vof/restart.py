"""A few more solver steps from one written time of a finished run, each one written.

The momentum checks need consecutive steps (:mod:`.control_volume`), the runs write every
``write_interval``. :func:`steps_from` copies ``constant/``, ``system/`` and the written time
into ``<case>/<name>/``, sets ``startTime`` to that time, ``endTime`` ``steps`` time steps
later and writes every step (``writeControl timeStep``), and runs the solver there. The
face fluxes ``phi`` of intermediate writes are not kept by :func:`.junction.run_junction`;
the solver then starts from ``phi = flux(U)``, so use the steps after the first.
"""

from __future__ import annotations

import re
import shutil
from collections.abc import Callable
from pathlib import Path

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.monitor import SolverMonitor
from oocyte_fe.microchannel.vof.post import time_directories
from oocyte_fe.microchannel.vof.runner import OpenFoam, run_solver


def _entry(text: str, key: str) -> str:
    found = re.search(rf"^{key}\s+([^;]+);", text, flags=re.M)
    if not found:
        raise InputError("controlDict", key, "a top-level entry")
    return found.group(1).strip()


def steps_from(
    foam: OpenFoam, case: Path, folder: Path, steps: int, name: str = "steps", nice: int = 0
) -> list[Path]:
    """Run ``steps`` steps of the case's solver from the written time ``folder``; the time
    folders written (one per step, in order), under ``case / name``."""
    if steps < 1:
        raise InputError("steps_from", "steps", "at least one step", steps)
    out = Path(case) / name
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    for d in ("constant", "system"):
        shutil.copytree(Path(case) / d, out / d)
    shutil.copytree(folder, out / folder.name)
    control = (out / "system" / "controlDict").read_text()
    head, functions = control.split("functions", 1) if "functions" in control else (control, "")
    dt = float(_entry(head, "deltaT"))
    start = float(folder.name)
    end = start + steps * dt
    for key, value in (("startTime", folder.name), ("endTime", f"{end:.12g}")):
        head = re.sub(rf"^{key}\s+[^;]+;", f"{key} {value};", head, flags=re.M)
    head = re.sub(r"^writeControl\s+[^;]+;", "writeControl timeStep;", head, flags=re.M)
    head = re.sub(r"^writeInterval\s+[^;]+;", "writeInterval 1;", head, flags=re.M)
    (out / "system" / "controlDict").write_text(
        head + ("functions" + functions if functions else "")
    )
    solver = _entry(head, "application")
    monitor = SolverMonitor(end, dt, 1.0, 1e9)  # a few steps of a run that already passed
    run_solver(foam, out, monitor, nice=nice, solver=solver)
    return [d for t, d in time_directories(out) if t > start * (1 + 1e-12)]


StepPair = Callable[[Path], tuple[Path, Path]]
"""From a written time folder of a run: the folders of the two solver steps after it."""


def step_pair(foam: OpenFoam, nice: int = 0) -> StepPair:
    """For a load that balances the cell's momentum as the solver does: from a written time
    folder of a run, two steps after it (under ``<case>/load_steps_<time>``); the second is
    the first step that starts from a solved flux (module docstring)."""

    def pair(write: Path) -> tuple[Path, Path]:
        written = steps_from(foam, write.parent, write, 2, f"load_steps_{write.name}", nice)
        if len(written) < 2:
            raise InputError(write, "time folders", "two steps written after the restart")
        return written[0], written[1]

    return pair
