"""Sample designs: points of the unit hypercube from ``scipy.stats.qmc``, mapped to values.

Latin hypercube: each of the ``n`` equal strata of every coordinate holds exactly one point,
so a list parameter with ``n`` values and ``n`` samples takes each value once. Sobol: a
scrambled low-discrepancy sequence, balanced for ``n = 2^m``. The values are
``x_j = F_j^{-1}(u_j)`` with ``F_j`` the parameter's cumulative distribution.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.stats import qmc

from oocyte_fe.sweep.spec import SweepSpec


@dataclass(frozen=True)
class Design:
    """The sample design: unit-cube points ``unit`` (n, d) and the values they map to."""

    names: list[str]
    unit: np.ndarray
    values: list[dict[str, Any]]


def unit_points(sampler: str, n: int, d: int, seed: int) -> np.ndarray:
    """``n`` points in [0, 1)^d from the Latin hypercube (``lhs``) or Sobol sampler."""
    if sampler == "lhs":
        return qmc.LatinHypercube(d=d, seed=seed).random(n)
    if sampler == "sobol":
        return qmc.Sobol(d=d, scramble=True, seed=seed).random(n)
    raise ValueError(f"unknown sampler {sampler!r}")


def _plain(value: Any) -> Any:
    """numpy scalars to Python ones (JSON, TOML and pydantic take those)."""
    return value.item() if isinstance(value, np.generic) else value


def design(sweep: SweepSpec, quick: bool = False) -> Design:
    """The deterministic design of a sweep: same table, same seed, same samples."""
    names = list(sweep.parameters)
    unit = unit_points(sweep.sampler, sweep.count(quick), len(names), sweep.seed)
    columns = [sweep.parameters[name].ppf(unit[:, j]) for j, name in enumerate(names)]
    values = [
        {name: _plain(col[i]) for name, col in zip(names, columns, strict=True)}
        for i in range(len(unit))
    ]
    return Design(names, unit, values)
