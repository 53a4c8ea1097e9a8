"""Write the two curve files of the ``afm_ramp_viscoelastic`` case (run once; they are shipped).

Usage, from the repository root:
``PYTHONPATH=. python3 cases/afm_ramp_viscoelastic/make_curves.py``

The curves are the project's own FE, not measurements: ``fe_source/ramp_T0.1s.csv`` and
``fe_source/ramp_T1s.csv`` are copies of ``tests/data/afm_ramp_fe/`` (made by
``benchmarks/afm_ramp_fe_curves.py``: a homogeneous 140 um cell, a rigid 10 um sphere, E0 = 1
kPa, nu = 0.5, Prony g = (0.3, 0.3), tau = (0.05, 0.5) s; a triangular ramp to 0.2 um and back
in 0.1 s and in 1 s). Each becomes an afmformats HDF5 file, as an instrument would record it:
40 points of free travel at the same speed before contact and after the retract (force 0), a
cantilever of k = 0.1 N/m (its deflection F/k added to the height, so the tip moves as the FE
probe did), approach and retract as afmformats' segments 0 and 1, and the time of every point.
No noise is added.
"""

from __future__ import annotations

from pathlib import Path

import afmformats
import h5py
import numpy as np

HERE = Path(__file__).parent
K_N_PER_M = 0.1
FREE_POINTS = 40


def write_ramp(source: Path, target: Path) -> None:
    """One FE ramp (time_s, advance_um, force_nN) as an afmformats HDF5 force curve."""
    t, x, f = np.loadtxt(source, delimiter=",").T
    h, n_approach = t[1] - t[0], int(np.argmax(x)) + 1
    speed = x[1] / h
    before = -h * np.arange(FREE_POINTS, 0, -1)
    after = t[-1] + h * np.arange(1, FREE_POINTS + 1)
    time = np.r_[before, t, after] - before[0]
    tip = np.r_[speed * before, x, x[-1] - speed * (after - t[-1])]
    force = np.r_[np.zeros(FREE_POINTS), f, np.zeros(FREE_POINTS)]
    piezo = tip + force / (K_N_PER_M * 1e3)  # um; F/k in nN / (nN/um)
    segment = np.arange(time.size) >= FREE_POINTS + n_approach
    data = {
        "force": force * 1e-9,
        "height (measured)": -piezo * 1e-6,  # afmformats' sign: decreasing towards the sample
        "segment": segment,
        "time": time,
    }
    metadata = {
        "enum": 0,
        "path": target,
        "imaging mode": "force-distance",
        "spring constant": K_N_PER_M,
        "sensitivity": 5e-8,
        "point count": time.size,
        "duration": float(time[-1]),
    }
    target.unlink(missing_ok=True)
    with h5py.File(target, "w") as h5:
        afmformats.AFMForceDistance(data, metadata).export_data(h5, fmt="hdf5")


if __name__ == "__main__":
    (HERE / "curves" / "cell").mkdir(parents=True, exist_ok=True)
    for name in ("ramp_T0.1s", "ramp_T1s"):
        write_ramp(HERE / "fe_source" / f"{name}.csv", HERE / "curves" / "cell" / f"{name}.h5")
