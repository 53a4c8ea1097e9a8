"""The shelled-oocyte correction table of ``afm.corrections`` from the project's FE.

A rigid sphere of radius ``Rp`` indents the layered cell (outer radius ``R``, a ZP of
thickness ``h`` and modulus ``E_ZP`` bonded to a cytoplasm of ``E_c``; both neo-Hookean,
nu = 0.5) on a bonded patch at the bottom, as in the case ``fe_afm_sphere``. One FE run gives
the whole force-depth curve ``F(d)``. A user fits afm's ``hertz_sphere`` (Sneddon's exact
sphere) with the effective radius ``R* = Rp R / (Rp + R)`` (a homogeneous sphere's curvature)
to the curve from contact to a depth ``d`` by least squares with points uniform in depth:

    E_fit(d) = int_0^d F s dd' / int_0^d s^2 dd',    s = shape(d'; R*, nu)    [kPa]

(``F`` between the FE frames by a monotone cubic of the local modulus ``F / s`` in sqrt(d)).
The table's ratio is ``E_fit(layered) / E_fit(homogeneous)``, the homogeneous run being the
same mesh with ``E_c = E_ZP``: so the ratio is 1 for ``E_c / E_ZP = 1`` and at ``d -> 0``
(the row ``d = 0`` is that limit), and the FE's own deficit against Hertz (docs/fe.md)
cancels; it is written beside the ratio (``hom``: ``E_fit / E`` of the homogeneous cell).

Run ``python -m oocyte_fe.afm_corrections.table`` to regenerate
``afm/data/shell_correction.csv`` (one FE process, results cached by their inputs).
"""

from __future__ import annotations

import argparse
import datetime
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

from afm import get_model
from oocyte_fe.experiment.analysis import depth_um, push_force_nN
from oocyte_fe.experiment.cache import cached_arrays
from oocyte_fe.experiment.description import Experiment
from oocyte_fe.experiment.driver import run_experiment

CELL_RADIUS_UM = 70.0
"""The seed's cell (140 um across)."""
ZONA_UM = 15.0
"""The seed's ZP thickness; lengths scale with it (the table is in d/h and Rp/h)."""
E_RATIOS = (1.0, 0.5, 0.22, 0.1, 0.05)
"""E_cytoplasm / E_ZP of the table (1: the homogeneous run every ratio is divided by)."""
PROBE_RATIOS = (1 / 3, 2 / 3, 4 / 3)
"""Rp / h of the table (probes of 5, 10 and 20 um on the seed's 15 um ZP)."""
MAX_DEPTH_H = 0.5
"""Deepest d / h."""
MAX_DEPTH_RP = 0.6
"""Deepest d / Rp (a sphere's Hertz fit beyond this is not what a user does)."""
DEPTH_STEP_H = 0.025
"""Spacing of the table's d / h nodes."""
FRAMES = 24
"""FE frames per curve, uniform in sqrt(depth) (the ratio falls like sqrt(d) from d = 0)."""
REFINE_UM = 0.25
"""Element size at a probe of Rp = 5 um (``fe_afm_sphere``'s, mesh-converged there); it grows
like sqrt(Rp), as the contact radius at a given depth, so every probe has as many elements
across its contact."""
NU = 0.5
COLD_RUN = "measured without the cache: 6.9 CPU-min, 12.6 min wall on 2 shared cores"
"""What regenerating costs with no FE result cached (15 runs; measured 2026-12-02)."""


def max_depth_h(probe_h: float) -> float:
    """Deepest d/h tabulated for a probe of Rp/h = ``probe_h``: min(0.5, 0.6 Rp/h), on a node."""
    return DEPTH_STEP_H * np.floor(min(MAX_DEPTH_H, MAX_DEPTH_RP * probe_h) / DEPTH_STEP_H + 1e-9)


def default_refine_um(probe_um: float) -> float:
    """Contact element size for a probe of radius ``probe_um``: 0.25 um sqrt(Rp / 5 um)."""
    return REFINE_UM * float(np.sqrt(probe_um / 5.0))


def effective_radius_um(probe_um: float, cell_um: float = CELL_RADIUS_UM) -> float:
    """R* = Rp R / (Rp + R) [um]."""
    return probe_um * cell_um / (probe_um + cell_um)


