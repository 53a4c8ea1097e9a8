"""Benchmark: a 100-curve batch through the user route, with plots and the CSV (issue 17 goal:
under 10 s on 2 cores).

Usage: python benchmarks/afm_batch.py [n_curves] [n_points]   (defaults 100 curves, 2000 points)

Writes ``n_curves`` synthetic curves (Sneddon cone 10 deg, E from N(7.01, 2.88) kPa floored at
1 kPa, contact at 5 um, 1 % noise, baseline offset; :func:`afm.synthetic.indentation_curve`) as
CSV files into a temporary ``afm_fit_files`` case folder and times, as a user runs it,
``python3 -m oocyte_fe run <case>`` in a child process: reading, fitting, ``fits.csv``, one PNG
per curve (two drawing processes), histogram, material files and report. Prints the wall time,
the CPU time of the child processes (user + system) and the load average before and after: on
a shared machine the wall time is the CPU time stretched by the other processes' load, so both
are quoted. Run it from the repository root so this checkout's packages are used.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from afm.curve_io import write_curve
from afm.synthetic import indentation_curve

GOAL_S = 10.0


def write_case(folder: Path, n_curves: int, n_points: int) -> Path:
    """An ``afm_fit_files`` case of ``n_curves`` synthetic curves in ``folder``."""
    rng = np.random.default_rng(17)
    curves = folder / "curves"
    curves.mkdir(parents=True)
    for i, e in enumerate(np.maximum(rng.normal(7.01, 2.88, n_curves), 1.0)):
        curve = indentation_curve(
            float(e), 5.0, n_points=n_points, noise_fraction=0.01, offset_nN=0.2, seed=i
        )
        write_curve(curve, curves / f"curve_{i:03d}.csv")
    (folder / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "batch benchmark"\ntimeout_s = 600\n'
        '[inputs]\ncurves = "curves"\ngeometry = { half_angle_deg = 10.0 }\n'
    )
    return folder


def main(n_curves: int = 100, n_points: int = 2000) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        case = write_case(Path(tmp) / "batch", n_curves, n_points)
        out = Path(tmp) / "results"
        load_before = os.getloadavg()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        command = [sys.executable, "-m", "oocyte_fe", "run", str(case), "--out", str(out)]
        subprocess.run(command, check=True, capture_output=True)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        load_after = os.getloadavg()
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        plots = len(list((out / "batch" / "curve_plots").glob("*.png")))
        rows = (out / "batch" / "fits.csv").read_text().count("\n") - 1
    print(f"{n_curves} curves of {n_points} points: {rows} rows in fits.csv, {plots} plots")
    print(f"wall {wall:.1f} s (goal {GOAL_S:g} s), CPU (user + system, all processes) {cpu:.1f} s")
    print(
        f"cores {os.cpu_count()}, load average (1 min) before {load_before[0]:.2f}, "
        f"after {load_after[0]:.2f}"
    )


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
