"""Case kind: the spindle-offset prediction recalibrated on a resampled Table II (seed 000).

The measured forces of Table II are resampled with a stated relative scatter
(:func:`oocyte_fe.sweep.resample.resample_relative`, realisation ``noise_seed``); the NMSD is
recalibrated on the resampled curve and the spindle offset predicted exactly as by the kind
``nmsd_spindle_offset``. A sweep over ``noise_seed`` (and any other input) spreads the
prediction over the scatter of the force data.
"""

from __future__ import annotations

import dataclasses

from pydantic import Field

from nmsd.tableII import UN_TO_NN, read_force_displacement
from oocyte_fe.kinds.nmsd_cases import run_spindle
from oocyte_fe.kinds.nmsd_inputs import SpindleInputs
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind, get_kind
from oocyte_fe.sweep.resample import relative_scatter, resample_relative, write_force_csv


class ResampledSpindleInputs(SpindleInputs):
    noise_rel: float = Field(
        0.025,
        ge=0,
        lt=1,
        description="relative SD of the multiplicative force noise",
        json_schema_extra={"unit": "1"},
    )
    noise_seed: int = Field(
        0,
        ge=0,
        description="realisation of the noise (0, 1, 2, ...)",
        json_schema_extra={"unit": "1"},
    )


@case_kind(
    "nmsd_spindle_offset_resampled",
    inputs=ResampledSpindleInputs,
    metrics={
        **get_kind("nmsd_spindle_offset").metrics,
        "force_change_rms_pct": "RMS relative change of the resampled forces >= 1 uN, %",
    },
)
def run_resampled(ctx: CaseContext) -> CaseOutcome:
    """Resample Table II within its scatter, recalibrate, predict the spindle offset."""
    inp = ctx.inputs
    data = read_force_displacement(inp.data)
    ctx.step(f"resampling Table II (noise {inp.noise_rel:g}, seed {inp.noise_seed})")
    force = resample_relative(data.force_nN, inp.noise_rel, inp.noise_seed)
    columns = {"force_experiment_uN": force / UN_TO_NN}
    if data.paper_model_nN is not None:
        columns["force_simulation_uN"] = data.paper_model_nN / UN_TO_NN
    path = write_force_csv(ctx.output("tableII_resampled.csv"), data.displacement_um, columns)
    fields = inp.model_dump(exclude={"noise_rel", "noise_seed"})
    spindle = dataclasses.replace(ctx, inputs=SpindleInputs(**{**fields, "data": path}))
    outcome = run_spindle(spindle)
    change = relative_scatter(force, data.force_nN, floor=1.0 * UN_TO_NN)
    outcome.metrics["force_change_rms_pct"] = 100 * change
    outcome.sections.insert(
        0,
        (
            "Resampled Table II",
            f"Measured forces times (1 + {inp.noise_rel:g} z), z ~ N(0, 1), seed "
            f"{inp.noise_seed}: RMS change {100 * change:.2f} % over the points >= 1 uN "
            "(`tableII_resampled.csv`).",
        ),
    )
    return outcome
