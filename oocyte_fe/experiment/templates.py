"""Ready experiments for ``oocyte-fe new fe_experiment DIR --template NAME``.

Each template is the ``[inputs]`` of a case that runs unedited: the seed's layered oocyte
(140 um across, a 15 um ZP over the cytoplasm, the AFM moduli of seed 001: ZP 7.0 kPa,
cytoplasm 1.55 kPa, nu = 0.5) in a lab's experiment. Edit the cell, the tools and the time path.
"""

from __future__ import annotations

from typing import Any

SEED_CELL: dict[str, Any] = {
    "outer_diameter_um": 140.0,
    "zona_thickness_um": 15.0,
    "symmetry": "axisymmetric",
    "mesh_size_um": 8.0,
    "materials": {
        "zona": {"E_kPa": 7.0, "nu": 0.5},
        "cytoplasm": {"E_kPa": 1.55, "nu": 0.5},
    },
}


def _ramp(end: float, value: float) -> dict[str, list[float]]:
    return {"time_s": [0.0, end], "value": [0.0, value]}


TEMPLATES: dict[str, dict[str, Any]] = {
    "aspiration": {
        "description": "Micropipette aspiration of the layered oocyte, 0-200 Pa in 10 frames",
        "cell": {
            **SEED_CELL,
            "refine_size_um": 1.0,
            "refine_half_angle_deg": 20.0,
            "refine_depth_um": 15.0,
            "points": {"apex": [0.0, 70.0], "centre": [0.0, 0.0]},
        },
        "tools": {
            "pipette": {
                "type": "straight_pipette",
                "inner_radius_um": 10.0,
                "wall_um": 5.0,
                "mouth_fillet_um": 0.5,
                "suction_Pa": _ramp(2.0, 200.0),
            }
        },
        "time": {"duration_s": 2.0, "frames": 10},
        "record": {
            "fields": True,
            "sections_at_s": [2.0],
            "section_window_um": [-40.0, 40.0, 30.0, 90.0],
        },
    },
    "plates": {
        "description": "The layered oocyte compressed between two plates to 30 % of its diameter",
        "cell": {**SEED_CELL, "points": {"equator": [70.0, 0.0]}},
        "tools": {
            "top": {"type": "plate", "side": "top", "displacement_um": _ramp(1.0, 21.0)},
            "bottom": {"type": "plate", "side": "bottom", "displacement_um": _ramp(1.0, 21.0)},
        },
        "time": {"duration_s": 1.0, "frames": 12},
    },
    "afm_indentation": {
        "description": "AFM indentation of the whole oocyte by a 5 um spherical probe, 1 um in 1 s",
        "cell": {
            **SEED_CELL,
            "refine_size_um": 0.25,
            "refine_half_angle_deg": 6.0,
            "refine_depth_um": 4.0,
            "curved_edges": False,
        },
        "tools": {
            "probe": {
                "type": "sphere",
                "radius_um": 5.0,
                "penalty_factor": 100.0,
                "displacement_um": _ramp(1.0, 1.0),
            },
            "dish": {"type": "holding_pipette", "side": "bottom", "half_width_um": 60.0},
        },
        "time": {"duration_s": 1.0, "frames": 8},
    },
    "neck": {
        "description": "The seed's oocyte (180 um) pulled through a 200 -> 150 um necked pipette",
        "cell": {
            **SEED_CELL,
            "outer_diameter_um": 180.0,
            "mesh_size_um": 14.0,
            "refine_size_um": 7.0,
            "refine_depth_um": 20.0,
            "refine_windows_deg": [[20.0, 160.0]],
            "curved_edges": False,
            "points": {"equator": [90.0, 0.0]},
        },
        "tools": {
            "pipette": {
                "type": "necked_pipette",
                "bore_diameter_um": 200.0,
                "neck_diameter_um": 150.0,
                "taper_length_um": 200.0,
                "friction": 0.2,
                "suction_control": {"tool": "cap", "target_nN": 0.0},
            },
            "cap": {
                "type": "holding_pipette",
                "side": "bottom",
                "cap_deg": 10.0,
                "components": "axial",
                "displacement_um": _ramp(1.0, 150.0),
            },
        },
        "time": {"duration_s": 1.0, "frames": 50, "max_iterations": 20},
    },
    "press": {
        "description": "Plane-strain press of the layered oocyte by a wedge pipette, held opposite",
        "cell": {
            **SEED_CELL,
            "symmetry": "plane_strain",
            "mesh_size_um": 6.0,
            "refine_size_um": 2.5,
            "refine_half_angle_deg": 30.0,
            "points": {"spindle": [35.0, 0.0]},
        },
        "tools": {
            "pipette": {
                "type": "wedge_pipette",
                "side": "right",
                "width_um": 10.0,
                "tip_angle_deg": 30.0,
                "penalty_factor": 30.0,
                "smoothing_um": 0.2,
                "displacement_um": _ramp(2.0, 40.0),
            },
            "holder": {"type": "holding_pipette", "side": "left", "half_width_um": 20.0},
        },
        "time": {"duration_s": 2.0, "frames": 16, "max_step_s": 0.0625},
    },
}
