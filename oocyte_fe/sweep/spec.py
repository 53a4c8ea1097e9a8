"""The ``[sweep]`` table of ``case.toml``: parameters with distributions, sampler, count, seed.

::

    [sweep]
    sampler = "lhs"            # "lhs" (Latin hypercube) or "sobol" (scrambled, 2^m samples)
    samples = 64
    quick_samples = 8          # used with --quick
    seed = 1
    sensitivity = "rbd_fast"   # SALib method: "rbd_fast" (first-order S1), "pawn" or "none"
    [sweep.parameters.E_zp_kPa]            # a dotted path into [inputs]
    distribution = "normal"                # mean, sd; truncated below at `lower` (0)
    mean = 7.01
    sd = 2.88
    [sweep.parameters.friction]
    distribution = "uniform"               # low, high; "loguniform" likewise (low > 0)
    low = 0.1
    high = 0.3
    [sweep.parameters.noise_seed]
    distribution = "list"                  # values, drawn with equal weight
    values = [0, 1, 2, 3]

Each distribution maps a unit-cube coordinate ``u`` in [0, 1) to a value by its inverse
cumulative distribution function, so the sampler's stratification carries over to the values.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from oocyte_fe.errors import InputError
from oocyte_fe.runner.schema import RuleBroken
from oocyte_fe.sweep.paths import PathError, set_path

STATISTICS = ("mean", "sd", "p05", "p50", "p95")
"""Statistics reported for every scalar metric, named ``<metric>.<statistic>``."""

COUNTS = {
    "n_ok": "samples that finished and enter the statistics",
    "n_failed": "samples that raised or were lost (excluded from the statistics)",
    "ok_fraction": "share of the samples that finished (n_ok / samples)",
}


class _Distribution(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)
    source: str | None = Field(default=None, description="where the numbers come from")


class Normal(_Distribution):
    """Normal(mean, sd) truncated below at ``lower`` (0 by default: positive values only)."""

    distribution: Literal["normal"]
    mean: float
    sd: float = Field(gt=0)
    lower: float = 0.0

    @model_validator(mode="after")
    def _mass_above_lower(self) -> Normal:
        if (self.mean - self.lower) / self.sd < -5:
            raise ValueError(f"mean - lower > -5 sd (almost no mass above lower = {self.lower})")
        return self

    def ppf(self, u: np.ndarray) -> np.ndarray:
        from scipy import stats  # loaded only when a sweep is sampled (slow to import)

        a = (self.lower - self.mean) / self.sd
        return stats.truncnorm.ppf(u, a, np.inf, loc=self.mean, scale=self.sd)

    def probes(self) -> list[Any]:
        return [max(self.mean, self.lower + 0.1 * self.sd)]

    def describe(self) -> str:
        return f"normal, mean {self.mean:g}, SD {self.sd:g}, truncated below {self.lower:g}"


class Uniform(_Distribution):
    """Uniform on [low, high]."""

    distribution: Literal["uniform"]
    low: float
    high: float

    @model_validator(mode="after")
    def _ordered(self) -> Uniform:
        if not self.high > self.low:
            raise ValueError(f"high > low (low = {self.low:g})")
        return self

    def ppf(self, u: np.ndarray) -> np.ndarray:
        return self.low + u * (self.high - self.low)

    def probes(self) -> list[Any]:
        return [self.low, self.high]

    def describe(self) -> str:
        return f"uniform on [{self.low:g}, {self.high:g}]"


class LogUniform(Uniform):
    """Log-uniform on [low, high], low > 0: uniform in log(value)."""

    distribution: Literal["loguniform"]  # type: ignore[assignment]
    low: float = Field(gt=0)

    def ppf(self, u: np.ndarray) -> np.ndarray:
        return self.low * (self.high / self.low) ** u

    def describe(self) -> str:
        return f"log-uniform on [{self.low:g}, {self.high:g}]"


class Choice(_Distribution):
    """An explicit list of values, each drawn with equal weight."""

    distribution: Literal["list"]
    values: list[Any] = Field(min_length=1)

    def ppf(self, u: np.ndarray) -> np.ndarray:
        index = np.minimum((np.asarray(u) * len(self.values)).astype(int), len(self.values) - 1)
        out = np.empty(index.size, dtype=object)  # one cell per draw: a vector value stays whole
        for i, k in enumerate(index.ravel()):
            out[i] = copy.deepcopy(self.values[int(k)])
        return out

    def probes(self) -> list[Any]:
        return list(self.values)

    def describe(self) -> str:
        shown = ", ".join(map(str, self.values[:6])) + (", ..." if len(self.values) > 6 else "")
        return f"list of {len(self.values)}: {shown}"


Parameter = Annotated[Normal | Uniform | LogUniform | Choice, Field(discriminator="distribution")]


class SweepSpec(BaseModel):
    """The ``[sweep]`` table."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True, allow_inf_nan=False)
    sampler: Literal["lhs", "sobol"] = "lhs"
    samples: int = Field(ge=2, le=100_000, description="number of samples")
    quick_samples: int | None = Field(
        default=None, ge=2, le=100_000, description="samples with --quick"
    )
    seed: int = Field(default=0, ge=0)
    sensitivity: Literal["rbd_fast", "pawn", "none"] = "rbd_fast"
    metrics: list[str] | None = Field(default=None, description="metrics to aggregate (all)")
    parameters: dict[str, Parameter] = Field(min_length=1)

    @model_validator(mode="after")
    def _sobol_power_of_two(self) -> SweepSpec:
        if self.sampler == "sobol":
            for n in (self.samples, self.quick_samples):
                if n is not None and n & (n - 1):
                    raise ValueError(f"a power of 2 for samples with the sobol sampler, got {n}")
        return self

    def count(self, quick: bool) -> int:
        return self.quick_samples if quick and self.quick_samples else self.samples


