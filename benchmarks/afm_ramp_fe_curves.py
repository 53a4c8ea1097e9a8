"""Force curves of a viscoelastic cell made by the project's FE, for the ramp-fit tests.

The setup of ``cases/fe_afm_sphere`` (a homogeneous 140 um cell on a 60 um bonded patch, a
rigid 10 um spherical probe, 0.25 um contact elements), with a Prony material

    E(t) = E0 [1 - sum g_i (1 - exp(-t/tau_i))],   E0 = 1 kPa, nu = 0.5,
    g = (0.3, 0.3), tau = (0.05, 0.5) s   (E_inf = 0.4 kPa, E_i = 0.3 kPa)

and a triangular ramp: the probe advances 0.2 um in T and returns in T, for T = 0.1 s and
T = 1 s (ramp speeds 2 and 0.2 um/s, a decade apart), 30 frames per segment. Written to
``tests/data/afm_ramp_fe/ramp_T<T>s.csv`` (time_s, advance_um, force_nN: the compressive force
on the probe) with a header naming this script. Run (a few minutes on a loaded machine)::

    OMP_NUM_THREADS=1 PYTHONPATH=. python benchmarks/afm_ramp_fe_curves.py [mesh_scale]
"""

from __future__ import annotations

import copy
import sys
import time
from pathlib import Path

import numpy as np

from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import push_force_nN

OUT = Path(__file__).parents[1] / "tests" / "data" / "afm_ramp_fe"
E0_KPA, NU = 1.0, 0.5
G, TAU_S = (0.3, 0.3), (0.05, 0.5)
DEPTH_UM = 0.2
FRAMES_PER_SEGMENT = 30
PROBE_RADIUS_UM, CELL_DIAMETER_UM = 10.0, 140.0

SPEC = {
    "description": "viscoelastic cell, sphere probe, triangular ramp (afm ramp-fit data)",
    "cell": {
        "outer_diameter_um": CELL_DIAMETER_UM,
        "zona_thickness_um": 0.0,
        "mesh_size_um": 8.0,
        "refine_size_um": 0.25,
        "refine_half_angle_deg": 6.0,
        "refine_depth_um": 4.0,
        "curved_edges": False,
        "materials": {
            "cytoplasm": {
                "E_kPa": E0_KPA,
                "nu": NU,
                "prony": {"g": list(G), "tau_s": list(TAU_S)},
            }
        },
    },
    "tools": {
        "probe": {"type": "sphere", "radius_um": PROBE_RADIUS_UM, "penalty_factor": 100.0},
        "dish": {"type": "holding_pipette", "side": "bottom", "half_width_um": 60.0},
    },
    "time": {"duration_s": 1.0, "frames": 2 * FRAMES_PER_SEGMENT},
}


def experiment(ramp_s: float, mesh_scale: float = 1.0) -> Experiment:
    spec = copy.deepcopy(SPEC)
    spec["tools"]["probe"]["displacement_um"] = {
        "time_s": [0.0, ramp_s, 2.0 * ramp_s],
        "value": [0.0, DEPTH_UM, 0.0],
    }
    spec["time"]["duration_s"] = 2.0 * ramp_s
    spec["mesh_scale"] = mesh_scale
    return Experiment.model_validate(spec)


def main() -> None:
    mesh_scale = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
    OUT.mkdir(parents=True, exist_ok=True)
    for ramp_s in (0.1, 1.0):
        tic = time.perf_counter()
        result = run_experiment(experiment(ramp_s, mesh_scale))
        seconds = time.perf_counter() - tic
        force = push_force_nN(result, "probe")
        table = np.column_stack([result.times_s, result.advance_um["probe"], force])
        header = (
            f"made by benchmarks/afm_ramp_fe_curves.py (oocyte_fe FE, {seconds:.0f} s, "
            f"mesh_scale {mesh_scale:g}, success {result.success}): homogeneous "
            f"{CELL_DIAMETER_UM:g} um cell, sphere probe R = {PROBE_RADIUS_UM:g} um, "
            f"E0 = {E0_KPA:g} kPa, nu = {NU:g}, prony g = {list(G)}, tau_s = {list(TAU_S)}; "
            f"triangular ramp to {DEPTH_UM:g} um in {ramp_s:g} s and back\n"
            "time_s,advance_um,force_nN"
        )
        name = OUT / f"ramp_T{ramp_s:g}s.csv"
        np.savetxt(name, table, delimiter=",", header=header, fmt="%.10g")
        print(f"T = {ramp_s:g} s: {seconds:.1f} s, {len(result.steps)} steps, -> {name}")


if __name__ == "__main__":
    main()
