"""Sweep throughput on Dask: samples per second with 1 and 2 local workers, and per-task overhead.

Two workloads, each run three ways on fresh sample folders (aggregation and plots excluded):

- ``loop``: the same samples run one after the other in this process (``run_sample`` in a
  plain for loop: same per-sample files, no Dask) -- the baseline;
- ``dask 1``/``dask 2``: submitted to a local cluster of 1 or 2 single-threaded worker
  processes (cluster start-up timed apart).

Workloads: ``analytic_linear`` (microseconds of work: the time is the per-sample overhead of
the runner plus Dask) and ``cases/sweep_spindle_offset --quick`` (one NMSD recalibration and
approach per sample, seconds of numpy work). Parallel efficiency = rate(2) / (2 rate(1));
overhead per task = (t_dask1 - t_loop) / n.

    python benchmarks/sweep_scaling.py [--spindle-samples 6] [--linear-samples 64]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import tempfile
import time
from pathlib import Path

from oocyte_fe.runner.casefile import Case, load_case
from oocyte_fe.sweep.cluster import dask_client
from oocyte_fe.sweep.run import plan_samples, run_sample, run_samples

ROOT = Path(__file__).resolve().parents[1]

LINEAR = """
kind = "analytic_linear"
description = "overhead probe"
[inputs]
x = [0.0, 0.0]
a = [1.0, 2.0]
[sweep]
samples = {n}
[sweep.parameters."x.0"]
distribution = "normal"
mean = 1.0
sd = 0.1
[sweep.parameters."x.1"]
distribution = "uniform"
low = 0.0
high = 1.0
"""


def with_samples(case: Case, n: int) -> Case:
    sweep = case.spec.sweep.model_copy(update={"samples": n, "quick_samples": n})
    return dataclasses.replace(case, spec=case.spec.model_copy(update={"sweep": sweep}))


def time_loop(case: Case, root: Path) -> float:
    samples = root / "loop"
    samples.mkdir(parents=True)
    planned = plan_samples(case)
    start = time.perf_counter()
    for p in planned:
        run_sample(p.case, samples)
    return time.perf_counter() - start


def time_dask(case: Case, root: Path, workers: int) -> tuple[float, float]:
    samples = root / f"dask{workers}"
    samples.mkdir(parents=True)
    planned = plan_samples(case)
    start = time.perf_counter()
    with dask_client(workers=workers) as client:
        started = time.perf_counter()
        client.wait_for_workers(workers)
        run_samples(planned, samples, client)
        done = time.perf_counter()
    return started - start, done - started


def bench(label: str, case: Case) -> None:
    n = case.spec.sweep.count(case.quick)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        t_loop = time_loop(case, root)
        s1, t1 = time_dask(case, root, 1)
        s2, t2 = time_dask(case, root, 2)
    r_loop, r1, r2 = n / t_loop, n / t1, n / t2
    print(f"\n{label}: {n} samples")
    print(f"  plain loop     {t_loop:8.2f} s  {r_loop:8.2f} samples/s")
    print(f"  dask 1 worker  {t1:8.2f} s  {r1:8.2f} samples/s  (cluster start {s1:.1f} s)")
    print(f"  dask 2 workers {t2:8.2f} s  {r2:8.2f} samples/s  (cluster start {s2:.1f} s)")
    print(f"  speed-up 2 vs 1 worker {r2 / r1:.2f}, parallel efficiency {r2 / (2 * r1):.0%}")
    print(f"  overhead per task (dask 1 - loop) {1e3 * (t1 - t_loop) / n:+.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--linear-samples", type=int, default=64)
    parser.add_argument("--spindle-samples", type=int, default=6)
    args = parser.parse_args()
    print(f"cores: {os.cpu_count()}, load average: {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "linear"
        folder.mkdir()
        (folder / "case.toml").write_text(LINEAR.format(n=args.linear_samples))
        bench("analytic_linear (overhead probe)", load_case(folder))
    spindle = load_case(ROOT / "cases" / "sweep_spindle_offset", quick=True)
    bench("sweep_spindle_offset --quick", with_samples(spindle, args.spindle_samples))


if __name__ == "__main__":
    main()
