"""The step -> 0 limit of a quantity computed at three steps h, h/r, h/r^2 (Richardson).

For a method whose error is ``f(h) = f0 + C h^p + O(h^(p+1))``, three solutions
``f1 = f(h), f2 = f(h/r), f3 = f(h/r^2)`` give the observed order and the limit::

    p  = ln((f1 - f2) / (f2 - f3)) / ln r
    f0 = f3 + (f3 - f2) / (r^p - 1)

valid when the differences have the same sign (monotone convergence); when they alternate,
or one is zero, there is no observed order and no limit (both nan: the three solutions are
not in the asymptotic range). The VOF Table 4 case applies it to the axis ratio at the junction
over dt, dt/2, dt/4 (docs/microchannel.md, "Mesh, corrector and time-step convergence").
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class Extrapolation:
    """The observed order ``order`` (nan: not monotone) and the limit ``limit`` of three
    solutions at steps refined by ``ratio``; ``finest`` is the third solution."""

    order: float
    limit: float
    finest: float
    ratio: float

    @property
    def monotone(self) -> bool:
        return math.isfinite(self.order)


def richardson(values: Sequence[float], ratio: float = 2.0) -> Extrapolation:
    """Observed order and limit (module docstring) of ``values`` = f(h), f(h/r), f(h/r^2)."""
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise InputError(
            "richardson", "values", "three finite solutions f(h), f(h/r), f(h/r^2)", list(values)
        )
    if not ratio > 1:
        raise InputError("richardson", "ratio", "a refinement ratio > 1", got=ratio)
    f1, f2, f3 = (float(v) for v in values)
    d12, d23 = f1 - f2, f2 - f3
    if d12 == 0 or d23 == 0 or (d12 > 0) != (d23 > 0):
        return Extrapolation(math.nan, math.nan, f3, ratio)
    order = math.log(d12 / d23) / math.log(ratio)
    return Extrapolation(order, f3 + (f3 - f2) / (ratio**order - 1), f3, ratio)
