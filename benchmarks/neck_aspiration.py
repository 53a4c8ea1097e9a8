"""Wall time and peak memory of the neck passage (issue 8), Newton iterations and cutbacks.

One viscoelastic passage (50 steps, 1 s) with the materials of the afm_creep_prony case
(re-generated here), at the element sizes given (default: 14 and 10 um, the quick and the
main mesh of ``cases/fe_neck_aspiration``). The ratio to the coarsest mesh in the same process
is the baseline. Goal of the issue: the full case under 60 s on 2 cores.
Run: ``python benchmarks/neck_aspiration.py [size_um ...]``.
"""

from __future__ import annotations

import logging
import resource
import sys
import tempfile
import time
from pathlib import Path

from oocyte_fe.neck.materials import materials_from_afm_case
from oocyte_fe.neck.passage import PassageSettings, run_passage

AFM_CASE = Path(__file__).parents[1] / "cases" / "afm_creep_prony"


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far [MB] (Linux ru_maxrss is in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


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
    main([float(a) for a in sys.argv[1:]] or [14.0, 10.0])
