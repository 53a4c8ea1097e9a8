"""The step -> 0 limit of a quantity computed at three steps h, h/r, h/r^2.

Three solutions ``f1 = f(h), f2 = f(h/r), f3 = f(h/r^2)`` give the contraction factor of their
differences and, if it is below 1 in size, the limit of the geometric sequence through them
(Aitken's delta-squared)::

    q  = (f2 - f3) / (f1 - f2)
    f0 = f3 - (f2 - f3) q / (1 - q)

For a method whose error is ``f(h) = f0 + C h^p + O(h^(p+1))`` (monotone convergence, q > 0)
this is Richardson's extrapolation with the observed order ``p = -ln q / ln r``:
``f0 = f3 + (f3 - f2)/(r^p - 1)``. When the differences alternate (q < 0) there is no observed
order; the geometric limit then lies between f2 and f3, and is only an estimate (two error
sources of opposite sign can make the same pattern). With ``|q| >= 1`` the solutions do not
converge and there is no limit (nan). The VOF Table 4 case applies it to the axis ratio at
the junction over dt, dt/2, dt/4 (docs/microchannel.md, "Mesh, corrector and time-step
convergence").

Meshes refined by unequal ratios (12.5, 6.25, 4.17 um: r = 2 then 1.5) take the same power law
``f(h) = f0 + C h^p`` through three solutions at ``h1 > h2 > h3`` (:func:`power_law`): the
order solves

    (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)

(the right side grows from ``ln(h1/h2) / ln(h2/h3)`` at p -> 0 without bound, so there is one
root when the left side exceeds that), and ``f0 = f3 - (f2 - f3) h3^p / (h2^p - h3^p)``.
With ``h2/h1 = h3/h2 = 1/r`` it is :func:`richardson`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from scipy.optimize import brentq

from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class Extrapolation:
    """Three solutions at steps refined by ``ratio``: the contraction factor ``factor`` (q),
    the observed order ``order`` (nan unless 0 < q < 1), the limit ``limit`` (nan unless
    |q| < 1) and the finest solution ``finest``."""

    factor: float
    order: float
    limit: float
    finest: float
    ratio: float

    @property
    def monotone(self) -> bool:
        """The differences keep their sign and shrink: an observed order exists."""
        return 0 <= self.factor < 1

    @property
    def converging(self) -> bool:
        """The differences shrink (|q| < 1): a limit exists (monotone or alternating)."""
        return abs(self.factor) < 1


def richardson(values: Sequence[float], ratio: float = 2.0) -> Extrapolation:
    """Contraction factor, observed order and limit (module docstring) of ``values`` =
    f(h), f(h/r), f(h/r^2)."""
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise InputError(
            "richardson", "values", "three finite solutions f(h), f(h/r), f(h/r^2)", list(values)
        )
    if not ratio > 1:
        raise InputError("richardson", "ratio", "a refinement ratio > 1", got=ratio)
    f1, f2, f3 = (float(v) for v in values)
    d12, d23 = f1 - f2, f2 - f3
    if d12 == 0:
        q = 0.0 if d23 == 0 else math.copysign(math.inf, d23)
    else:
        q = d23 / d12
    order = -math.log(q) / math.log(ratio) if 0 < q < 1 else (math.inf if q == 0 else math.nan)
    limit = f3 - d23 * q / (1 - q) if abs(q) < 1 else math.nan
    return Extrapolation(q, order, limit, f3, ratio)


def power_law(steps: Sequence[float], values: Sequence[float]) -> Extrapolation:
    """Observed order and limit (module docstring) of ``values`` = f(h1), f(h2), f(h3) at
    ``steps`` h1 > h2 > h3 > 0 (any unit). ``factor`` is ``(f2 - f3) / (f1 - f2)``, ``ratio``
    ``h2 / h3``; order and limit are nan unless the differences keep their sign and shrink
    fast enough for an order above 0 (with unequal ratios ``factor`` may then exceed 1: test
    the order, not ``monotone``)."""
    h = [float(v) for v in steps]
    f = [float(v) for v in values]
    if len(h) != 3 or len(f) != 3 or not all(math.isfinite(v) for v in h + f):
        raise InputError("power_law", "values", "three finite solutions at three steps", f)
    if not h[0] > h[1] > h[2] > 0:
        raise InputError("power_law", "steps", "steps h1 > h2 > h3 > 0", got=h)
    d12, d23 = f[0] - f[1], f[1] - f[2]
    factor = d23 / d12 if d12 else (0.0 if d23 == 0 else math.copysign(math.inf, d23))
    nan = Extrapolation(factor, math.nan, math.nan, f[2], h[1] / h[2])
    if d23 == 0 or not 0 < factor:
        return nan
    target = d12 / d23

    def gap(p: float) -> float:
        return (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p) - target

    low, high = 1e-6, 1.0
    if gap(low) >= 0:  # the differences shrink too slowly for a positive order
        return nan
    while gap(high) < 0:
        high *= 2.0
        if high > 64:
            return nan
    p = brentq(gap, low, high, xtol=1e-12)
    limit = f[2] - d23 * h[2] ** p / (h[1] ** p - h[2] ** p)
    return Extrapolation(factor, p, limit, f[2], h[1] / h[2])


@dataclass(frozen=True)
class TimeStepStudy:
    """The axis ratio b/a at dt, dt/2, dt/4, ...: where it was read (``"x = 0"``, or ``"the
    end of the runs"`` when a run does not reach the junction), the change of 1 - b/a from dt
    to dt/2 (%), and with three or more runs the limit dt -> 0 of the finest three."""

    dt_s: float
    ratios: tuple[float, ...]
    where: str
    change_pct: float
    extrapolation: Extrapolation | None

    def metrics(self) -> dict[str, float]:
        """The case's metrics: ``dt_change_pct``; ``dt_order``, ``dt_factor`` (three runs);
        ``ratio_dt_limit``, ``deformation_dt_limit``, ``ratio_dt_error_pct`` (a limit)."""
        out = {"dt_change_pct": self.change_pct}
        ex = self.extrapolation
        if ex is not None:
            out.update(dt_order=ex.order, dt_factor=ex.factor)
            if ex.converging:
                out.update(
                    ratio_dt_limit=ex.limit,
                    deformation_dt_limit=1 - ex.limit,
                    ratio_dt_error_pct=100 * abs(self.ratios[0] / ex.limit - 1),
                )
        return out


def common_reading(
    at_junction: Sequence[float], at_end: Sequence[float]
) -> tuple[str, tuple[float, ...]]:
    """Where runs compared with each other are read, and their b/a there: at the junction
    (x = 0) when every run reaches it, else at the end of the runs (a nan in ``at_junction``
    marks a run that did not reach x = 0). Returns ``("x = 0", at_junction)`` or ``("the end
    of the runs", at_end)``."""
    if len(at_end) != len(at_junction):
        raise InputError("common_reading", "at_end", f"{len(at_junction)} ratios, one per run")
    if all(math.isfinite(v) for v in at_junction):
        return "x = 0", tuple(float(v) for v in at_junction)
    return "the end of the runs", tuple(float(v) for v in at_end)


def time_step_study(
    dt_s: float, at_junction: Sequence[float], at_end: Sequence[float]
) -> TimeStepStudy:
    """b/a per time step dt, dt/2, ... read where :func:`common_reading` says (x = 0, or the
    end of the runs when one of them did not reach it); at least two runs."""
    if len(at_junction) < 2 or len(at_end) != len(at_junction):
        raise InputError(
            "time_step_study", "at_junction", "ratios of two or more runs (dt, dt/2, ...)"
        )
    where, ratios = common_reading(at_junction, at_end)
    change = 100 * abs((1 - ratios[1]) / (1 - ratios[0]) - 1)
    ex = richardson(ratios[-3:]) if len(ratios) >= 3 else None
    return TimeStepStudy(dt_s, ratios, where, change, ex)
