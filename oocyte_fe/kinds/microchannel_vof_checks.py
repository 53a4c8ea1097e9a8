"""The checks a VOF case takes from its runs' logs: the Courant number up to the last state
the case reads."""

from __future__ import annotations

import math

from oocyte_fe.kinds.microchannel_vof_inputs import VofInputs
from oocyte_fe.microchannel.vof.junction import READ_WINDOW_UM, JunctionRun
from oocyte_fe.runner.registry import Check


def courant_check(
    inp: VofInputs, runs: list[JunctionRun], metrics: dict[str, float | list[float]]
) -> list[Check]:
    """``max_courant_read``: the largest Courant number of any run until its cell's centroid
    passes x = +READ_WINDOW_UM (25 um: the last state b/a at x = 0 is read from; the whole run
    where the cell does not get there) within ``inp.max_courant``. The runs take fixed steps;
    in a 3.125 um run whose Courant number leapt from 0.86 to 2.1 for 0.1 ms the cell's
    1 - b/a went from 0.001 to 0.067 (docs/microchannel.md). The metric ``max_courant`` keeps
    the largest over whole runs (the three-phase model's at 900 hPa: 1.30 in the outlet arm,
    after the cell has passed the junction). None without logs."""
    co = [r.max_courant for r in runs if math.isfinite(r.max_courant)]
    ico = [r.max_interface_courant for r in runs if math.isfinite(r.max_interface_courant)]
    if ico:
        metrics["max_interface_courant"] = max(ico)
    if not co:
        return []
    metrics["max_courant"] = max(co)
    read = [
        r.courant_while_read if math.isfinite(r.courant_while_read) else r.max_courant
        for r in runs
        if math.isfinite(r.max_courant)
    ]
    largest = metrics["max_courant_read"] = max(read)
    return [
        Check(
            "max_courant_read",
            largest,
            largest <= inp.max_courant,
            f"<= {inp.max_courant:g} until the cell passes x = +{READ_WINDOW_UM:g} um "
            f"(whole runs: {max(co):.2f})",
        )
    ]
