"""Case kind ``afm_shell_correction``: the shipped shelled-oocyte table and Dimitriadis'
bonded-layer correction against fresh FE runs (heavy: about 8 minutes).

The table (``afm/data/shell_correction.csv``, made by :mod:`oocyte_fe.afm_corrections.table`)
is read by :func:`afm.corrections.shell_ratio` at points that are not its nodes and compared
with FE runs made now at those points; Dimitriadis' factor with the FE of a layer on a 1000
times stiffer support (:mod:`oocyte_fe.afm_corrections.bottom_check`) in its own range.
"""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
from pydantic import Field, ValidationInfo, field_validator

from afm.corrections import cone_shell_ratio, shell_ratio
from oocyte_fe.errors import InputError
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind
from oocyte_fe.runner.schema import CaseInputs

METRICS = {
    "table_vs_fe_max_error": "largest |table / fresh FE - 1| at the off-node points",
    "cone_table_vs_fe_max_error": "largest |cone table / fresh FE - 1| off its nodes and angle",
    "dimitriadis_vs_fe_max_error": "largest |FE / Dimitriadis - 1| for x_min <= x <= x_max",
    "garcia_vs_fe_max_error": "largest |(FE layer / FE homogeneous) / Garcia - 1|, y range",
}


RANGE_LIMIT = 1.0
"""Largest upper end of ``dimitriadis_x`` and ``garcia_y`` (both checks stop below it)."""
REACH = {
    # bonded_layer_check: a 5 um sphere (R* = 5 x 1000 / 1005 um) 3 um into a 5 um layer
    "dimitriadis_x": math.sqrt(5.0 * 1000.0 / 1005.0 * 3.0) / 5.0,
    # cone_layer_check: a 70 deg cone 1.8 um into a 5 um layer
    "garcia_y": 1.8 * math.tan(math.radians(70.0)) / 5.0,
}
"""Deepest x = sqrt(R* d)/h and y = d tan(alpha)/h of the FE checks (defaults of
:mod:`oocyte_fe.afm_corrections.bottom_check`): a range starting beyond selects no point."""


class OffNode(CaseInputs):
    e_ratio: float = Field(gt=0.01, le=1, description="E_cytoplasm / E_ZP")
    probe_h: float = Field(gt=0.1, le=2, description="probe radius / ZP thickness")
    depth_h: list[Annotated[float, Field(gt=0, le=0.6)]] = Field(min_length=1)


class ConeOffNode(CaseInputs):
    e_ratio: float = Field(gt=0.01, le=1, description="E_cytoplasm / E_ZP")
    half_angle_deg: float = Field(ge=30, le=80, description="the cone's half angle")
    y: list[Annotated[float, Field(gt=0, le=0.3)]] = Field(
        min_length=1, description="y = d tan(alpha) / h"
    )


class ShellCheckInputs(CaseInputs):
    off_nodes: list[OffNode] = Field(min_length=1, description="points that are not nodes")
    cone_off_nodes: list[ConeOffNode] = Field(
        min_length=1, description="cone points: E ratios, depths or angles that are not nodes"
    )
    dimitriadis_x: list[float] = Field(
        [0.16, 0.55],
        min_length=2,
        max_length=2,
        description="the x = sqrt(R* d)/h range",
        json_schema_extra={"unit": "1"},
    )
    garcia_y: list[float] = Field(
        [0.1, 1.0],
        min_length=2,
        max_length=2,
        description="the y = d tan(alpha)/h range of the cone check (70 deg)",
        json_schema_extra={"unit": "1"},
    )

    @field_validator("dimitriadis_x", "garcia_y")
    @classmethod
    def _range(cls, value: list[float], info: ValidationInfo) -> list[float]:
        """[lo, hi] with 0 <= lo < hi <= 1 and lo below the deepest point of the FE check."""
        reach = REACH[str(info.field_name)]
        lo, hi = value
        if not (0 <= lo < hi <= RANGE_LIMIT and lo < reach):
            raise ValueError(
                f"a range [lo, hi] with 0 <= lo < hi <= {RANGE_LIMIT:g} and lo below "
                f"{reach:.3f}, the deepest point of the FE check"
            )
        return value


def _in_range(
    ctx: CaseContext, field: str, name: str, points: np.ndarray, bounds: list[float]
) -> np.ndarray:
    """Mask of the FE check's ``points`` within ``bounds`` (the input ``field``); a range that
    holds none is an :class:`InputError` listing the points."""
    lo, hi = bounds
    use = (points >= lo) & (points <= hi)
    if not use.any():
        listed = ", ".join(f"{p:.3f}" for p in points)
        raise InputError(
            ctx.case_dir / "case.toml",
            f"inputs.{field}",
            f"a range holding an FE point ({name} = {listed})",
            [lo, hi],
        )
    return use


