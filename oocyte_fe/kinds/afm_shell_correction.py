"""Case kind ``afm_shell_correction``: the shipped shelled-oocyte table and Dimitriadis'
bonded-layer correction against fresh FE runs (heavy: about 5 CPU-minutes).

The table (``afm/data/shell_correction.csv``, made by :mod:`oocyte_fe.afm_corrections.table`)
is read by :func:`afm.corrections.shell_ratio` at points that are not its nodes and compared
with FE runs made now at those points; Dimitriadis' factor with the FE of a layer on a 1000
times stiffer support (:mod:`oocyte_fe.afm_corrections.bottom_check`) in its own range.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field

from afm.corrections import shell_ratio
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind
from oocyte_fe.runner.schema import CaseInputs

METRICS = {
    "table_vs_fe_max_error": "largest |table / fresh FE - 1| at the off-node points",
    "dimitriadis_vs_fe_max_error": "largest |FE / Dimitriadis - 1| for x_min <= x <= x_max",
}


class OffNode(CaseInputs):
    e_ratio: float = Field(gt=0.01, le=1, description="E_cytoplasm / E_ZP")
    probe_h: float = Field(gt=0.1, le=2, description="probe radius / ZP thickness")
    depth_h: list[Annotated[float, Field(gt=0, le=0.6)]] = Field(min_length=1)


class ShellCheckInputs(CaseInputs):
    off_nodes: list[OffNode] = Field(min_length=1, description="points that are not nodes")
    dimitriadis_x: list[float] = Field(
        [0.16, 0.55],
        min_length=2,
        max_length=2,
        description="the x = sqrt(R* d)/h range",
        json_schema_extra={"unit": "1"},
    )


@case_kind("afm_shell_correction", inputs=ShellCheckInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fresh FE runs against the shipped table and against Dimitriadis."""
    from oocyte_fe.afm_corrections.bottom_check import bonded_layer_check
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
    ctx.step("Dimitriadis against the FE of a layer on a stiff support")
    check = bonded_layer_check()
    lo, hi = inp.dimitriadis_x
    use = (check["x"] >= lo) & (check["x"] <= hi)
    rel = check["layer"][use] / check["dimitriadis"][use]
    lines = ["| x | FE / Hertz | Dimitriadis | ratio |", "|---|---|---|---|"]
    lines += [
        f"| {x:.3f} | {f:.4f} | {d:.4f} | {f / d:.4f} |"
        for x, f, d in zip(check["x"], check["layer"], check["dimitriadis"], strict=True)
    ]
    return CaseOutcome(
        metrics={
            "table_vs_fe_max_error": max(errors),
            "dimitriadis_vs_fe_max_error": float(np.max(np.abs(rel - 1))) if use.any() else np.nan,
        },
        sections=[
            ("The table off its nodes", "\n".join(rows)),
            (
                "Dimitriadis (bonded layer) against the FE",
                "\n".join(lines)
                + f"\n\nChecked over {lo:g} <= x <= {hi:g}: below, the contact spans fewer than "
                "4 elements; above, finite strain takes the FE below the small-strain formula.",
            ),
        ],
    )
