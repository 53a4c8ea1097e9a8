"""Benchmark: a 64 x 64 force map (4 096 curves) from file to fits.csv, the modulus map and the
material files through the user route (issue 28 goal: under 20 s on 2 cores).

Usage: python benchmarks/afm_map.py [side] [n_points]   (defaults 64 x 64 curves, 2000 points)

Writes a ``side x side`` map of synthetic curves (:func:`afm.synthetic.indentation_curve`:
Sneddon cone 10 deg, nu 0.5, k = 0.07 N/m, contact at 5 um of 8, 1 % noise, baseline offset;
E = 2 kPa with a 6 kPa disc of radius 20 um in the middle, 5 um pitch) as one afmformats
HDF5 file (afmformats' own exporter: approach and retract, map positions and grid metadata,
what PyJibe exports), then times, as a user runs it, ``python3 -m oocyte_fe run`` on an
``afm_fit_files`` case of that file in a child process: reading, fitting (two processes),
``fits.csv``, the modulus map, the strip plot, the material file and the report; per-curve
plots only for curves rated poor or refused (``curve_plots = "poor"``: 4 096 plots at about
70 ms of CPU each would take minutes). Prints the wall time, the CPU time of the child
processes and the load average before and after (on a shared machine the wall time is the
CPU time stretched by the other processes' load), and how close the fitted moduli are to the
ones the curves were made with. Run it from the repository root so this checkout's packages
are used.
"""

from __future__ import annotations

import csv
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import afmformats
import h5py
import numpy as np

from afm.synthetic import indentation_curve

GOAL_S = 20.0
PITCH_UM = 5.0


def true_modulus(x_um: float, y_um: float, side: int) -> float:
    """E [kPa] at a map position: 6 kPa inside a disc of radius 20 um at the centre, else 2."""
    centre = 0.5 * PITCH_UM * (side - 1)
    return 6.0 if (x_um - centre) ** 2 + (y_um - centre) ** 2 <= 20.0**2 else 2.0


def write_map(path: Path, side: int, n_points: int) -> Path:
    """The map as afmformats HDF5 (one group per curve, approach then retract)."""
    with h5py.File(path, "w") as h5:
        for i in range(side * side):
            x, y = PITCH_UM * (i % side), PITCH_UM * (i // side)
            curve = indentation_curve(
                true_modulus(x, y, side),
                5.0,
                n_points=n_points,
                noise_fraction=0.01,
                offset_nN=0.2,
                seed=i,
            )
            force, height = curve.force_nN * 1e-9, -curve.piezo_um * 1e-6
            data = {
                "force": np.concatenate([force, force[::-1]]),
                "height (measured)": np.concatenate([height, height[::-1]]),
                "segment": np.repeat([False, True], n_points),
                "time": np.linspace(0.0, 2.0, 2 * n_points),
            }
            metadata = {
                "enum": i,
                "path": path,
                "imaging mode": "force-distance",
                "spring constant": 0.07,
                "sensitivity": 50e-9,
                "position x": x * 1e-6,
                "position y": y * 1e-6,
                "grid shape x": side,
                "grid shape y": side,
                "grid index x": i % side,
                "grid index y": i // side,
                "grid size x": side * PITCH_UM * 1e-6,
                "grid size y": side * PITCH_UM * 1e-6,
                "point count": 2 * n_points,
                "segment count": 2,
                "duration": 2.0,
            }
            afmformats.AFMForceDistance(data, metadata).export_data(h5, fmt="hdf5")
    return path


def main(side: int = 64, n_points: int = 2000) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        case = Path(tmp) / "map_case"
        case.mkdir()
        start = time.perf_counter()
        write_map(case / "map.h5", side, n_points)
        took = time.perf_counter() - start
        print(f"wrote {side} x {side} curves of {n_points} points in {took:.0f} s")
        (case / "case.toml").write_text(
            'kind = "afm_fit_files"\ndescription = "force map benchmark"\ntimeout_s = 900\n'
            '[inputs]\ncurves = "map.h5"\ngeometry = { half_angle_deg = 10.0 }\n'
            'curve_plots = "poor"\n'
        )
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
        folder = out / "map_case"
        with (folder / "fits.csv").open() as fh:
            rows = list(csv.DictReader(fh))
        errors = [
            abs(
                float(r["E_kPa"]) / true_modulus(float(r["map_x_um"]), float(r["map_y_um"]), side)
                - 1
            )
            for r in rows
            if r["E_kPa"]
        ]
        outputs = [
            p.name
            for p in (folder / "modulus_map_map.png", folder / "material_map_case.toml")
            if p.is_file()
        ]
        n_good = sum(r["quality"] == "good" for r in rows)
    print(
        f"{len(rows)} rows in fits.csv ({n_good} rated good), written: {', '.join(outputs)}; "
        f"|E / E_true - 1| median {100 * np.median(errors):.2f} %, max {100 * max(errors):.2f} %"
    )
    verdict = "met" if wall < GOAL_S else "MISSED"
    print(f"wall {wall:.1f} s (goal {GOAL_S:g} s: {verdict}), CPU (user + system) {cpu:.1f} s")
    print(
        f"cores {os.cpu_count()}, load average (1 min) before {load_before[0]:.2f}, "
        f"after {load_after[0]:.2f}"
    )


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
