"""Dimitriadis' bonded-layer correction (``afm.bottom_effect``) against the project's FE in its
own limit: a ZP-like layer of thickness ``h`` on a cell 1000 times stiffer and so large
(R = 1 mm) that the layer is nearly flat under the probe.

The FE force over Hertz's (Sneddon's exact sphere, R* = Rp R/(Rp + R)) is compared with
Dimitriadis' factor ``1 + 1.133 x + 1.283 x^2 + 0.769 x^3 + 0.0975 x^4``, x = sqrt(R* d)/h,
both raw and over the same FE model with a homogeneous cell (the FE's own deficit against
Hertz removed). The contact penalty is 100 E_layer / h_e (a factor 0.1 of the stiff support's).
"""

from __future__ import annotations

import numpy as np

from afm import get_model
from afm.bottom_effect import dimitriadis_factor
from oocyte_fe.afm_corrections.table import effective_radius_um, experiment, force_curve

CELL_UM = 1000.0
"""A cell so large that the layer is nearly flat under the probe (R* = 0.995 Rp)."""
STIFF = 1000.0
"""E_support / E_layer."""


def bonded_layer_check(
    probe_um: float = 5.0, layer_um: float = 5.0, depth_um: float = 3.0
) -> dict[str, np.ndarray]:
    """Per FE frame: depth [um], x = sqrt(R* d)/h, F_FE/F_Hertz on the layer and on the
    homogeneous cell, and Dimitriadis' factor."""
    rstar = effective_radius_um(probe_um, CELL_UM)
    out: dict[str, np.ndarray] = {}
    for key, ratio, factor in (("layer", STIFF, 0.1), ("homogeneous", 1.0, 100.0)):
        exp = experiment(
            ratio,
            probe_um / layer_um,
            depth_h=depth_um / layer_um,
            cell_um=CELL_UM,
            zona_um=layer_um,
            penalty_factor=factor,
            mesh_um=100.0,
        )
        d, f = force_curve(exp)
        hertz = get_model("hertz_sphere").shape(d[1:], {"radius_um": rstar}, 0.5)
        out["depth_um"] = d[1:]
        out[key] = f[1:] / hertz
    out["x"] = np.sqrt(rstar * out["depth_um"]) / layer_um
    out["dimitriadis"] = dimitriadis_factor(out["depth_um"], rstar, layer_um)
    return out


def cone_layer_check(
    half_angle_deg: float = 70.0, layer_um: float = 5.0, depth_um: float = 1.8, frames: int = 6
) -> dict[str, np.ndarray]:
    """Garcia and Garcia's cone factor against the FE (docs/fe.md: cones of 55 deg and blunter
    are verified): the FE force of a cone on a layer ``layer_um`` thick bonded to a 1000 times
    stiffer 1 mm cell, over the same FE with a homogeneous cell (the FE's own finite-strain
    deficit against Sneddon removed), per frame: depth, y = d tan(alpha)/h, that ratio and
    Garcia's factor. Contact elements a tenth of the final contact radius."""
    from afm.bottom_effect import garcia_cone_factor
    from oocyte_fe.experiment import Experiment, run_experiment
    from oocyte_fe.experiment.analysis import depth_um as depth_of
    from oocyte_fe.experiment.analysis import push_force_nN

    tan = float(np.tan(np.radians(half_angle_deg)))
    a = 2.0 / np.pi * depth_um * tan
    t = np.linspace(0.0, 1.0, frames + 1)
    forces = {}
    for key, ratio in (("layer", STIFF), ("homogeneous", 1.0)):
        exp = Experiment.model_validate(
            {
                "cell": {
                    "outer_diameter_um": 2 * CELL_UM,
                    "zona_thickness_um": layer_um,
                    "mesh_size_um": CELL_UM / 8,
                    "refine_size_um": 0.1 * a,
                    "refine_half_angle_deg": float(np.degrees(3 * a / CELL_UM)),
                    "refine_depth_um": max(3 * a, 1.5 * layer_um),
                    "curved_edges": False,
                    "materials": {
                        "zona": {"E_kPa": 1.0, "nu": 0.5},
                        "cytoplasm": {"E_kPa": ratio, "nu": 0.5},
                    },
                },
                "tools": {
                    "tip": {
                        "type": "cone",
                        "half_angle_deg": half_angle_deg,
                        "penalty_factor": 100.0 / ratio,  # 100 E_layer / h either way
                        "displacement_um": {"time_s": list(t), "value": list(depth_um * t**2)},
                    },
                    "dish": {"type": "holding_pipette", "side": "bottom", "half_width_um": 500.0},
                },
                "time": {
                    "duration_s": 1.0,
                    "frames": frames,
                    "at_path_knots": False,
                },  # t: a parameter
            }
        )
        result = run_experiment(exp)
        forces[key] = push_force_nN(result, "tip")[1:]
        d = depth_of(result, "tip")[1:]
    return {
        "depth_um": d,
        "y": d * tan / layer_um,
        "layer_over_homogeneous": forces["layer"] / forces["homogeneous"],
        "garcia": garcia_cone_factor(d, half_angle_deg, layer_um),
    }


if __name__ == "__main__":
    check = bonded_layer_check()
    print("d_um  x  FE/Hertz  FE/FE_hom  Dimitriadis  (FE/FE_hom)/Dimitriadis")
    for k in range(len(check["x"])):
        rel = check["layer"][k] / check["homogeneous"][k]
        print(
            f"{check['depth_um'][k]:.4f} {check['x'][k]:.3f} {check['layer'][k]:.4f} "
            f"{rel:.4f} {check['dimitriadis'][k]:.4f} {rel / check['dimitriadis'][k]:.4f}"
        )
