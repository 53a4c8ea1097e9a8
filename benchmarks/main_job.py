"""Wall and CPU time of README's main command, ``python -m oocyte_fe run cases/`` (issue 26 D).

Runs the command in a child process (into a temporary results folder; numba's cache and the
mesh/FE result cache left as they are unless ``--cold``), and prints its wall time, the CPU
time of the child and its own children (the case workers), their ratios to the issue's goals
(3 min wall, 5 CPU-min on 2 idle cores), and each case's CPU and wall seconds
(``result.json``), most CPU first, with the rest (process start-up and imports of the case
processes, the parent's scheduling) as ``overhead``. CPU is the figure to compare on a shared
machine. Run on an idle machine:
``python benchmarks/main_job.py [--cold] [-j N] [--runs N] [--save FILE.json]`` (with
``--runs 3`` the median run: CPU time varies by about 15 % between idle runs here).
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

import numpy as np

ROOT = Path(__file__).parents[1]
GOAL_WALL_S = 180.0
GOAL_CPU_S = 300.0


def run_once(args: argparse.Namespace) -> dict:
    """One run of the main command: wall and CPU s, per-case (CPU s, wall s), cases not ok."""
    if args.cold:
        for cache in ROOT.rglob("__pycache__"):
            for f in cache.glob("*.nbi"):
                f.unlink()
            for f in cache.glob("*.nbc"):
                f.unlink()
    env = {**os.environ, "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory() as out, tempfile.TemporaryDirectory() as cache:
        if args.cold:
            env["OOCYTE_FE_CACHE"] = cache  # meshes and FE results made anew
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        tic = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "oocyte_fe", "run", "cases/", "-j", str(args.j), "--out", out],
            cwd=ROOT,
            capture_output=True,
            text=True,
            env=env,
        )
        wall = time.perf_counter() - tic
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        cases, failed = {}, {}
        for found in Path(out).glob("*/result.json"):
            data = json.loads(found.read_text())
            cases[data["name"]] = (float(data.get("cpu_seconds", 0.0)), float(data["seconds"]))
            if data["status"] not in ("PASS", "MISS", "SKIPPED"):
                failed[data["name"]] = f"{data['status']}: {data['reason']}"
        shutil.rmtree(out, ignore_errors=True)
    if done.returncode and not failed:
        print(done.stdout[-2000:], done.stderr[-2000:])
    return {
        "exit": done.returncode,
        "wall_s": wall,
        "cpu_s": cpu,
        "cases": cases,
        "overhead_cpu_s": cpu - sum(c for c, _ in cases.values()),
        "not_ok": failed,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--cold", action="store_true", help="clear numba's cache; a fresh mesh/FE result cache"
    )
    parser.add_argument("-j", type=int, default=os.cpu_count() or 1)
    parser.add_argument(
        "--runs", type=int, default=1, help="run the job this many times; report the median"
    )
    parser.add_argument("--save", type=Path, help="write the per-case CPU and wall s (JSON)")
    args = parser.parse_args()
    runs = []
    for k in range(max(1, args.runs)):
        run = run_once(args)
        runs.append(run)
        print(
            f"run {k + 1}: exit code {run['exit']}; "
            f"wall {run['wall_s']:.1f} s, CPU {run['cpu_s']:.1f} s"
        )
    # the median run by CPU time (an idle machine's CPU time varies by about 15 % run to run)
    run = sorted(runs, key=lambda r: r["cpu_s"])[(len(runs) - 1) // 2]
    wall = float(np.median([r["wall_s"] for r in runs]))
    cpu = run["cpu_s"]
    cases = run["cases"]
    which = "median of" if len(runs) > 1 else "of"
    print(f"-j {args.j}; {len(cases)} cases; {which} {len(runs)} run(s)")
    print(f"wall {wall:7.1f} s   goal {GOAL_WALL_S:.0f} s   ratio {wall / GOAL_WALL_S:.2f}")
    print(f"CPU  {cpu:7.1f} s   goal {GOAL_CPU_S:.0f} s   ratio {cpu / GOAL_CPU_S:.2f}")
    print(f"  {'case (the median run)':34s} {'CPU s':>7s} {'wall s':>7s}")
    for name, (case_cpu, seconds) in sorted(cases.items(), key=lambda kv: -kv[1][0]):
        print(f"  {name:34s} {case_cpu:7.1f} {seconds:7.1f}")
    print(f"  {'overhead (start-up, imports)':34s} {run['overhead_cpu_s']:7.1f}")
    for name, why in sorted(run["not_ok"].items()):
        print(f"  not ok: {name}: {why}")
    if args.save:
        args.save.write_text(
            json.dumps({"median_wall_s": wall, "median": run, "runs": runs}, indent=1)
        )


if __name__ == "__main__":
    main()