def sweep_metric_names(kind_metrics: Mapping[str, str]) -> dict[str, str]:
    """Names a sweep case may use in ``[reference]``/``[tolerances]``: statistics and counts."""
    names = {f"{m}.{s}": f"{s} of {m} over the samples" for m in kind_metrics for s in STATISTICS}
    return {**names, **COUNTS}


def check_sweep(
    file: str,
    sweep: SweepSpec,
    kind_name: str,
    kind_metrics: Mapping[str, str],
    base: dict[str, Any],
    validate: Callable[[dict[str, Any]], object],
) -> None:
    """Check at load time that each parameter path leads to an input that accepts its values.

    ``base`` is the case's validated inputs as a dict; ``validate(data)`` validates a full
    inputs dict with the kind's model (raising :class:`pydantic.ValidationError`). Each
    parameter's probe values (mean, both bounds, every listed value) are put at its path and
    validated. Raises a one-line :class:`InputError` naming ``sweep.parameters.<path>``.
    """
    for metric in sweep.metrics or []:
        if metric not in kind_metrics:
            raise InputError(
                file, "sweep.metrics", f"metrics of kind {kind_name!r}: {', '.join(kind_metrics)}"
            )
    names = list(sweep.parameters)
    for name in names:
        for other in names:
            if other.startswith(f"{name}."):
                raise InputError(
                    file,
                    f"sweep.parameters.{other}",
                    f"a path apart from sweep.parameters.{name} (both would set the same input)",
                )
    for name, param in sweep.parameters.items():
        field = f"sweep.parameters.{name}"
        for probe in param.probes():
            try:
                validate(set_path(base, name, probe))
            except PathError as exc:
                raise InputError(
                    file, field, f"a dotted path to a field of [inputs] ({exc})"
                ) from None
            except ValidationError as exc:
                first = exc.errors()[0]
                loc, msg = error_field(first, name)
                expected = f"values that inputs.{loc} accepts ({msg[0].lower()}{msg[1:]})"
                if first["type"] == "extra_forbidden":
                    expected = f"a path to a field of [inputs] (inputs.{loc} is no such key)"
                raise InputError(file, field, expected, got=probe) from None
            if isinstance(probe, float) and not math.isfinite(probe):
                raise InputError(file, field, "finite values", got=probe)


def error_field(error: Mapping[str, Any], path: str) -> tuple[str, str]:
    """The input a pydantic error names and its message: the field of its location, else of
    the cross-field rule that raised it (:class:`RuleBroken`), else the parameter's first
    path segment; the message without pydantic's prefix and without a repeat of the field."""
    msg = str(error["msg"]).removeprefix("Value error, ")
    loc = ".".join(str(p) for p in error["loc"])
    cause = (error.get("ctx") or {}).get("error")
    if not loc and isinstance(cause, RuleBroken):
        loc, msg = cause.field, cause.expected
    return loc or path.split(".")[0], msg or "a valid value"


def resolved_inputs(inputs: BaseModel) -> dict[str, Any]:
    """Validated inputs as a dict, data-file paths made absolute (they validate again as is)."""

    def walk(value: Any) -> Any:
        if isinstance(value, Path):
            return value.resolve()
        if isinstance(value, dict):
            return {k: walk(v) for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [walk(v) for v in value]
        return value

    return walk(inputs.model_dump())


def apply_values(base: dict[str, Any], values: dict[str, Any]) -> dict[str, Any]:
    """``base`` inputs with every sampled value put at its parameter's dotted path."""
    data = base
    for path, value in values.items():
        data = set_path(data, path, value)
    return data