@case_kind("afm_shell_correction", inputs=ShellCheckInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fresh FE runs against the shipped table and against Dimitriadis."""
    from oocyte_fe.afm_corrections.bottom_check import bonded_layer_check, cone_layer_check
    from oocyte_fe.afm_corrections.cone_table import fresh_cone_ratio
    from oocyte_fe.afm_corrections.table import column

    inp: ShellCheckInputs = ctx.inputs  # type: ignore[assignment]
    rows = [
        "| E_c/E_ZP | Rp/h | d/h | table | fresh FE | table / FE |",
        "|---|---|---|---|---|---|",
    ]
    errors = []
    for p in inp.off_nodes:
        ctx.step(f"FE at E ratio {p.e_ratio:g}, Rp/h {p.probe_h:g}")
        depth = np.array(p.depth_h)
        fe = column(p.e_ratio, p.probe_h, depth).e_fit / column(1.0, p.probe_h, depth).e_fit
        for d, f in zip(depth, fe, strict=True):
            t = shell_ratio(float(d), p.e_ratio, p.probe_h)
            errors.append(abs(t / f - 1))
            rows.append(
                f"| {p.e_ratio:g} | {p.probe_h:g} | {d:g} | {t:.4f} | {f:.4f} | {t / f:.4f} |"
            )
    cone_rows = [
        "| E_c/E_ZP | half angle | y | table | fresh FE | table / FE |",
        "|---|---|---|---|---|---|",
    ]
    cone_errors = []
    for c in inp.cone_off_nodes:
        ctx.step(f"FE cone {c.half_angle_deg:g} deg at E ratio {c.e_ratio:g}")
        y = np.array(c.y)
        fe = fresh_cone_ratio(c.e_ratio, c.half_angle_deg, y)
        for yy, f in zip(y, fe, strict=True):
            t = cone_shell_ratio(float(yy), c.e_ratio)
            cone_errors.append(abs(t / f - 1))
            cone_rows.append(
                f"| {c.e_ratio:g} | {c.half_angle_deg:g} | {yy:g} | {t:.4f} | {f:.4f} | "
                f"{t / f:.4f} |"
            )
    ctx.step("Dimitriadis against the FE of a layer on a stiff support")
    check = bonded_layer_check()
    lo, hi = inp.dimitriadis_x
    use = _in_range(ctx, "dimitriadis_x", "x", check["x"], inp.dimitriadis_x)
    rel = check["layer"][use] / check["dimitriadis"][use]
    lines = ["| x | FE / Hertz | Dimitriadis | ratio |", "|---|---|---|---|"]
    lines += [
        f"| {x:.3f} | {f:.4f} | {d:.4f} | {f / d:.4f} |"
        for x, f, d in zip(check["x"], check["layer"], check["dimitriadis"], strict=True)
    ]
    ctx.step("Garcia's cone factor against the FE of a layer on a stiff support")
    cone = cone_layer_check()
    ylo, yhi = inp.garcia_y
    in_y = _in_range(ctx, "garcia_y", "y", cone["y"], inp.garcia_y)
    cone_rel = cone["layer_over_homogeneous"][in_y] / cone["garcia"][in_y]
    cone_lines = ["| y | FE layer / homogeneous | Garcia | ratio |", "|---|---|---|---|"]
    cone_lines += [
        f"| {y:.3f} | {f:.4f} | {g:.4f} | {f / g:.4f} |"
        for y, f, g in zip(cone["y"], cone["layer_over_homogeneous"], cone["garcia"], strict=True)
    ]
    return CaseOutcome(
        metrics={
            "garcia_vs_fe_max_error": float(np.max(np.abs(cone_rel - 1))) if in_y.any() else np.nan,
            "table_vs_fe_max_error": max(errors),
            "cone_table_vs_fe_max_error": max(cone_errors),
            "dimitriadis_vs_fe_max_error": float(np.max(np.abs(rel - 1))) if use.any() else np.nan,
        },
        sections=[
            ("The table off its nodes", "\n".join(rows)),
            (
                "The cone table off its nodes and angle",
                "\n".join(cone_rows)
                + "\n\nThe table was made with a 70 deg cone; fresh runs at other angles test "
                "that the ratio depends on y = d tan(alpha)/h and E_c/E_ZP only (docs/afm.md). "
                "Each fresh run goes to its deepest y with its own mesh (a fifteenth of its "
                "final contact radius).",
            ),
            (
                "Dimitriadis (bonded layer) against the FE",
                "\n".join(lines)
                + f"\n\nChecked over {lo:g} <= x <= {hi:g}: below, the contact spans fewer than "
                "4 elements; above, finite strain takes the FE below the small-strain formula.",
            ),
            (
                "Garcia (cone, bonded layer) against the FE",
                "\n".join(cone_lines)
                + f"\n\nA 70 deg cone on a 5 um layer bonded to a 1000 times stiffer 1 mm cell, "
                "over the same FE with a homogeneous cell (the finite-strain deficit against "
                f"Sneddon removed); checked over {ylo:g} <= y <= {yhi:g} (below, the contact "
                "spans fewer than 4 elements).",
            ),
        ],
    )
