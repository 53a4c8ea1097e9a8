"""A test-only case kind: returns y = 2 x, or crashes, sleeps, writes partial output, or hands
an argument to a library that refuses it."""

from __future__ import annotations

import time

from pydantic import Field

from afm.models.sneddon_cone import HALF_ANGLE
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind
from oocyte_fe.runner.schema import CaseInputs


class EchoInputs(CaseInputs):
    x_um: float = Field(gt=0, description="a positive length, um")
    nu: float = Field(default=0.3, ge=-1.0, lt=0.5, description="Poisson ratio (compressible)")
    crash: bool = False
    sleep_s: float = Field(default=0.0, ge=0)
    steps: int = Field(default=0, ge=0, description="counted steps (ctx.progress), 0.01 s each")
    data: DataFile | None = None
    cone_half_angle_deg: float = Field(
        default=10.0, gt=0, lt=90, description="passed to afm's cone model (bounds (1e-3, 90))"
    )


@case_kind("test_echo", inputs=EchoInputs, metrics={"y_um": "2 x, um", "n_rows": "rows in data"})
def run_echo(ctx: CaseContext) -> CaseOutcome:
    """Echo kind used by the runner tests."""
    inp = ctx.inputs
    ctx.output("partial.txt").write_text("written before any crash")
    ctx.output("scheduler.txt").write_text(str(ctx.scheduler))  # the CLI's --scheduler
    ctx.step("computing")
    for i in range(inp.steps):
        time.sleep(0.01)
        ctx.progress(i + 1, inp.steps, "counting")
    if inp.sleep_s:
        time.sleep(inp.sleep_s)
    HALF_ANGLE.check(inp.cone_half_angle_deg)  # a library argument bounded more loosely here
    if inp.crash:
        raise RuntimeError("deliberate crash for the test")
    rows = len(inp.data.read_text().splitlines()) if inp.data else 0
    return CaseOutcome(metrics={"y_um": 2.0 * inp.x_um, "n_rows": float(rows)})