def experiment(
    e_ratio: float,
    probe_h: float,
    *,
    depth_h: float | None = None,
    cell_um: float = CELL_RADIUS_UM,
    zona_um: float = ZONA_UM,
    refine_um: float | None = None,
    frames: int = FRAMES,
    e_zona_kPa: float = 1.0,
    penalty_factor: float = 100.0,
    mesh_um: float | None = None,
) -> Experiment:
    """The FE experiment of one table column: E_c/E_ZP = ``e_ratio``, Rp/h = ``probe_h``,
    to d/h = ``depth_h`` (default: :func:`max_depth_h`); depth ``d_max t^2`` over t in [0, 1]
    s (frames uniform in sqrt(d)); contact elements ``refine_um`` (default: :func:`refine_um`)."""
    rp = probe_h * zona_um
    d = (depth_h or max_depth_h(probe_h)) * zona_um
    a = np.sqrt(effective_radius_um(rp, cell_um) * d)  # Hertz contact radius at the end
    t = np.linspace(0.0, 1.0, 2 * frames + 1)
    half_angle = float(np.degrees(np.arcsin(min(1.0, 1.5 * a / cell_um)))) + 1.0
    return Experiment.model_validate(
        {
            "description": f"shell correction: E_c/E_ZP = {e_ratio:g}, Rp/h = {probe_h:g}",
            "cell": {
                "outer_diameter_um": 2 * cell_um,
                "zona_thickness_um": zona_um,
                "mesh_size_um": mesh_um or min(8.0, cell_um / 8),
                "refine_size_um": refine_um or default_refine_um(rp),
                "refine_half_angle_deg": half_angle,
                "refine_depth_um": max(4.0, 2 * d),
                "curved_edges": False,
                "materials": {
                    "zona": {"E_kPa": e_zona_kPa, "nu": NU},
                    "cytoplasm": {"E_kPa": e_ratio * e_zona_kPa, "nu": NU},
                },
            },
            "tools": {
                "probe": {
                    "type": "sphere",
                    "radius_um": rp,
                    "penalty_factor": penalty_factor,
                    "displacement_um": {"time_s": list(t), "value": list(d * t**2)},
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


def force_curve(exp: Experiment) -> tuple[np.ndarray, np.ndarray]:
    """(depth [um], force [nN]) of the probe over the frames solved, cached by the inputs."""

    def solve() -> dict[str, np.ndarray]:
        result = run_experiment(exp)
        if not result.success:
            raise RuntimeError(f"{exp.description}: the FE stopped ({result.reason})")
        return {"depth": depth_um(result, "probe"), "force": push_force_nN(result, "probe")}

    arrays, _ = cached_arrays(exp, "afm-shell-curve", solve)
    return arrays["depth"], arrays["force"]


def fitted_moduli(
    depth: np.ndarray,
    force: np.ndarray,
    model_name: str,
    geometry: dict[str, float],
    to_depth: np.ndarray,
    axis: Callable[[np.ndarray], np.ndarray] = np.sqrt,
) -> np.ndarray:
    """E_fit [kPa] of afm's ``model_name`` (tip ``geometry``, nu 0.5) fitted from contact to
    each depth of ``to_depth`` (points uniform in depth; module docstring). Between the FE
    frames the local modulus ``F / s`` is a monotone cubic in ``axis(d)`` (sqrt(d) for a
    sphere, whose ratio falls like sqrt(d); d for a cone, whose ratio falls like d)."""
    model = get_model(model_name)
    inside = depth > 0
    local = force[inside] / model.shape(depth[inside], geometry, NU)  # F / s
    modulus = PchipInterpolator(axis(depth[inside]), local, extrapolate=True)  # smooth
    out = []
    for d in np.atleast_1d(to_depth):
        x = np.linspace(0.0, d, 4001)[1:]
        s = model.shape(x, geometry, NU)
        out.append(np.sum(modulus(axis(x)) * s * s) / np.sum(s * s))
    return np.array(out)


def hertz_fit(
    depth: np.ndarray, force: np.ndarray, radius_um: float, to_depth: np.ndarray
) -> np.ndarray:
    """E_fit [kPa] of afm's ``hertz_sphere`` (radius ``radius_um``, nu 0.5) fitted from contact
    to each depth of ``to_depth`` (points uniform in depth; module docstring)."""
    return fitted_moduli(depth, force, "hertz_sphere", {"radius_um": radius_um}, to_depth)


@dataclass(frozen=True)
class Column:
    """Fitted moduli of one (E_c/E_ZP, Rp/h) run at the depths ``depth_h`` (d/h)."""

    e_ratio: float
    probe_h: float
    depth_h: np.ndarray
    e_fit: np.ndarray  # E_fit / E_ZP


def column(
    e_ratio: float, probe_h: float, depth_h: np.ndarray, *, run_to_h: float | None = None, **kw
) -> Column:
    """Run (or read from the cache) one FE curve, to d/h = ``run_to_h`` (default:
    :func:`max_depth_h`), and fit it to each d/h of ``depth_h``."""
    exp = experiment(e_ratio, probe_h, depth_h=run_to_h, **kw)
    zona = exp.cell.zona_thickness_um
    rstar = effective_radius_um(probe_h * zona, exp.cell.radius_um)
    d, f = force_curve(exp)
    e_zona = exp.cell.materials.zona.E_kPa
    return Column(e_ratio, probe_h, depth_h, hertz_fit(d, f, rstar, depth_h * zona) / e_zona)


def table_rows() -> list[dict[str, float]]:
    """Every node of the table: d/h, E_c/E_ZP, Rp/h, ratio, homogeneous (E_fit / E)."""
    rows = []
    for probe_h in PROBE_RATIOS:
        depth_h = np.arange(1, round(max_depth_h(probe_h) / DEPTH_STEP_H) + 1) * DEPTH_STEP_H
        homogeneous = column(1.0, probe_h, depth_h)
        for e_ratio in E_RATIOS:
            layered = homogeneous if e_ratio == 1.0 else column(e_ratio, probe_h, depth_h)
            ratio = layered.e_fit / homogeneous.e_fit
            rows.append(dict(depth_h=0.0, e_ratio=e_ratio, probe_h=probe_h, ratio=1.0, hom=1.0))
            for k, dh in enumerate(depth_h):
                rows.append(
                    dict(
                        depth_h=float(dh),
                        e_ratio=e_ratio,
                        probe_h=probe_h,
                        ratio=float(ratio[k]),
                        hom=float(homogeneous.e_fit[k]),
                    )
                )
    return rows


def code_version() -> str:
    try:
        out = subprocess.run(
            ["git", "describe", "--always", "--dirty"],
            cwd=Path(__file__).parent,
            capture_output=True,
            text=True,
            check=True,
        )
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def write_table(path: Path, rows: list[dict[str, float]], cpu_s: float) -> None:
    """The table as CSV with a ``#`` header: how it was made, the code version and the grid."""
    header = [
        "shell correction for a spherical probe on the layered oocyte (afm.corrections)",
        "made by: python -m oocyte_fe.afm_corrections.table "
        f"(code {code_version()}, {datetime.date.today().isoformat()}, "
        f"{cpu_s / 60:.1f} CPU-min; FE results come from the cache when present; {COLD_RUN})",
        f"FE: axisymmetric P2, neo-Hookean, nu = {NU}, bonded layers, cell R = "
        f"{CELL_RADIUS_UM:g} um, ZP h = {ZONA_UM:g} um, contact elements "
        f"{REFINE_UM:g} um sqrt(Rp / 5 um), {FRAMES} frames uniform in sqrt(d), a 60 um "
        "bonded patch below",
        "fit: afm hertz_sphere with R* = Rp R/(Rp + R), contact to d, uniform in depth",
        "ratio = E_fit(layered) / E_fit(homogeneous, same mesh); hom = E_fit(homogeneous) / E",
        f"grid: depth_h = 0:{DEPTH_STEP_H}:min({MAX_DEPTH_H}, {MAX_DEPTH_RP} Rp/h); "
        f"e_ratio = {', '.join(f'{e:g}' for e in E_RATIOS)}; "
        f"probe_h = {', '.join(f'{p:.6g}' for p in PROBE_RATIOS)}",
        "spherical probes only: cones are in shell_correction_cone.csv",
    ]
    lines = [f"# {h}" for h in header] + ["depth_h,e_ratio,probe_h,ratio,hom"]
    lines += [
        f"{r['depth_h']:.4f},{r['e_ratio']:.6g},{r['probe_h']:.12g},{r['ratio']:.6f},{r['hom']:.6f}"
        for r in rows
    ]
    path.write_text("\n".join(lines) + "\n")


def regenerate(
    argv: list[str] | None,
    description: str,
    default: Path,
    rows: Callable[[], list[dict[str, float]]],
    write: Callable[[Path, list[dict[str, float]], float], None],
) -> None:
    """The command line of a table module: ``--out`` (default ``default``), then the rows
    computed (FE results from the cache when present) and written with the CPU time."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", type=Path, default=default)
    args = parser.parse_args(argv)
    tic = time.process_time()
    table = rows()
    write(args.out, table, time.process_time() - tic)
    print(f"wrote {args.out} ({len(table)} rows, {(time.process_time() - tic) / 60:.1f} CPU-min)")


def main(argv: list[str] | None = None) -> None:
    """Regenerate the table (``--out``: default afm/data/shell_correction.csv)."""
    default = Path(__file__).parents[2] / "afm" / "data" / "shell_correction.csv"
    regenerate(argv, __doc__.splitlines()[0], default, table_rows, write_table)


if __name__ == "__main__":
    main()
