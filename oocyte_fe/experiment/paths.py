"""A piecewise-linear history in time: a tool's displacement, a suction, a load's scale."""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from oocyte_fe.runner.schema import CaseInputs


class PathSpec(CaseInputs):
    """A piecewise-linear history ``value(time_s)``, held after its last time."""

    time_s: list[Annotated[float, Field(ge=0, le=1e9)]] = Field(min_length=2)
    value: list[Annotated[float, Field(ge=-1e6, le=1e6)]] = Field(min_length=2)

    @model_validator(mode="after")
    def _increasing(self) -> PathSpec:
        if len(self.time_s) != len(self.value):
            raise ValueError("as many values as times")
        t = self.time_s
        if t[0] != 0 or any(b <= a for a, b in zip(t, t[1:], strict=False)):
            raise ValueError("times increasing from 0")
        return self

    def __call__(self, t: float) -> float:
        return float(np.interp(t, self.time_s, self.value))
