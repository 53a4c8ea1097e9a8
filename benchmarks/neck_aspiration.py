"""Wall time and peak memory of the neck passage (issue 8), Newton iterations and cutbacks.

One viscoelastic passage (50 steps, 1 s) with the materials of the afm_creep_prony case
(re-generated here), at the element sizes given (default: 14 and 10 um, the quick and the
main mesh of ``cases/fe_neck_aspiration``). The ratio to the coarsest mesh in the same process
is the baseline. ``--case`` also runs the whole case (``python -m oocyte_fe run
cases/fe_neck_aspiration``: main and elastic passages, five sensitivity passages, the mesh
study) in a child process and prints its wall time and peak memory. Goal of the issue: the
full case under 60 s on 2 cores, at the finest mesh that meets the 2 % criterion.
Run: ``python benchmarks/neck_aspiration.py [--case] [size_um ...]``.
"""

from __future__ import annotations

import logging
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from oocyte_fe.neck.materials import materials_from_afm_case
from oocyte_fe.neck.passage import PassageSettings, run_passage

ROOT = Path(__file__).parents[1]
AFM_CASE = ROOT / "cases" / "afm_creep_prony"


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far [MB] (Linux ru_maxrss is in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def full_case() -> None:
    """The whole case in a child process: wall time, peak RSS of the child."""
    with tempfile.TemporaryDirectory() as tmp:
        tic = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "oocyte_fe", "run", "cases/fe_neck_aspiration", "--out", tmp],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        seconds = time.perf_counter() - tic
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
    status = "PASS" if done.returncode == 0 else f"exit {done.returncode}"
    print(f"full case: {seconds:.1f} s wall (goal 60 s), peak RSS {peak:.0f} MB, {status}")


def main(sizes: list[float]) -> None:
    log = logging.getLogger("neck_benchmark")
    with tempfile.TemporaryDirectory() as tmp:
        mats = materials_from_afm_case(AFM_CASE, Path(tmp), log)
    base = None
    for size in sizes:
        tic = time.perf_counter()
        result = run_passage(mats.regions(), PassageSettings(size_um=size))
        seconds = time.perf_counter() - tic
        base = base or seconds
        steps = result.steps
        body = result.problem.body
        print(
            f"size {size:g} um: {body.mesh.nelements} triangles, {body.n_dofs} dofs, "
            f"{seconds:.1f} s wall ({seconds / base:.2f} x the first), peak RSS "
            f"{peak_rss_mb():.0f} MB, {'complete' if result.complete else result.failure}"
        )
        print(
            f"  {len(steps)} steps, {sum(s.cutbacks for s in steps)} cutbacks, Newton "
            f"iterations per step: {[s.iterations for s in steps]}"
        )


if __name__ == "__main__":
    args = sys.argv[1:]
    if "--case" in args:
        args.remove("--case")
        full_case()
    main([float(a) for a in args] or [14.0, 10.0])
