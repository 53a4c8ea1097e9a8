"""The shelled-oocyte correction table for cones (``afm.corrections.cone_shell_ratio``).

A rigid cone of half angle ``alpha`` indents the layered cell of
:mod:`oocyte_fe.afm_corrections.table` (R = 70 um, a ZP of h = 15 um and E_ZP bonded to a
cytoplasm of E_c, neo-Hookean, nu = 0.5, a bonded patch below). A user fits afm's
``sneddon_cone`` from contact to the depth ``d`` (points uniform in depth):

    E_fit(d) = int_0^d F s dd' / int_0^d s^2 dd',   s = 2 tan(alpha) d'^2 / (pi (1 - nu^2))

and the table's ratio is ``E_fit(layered) / E_fit(homogeneous)`` (same mesh), tabulated
against

    y = d tan(alpha) / h   (= pi a / (2 h), a = 2 d tan(alpha) / pi Sneddon's contact radius)

Why one angle serves every cone: in linear elasticity the surface displacement under a cone
of contact radius ``a`` is ``d - r cot(alpha)`` with ``d = (pi/2) a cot(alpha)``; every field
of the layered body is ``cot(alpha)`` times that of a 45 deg cone with the same ``a``, so
``F / F_Sneddon`` depends on ``a / h`` (hence on ``y``) and ``E_c / E_ZP`` only, not on the
angle. The FE (finite strain) is run at ``ANGLE_DEG``; runs at 60 and 80 deg (and sharper, as
far as the FE converges) measure how far the invariance holds (docs/afm.md). Each column is
two runs with the same number of elements across the contact: ``near`` to y = ``NEAR_Y``
and ``far`` to y = ``MAX_Y``, contact elements a fifteenth of the final contact radius.

Run ``python -m oocyte_fe.afm_corrections.cone_table`` to regenerate
``afm/data/shell_correction_cone.csv`` (FE results cached by their inputs).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oocyte_fe.afm_corrections.table import (
    CELL_RADIUS_UM,
    E_RATIOS,
    NU,
    ZONA_UM,
    code_version,
    fitted_moduli,
    force_curve,
    regenerate,
)
from oocyte_fe.experiment.description import Experiment

ANGLE_DEG = 70.0
"""The table's cone (the FE cone is verified against Sneddon at 70 deg, docs/fe.md)."""
NEAR_Y = 0.05
"""Deepest y of the fine (``near``) run; below it the table takes that run."""
MAX_Y = 0.3
"""Deepest y of the table (contact radius 0.19 h: 2.9 um on the seed's ZP)."""
NEAR_STEP, FAR_STEP = 0.003125, 0.0125
"""Spacing of the y nodes below and above ``NEAR_Y`` (the FE frames, uniform in depth)."""
ELEMENTS_ACROSS = 15.0
"""Contact elements across the final contact radius of each run."""


def experiment(
    e_ratio: float,
    half_angle_deg: float = ANGLE_DEG,
    *,
    y_max: float = MAX_Y,
    frames: int = 24,
    cell_um: float = CELL_RADIUS_UM,
    zona_um: float = ZONA_UM,
    e_zona_kPa: float = 1.0,
) -> Experiment:
    """The FE experiment: a ``half_angle_deg`` cone into the layered cell (E_c/E_ZP =
    ``e_ratio``) to ``d = y_max h / tan(alpha)`` at constant speed over ``frames`` frames."""
    tan = float(np.tan(np.radians(half_angle_deg)))
    d = y_max * zona_um / tan
    a = 2.0 / np.pi * d * tan  # Sneddon's contact radius at the end [um]
    t = np.linspace(0.0, 1.0, frames + 1)
    return Experiment.model_validate(
        {
            "description": f"cone shell correction: E_c/E_ZP = {e_ratio:g}, "
            f"{half_angle_deg:g} deg to y = {y_max:g}",
            "cell": {
                "outer_diameter_um": 2 * cell_um,
                "zona_thickness_um": zona_um,
                "mesh_size_um": min(8.0, cell_um / 8),
                "refine_size_um": a / ELEMENTS_ACROSS,
                "refine_half_angle_deg": float(np.degrees(np.arcsin(min(1.0, 3 * a / cell_um)))),
                "refine_depth_um": 3 * a,
                "curved_edges": False,
                "materials": {
                    "zona": {"E_kPa": e_zona_kPa, "nu": NU},
                    "cytoplasm": {"E_kPa": e_ratio * e_zona_kPa, "nu": NU},
                },
            },
            "tools": {
                "probe": {
                    "type": "cone",
                    "half_angle_deg": half_angle_deg,
                    "length_um": max(20.0, 3 * d),
                    "penalty_factor": 100.0,
                    "displacement_um": {"time_s": list(t), "value": list(d * t)},
                },
                "dish": {
                    "type": "holding_pipette",
                    "side": "bottom",
                    "half_width_um": min(60.0, 0.9 * cell_um),
                },
            },
            "time": {"duration_s": 1.0, "frames": frames, "at_path_knots": False},  # t: a parameter
        }
    )


