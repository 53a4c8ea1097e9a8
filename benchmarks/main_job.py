"""Wall and CPU time of README's main command, ``python -m oocyte_fe run cases/`` (issue 26 D).

Runs the command in a child process (into a temporary results folder, numba's cache left as
it is unless ``--cold``), and prints its wall time, the CPU time of the child and its own
children (the case workers), their ratios to the issue's goals (3 min wall, 5 CPU-min on 2
idle cores), and the slowest cases from the run's metrics. Run on an idle machine:
``python benchmarks/main_job.py [--cold] [-j N]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).parents[1]
GOAL_WALL_S = 180.0
GOAL_CPU_S = 300.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cold", action="store_true", help="clear numba's cache first")
    parser.add_argument("-j", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    if args.cold:
        for cache in ROOT.rglob("__pycache__"):
            for f in cache.glob("*.nbi"):
                f.unlink()
            for f in cache.glob("*.nbc"):
                f.unlink()
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        tic = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "oocyte_fe", "run", "cases/", "-j", str(args.j), "--out", out],
            cwd=ROOT,
            capture_output=True,
            text=True,
            env={**os.environ, "MPLBACKEND": "Agg"},
        )
        wall = time.perf_counter() - tic
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        times = []
        for metrics in Path(out).glob("*/metrics.json"):
            data = json.loads(metrics.read_text())
            times.append((float(data.get("seconds", 0.0) or 0.0), metrics.parent.name))
        shutil.rmtree(out, ignore_errors=True)
    print(f"exit code {done.returncode}; -j {args.j}")
    print(f"wall {wall:7.1f} s   goal {GOAL_WALL_S:.0f} s   ratio {wall / GOAL_WALL_S:.2f}")
    print(f"CPU  {cpu:7.1f} s   goal {GOAL_CPU_S:.0f} s   ratio {cpu / GOAL_CPU_S:.2f}")
    for seconds, name in sorted(times, reverse=True)[:6]:
        print(f"  {name:32s} {seconds:7.1f} s")
    if done.returncode:
        print(done.stdout[-2000:], done.stderr[-2000:])


if __name__ == "__main__":
    main()
