"""A closed-form case kind for checking sweeps: ``y = c + sum_i a_i x_i``.

With independent normal inputs ``x_i ~ N(mu_i, sigma_i)`` the output is normal with mean
``c + sum a_i mu_i``, variance ``sum a_i^2 sigma_i^2`` and first-order sensitivity indices
``S1_i = a_i^2 sigma_i^2 / sum_j a_j^2 sigma_j^2``; ``tests/test_sweep_statistics.py``
holds a sweep over this kind to those values. Dimensionless.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, model_validator

from oocyte_fe.runner.registry import CaseContext, CaseOutcome, case_kind
from oocyte_fe.runner.schema import CaseInputs


class LinearInputs(CaseInputs):
    x: list[float] = Field(
        min_length=1,
        description="inputs x_i (a sweep sets x.0, x.1, ...)",
        json_schema_extra={"unit": "1"},
    )
    a: list[float] = Field(
        min_length=1, description="coefficients a_i, one per input", json_schema_extra={"unit": "1"}
    )
    c: float = Field(0.0, description="constant term", json_schema_extra={"unit": "1"})

    @model_validator(mode="after")
    def _same_length(self) -> LinearInputs:
        if len(self.a) != len(self.x):
            raise ValueError(f"as many coefficients a as inputs x ({len(self.x)})")
        return self


@case_kind(
    "analytic_linear",
    inputs=LinearInputs,
    metrics={"y": "c + sum_i a_i x_i (dimensionless)"},
)
def run_linear(ctx: CaseContext) -> CaseOutcome:
    """Evaluate y = c + sum a_i x_i (verification kind for sweeps)."""
    inp = ctx.inputs
    return CaseOutcome(metrics={"y": float(inp.c + np.dot(inp.a, inp.x))})