def fitted(
    e_ratio: float, half_angle_deg: float, y: np.ndarray, y_max: float, frames: int = 24
) -> np.ndarray:
    """E_fit / E_ZP of ``sneddon_cone`` fitted to the FE curve (run to ``y_max`` in
    ``frames`` frames, or read from the cache) from contact to each ``y``."""
    exp = experiment(e_ratio, half_angle_deg, y_max=y_max, frames=frames)
    d, f = force_curve(exp)
    tan = float(np.tan(np.radians(half_angle_deg)))
    geometry = {"half_angle_deg": half_angle_deg}
    to_depth = np.asarray(y) * exp.cell.zona_thickness_um / tan
    e_zona = exp.cell.materials.zona.E_kPa
    return fitted_moduli(d, f, "sneddon_cone", geometry, to_depth, axis=np.asarray) / e_zona


def fresh_cone_ratio(
    e_ratio: float, half_angle_deg: float, y: np.ndarray, frames: int = 24
) -> np.ndarray:
    """E_fit(layered) / E_fit(homogeneous) at each ``y`` from fresh runs to ``max(y)`` (their
    own mesh and ``frames``: a check of the table off its nodes)."""
    y_max = float(np.max(y))
    layered = fitted(e_ratio, half_angle_deg, y, y_max, frames)
    return layered / fitted(1.0, half_angle_deg, y, y_max, frames)


def y_nodes() -> tuple[np.ndarray, np.ndarray]:
    """The table's y nodes from the ``near`` run (up to NEAR_Y) and the ``far`` run (above)."""
    near = np.arange(1, round(NEAR_Y / NEAR_STEP) + 1) * NEAR_STEP
    far = np.arange(round(NEAR_Y / FAR_STEP) + 1, round(MAX_Y / FAR_STEP) + 1) * FAR_STEP
    return near, far


def ratio(
    e_ratio: float, half_angle_deg: float = ANGLE_DEG
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(y, E_fit(layered) / E_fit(homogeneous), E_fit(homogeneous) / E) at the table's nodes
    for a cone of ``half_angle_deg``."""
    near, far = y_nodes()
    out = []
    for y, y_max in ((near, NEAR_Y), (far, MAX_Y)):
        hom = fitted(1.0, half_angle_deg, y, y_max)
        layered = hom if e_ratio == 1.0 else fitted(e_ratio, half_angle_deg, y, y_max)
        out.append((layered / hom, hom))
    return (
        np.concatenate([near, far]),
        np.concatenate([out[0][0], out[1][0]]),
        np.concatenate([out[0][1], out[1][1]]),
    )


def table_rows() -> list[dict[str, float]]:
    """Every node: y, E_c/E_ZP, ratio, hom (E_fit / E of the homogeneous cell)."""
    rows = []
    for e_ratio in E_RATIOS:
        rows.append(dict(y=0.0, e_ratio=e_ratio, ratio=1.0, hom=1.0))
        for y, r, h in zip(*ratio(e_ratio), strict=True):
            rows.append(dict(y=float(y), e_ratio=e_ratio, ratio=float(r), hom=float(h)))
    return rows


def write_table(path: Path, rows: list[dict[str, float]], cpu_s: float) -> None:
    """The table as CSV with a ``#`` header: how it was made, the code version and the grid."""
    header = [
        "shell correction for a cone on the layered oocyte (afm.corrections.cone_shell_ratio)",
        "made by: python -m oocyte_fe.afm_corrections.cone_table "
        f"(code {code_version()}, {cpu_s / 60:.1f} CPU-min; FE results come from the cache when "
        "present)",
        f"FE: axisymmetric P2, neo-Hookean, nu = {NU}, bonded layers, cell R = "
        f"{CELL_RADIUS_UM:g} um, ZP h = {ZONA_UM:g} um, a {ANGLE_DEG:g} deg cone at constant "
        f"speed, contact elements a/{ELEMENTS_ACROSS:g} (a the final contact radius of each "
        f"run), runs to y = {NEAR_Y:g} and {MAX_Y:g}, a 60 um bonded patch below",
        "fit: afm sneddon_cone, contact to d, uniform in depth; y = d tan(alpha) / h",
        "ratio = E_fit(layered) / E_fit(homogeneous, same mesh); hom = E_fit(homogeneous) / E",
        f"grid: y = 0:{NEAR_STEP}:{NEAR_Y}, then :{FAR_STEP}:{MAX_Y}; e_ratio = "
        f"{', '.join(f'{e:g}' for e in E_RATIOS)}",
    ]
    lines = [f"# {h}" for h in header] + ["y,e_ratio,ratio,hom"]
    lines += [f"{r['y']:.6f},{r['e_ratio']:.6g},{r['ratio']:.6f},{r['hom']:.6f}" for r in rows]
    path.write_text("\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> None:
    """Regenerate the table (``--out``: default afm/data/shell_correction_cone.csv)."""
    default = Path(__file__).parents[2] / "afm" / "data" / "shell_correction_cone.csv"
    regenerate(argv, __doc__.splitlines()[0], default, table_rows, write_table)


if __name__ == "__main__":
    main()
