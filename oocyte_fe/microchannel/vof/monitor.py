"""Reading a ``multiphaseInterFoam`` or ``interIsoFoam`` log as it is written: progress, and
the silent failures.

The solver does not stop by itself when a VOF run goes wrong; on the oocyte case it keeps
stepping with garbage. :class:`SolverMonitor` is fed the log line by line and reports the
first of these, with the time and the numbers:

- **dt collapse**: the (adaptive) time step falls below ``dt_collapse`` x the set time step;
- **Courant number far above the physical one**: ``Co_max > courant_factor U_ref dt / dx``,
  where ``U_ref`` is the fastest velocity the inflow can produce (1.5 x the largest mean);
- **velocity above a bound**: ``max |U| > velocity_factor U_ref`` (fieldMinMax output);
- **unbounded alpha**: a phase fraction below ``-alpha_tolerance`` or above
  ``1 + alpha_tolerance``.

Progress is the simulated time over the end time, the Courant number and an ETA from the
wall-clock rate so far. The monitor also keeps the largest Courant number of the run and the
largest interface Courant number (the solver's ``Interface Courant Number`` line, cells of
the interface only), and each step's largest Courant number with its time
(:meth:`SolverMonitor.largest_courant_until`): a fixed-step run whose Courant number leaps
during the run has gone through an unstable episode even when none of the failures above
fires (the cases check it up to the last state they read, ``max_courant_read``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from time import monotonic

_NUM = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|-?nan|-?inf)"
_TIME = re.compile(rf"^Time = {_NUM}")
_DT = re.compile(rf"^deltaT = {_NUM}")
_CO = re.compile(rf"^Courant Number mean: {_NUM} max: {_NUM}")
_ICO = re.compile(rf"^Interface Courant Number mean: {_NUM} max: {_NUM}")
_LO, _HI = _NUM.replace("(", "(?P<lo>", 1), _NUM.replace("(", "(?P<hi>", 1)
_ALPHA = re.compile(rf"^(?P<name>[\w.-]+) volume fraction, min, max = {_NUM} {_LO} {_HI}")
# interIsoFoam: "Phase-1 volume fraction = v  Min(alpha.x) = a  Max(alpha.x) = b"
_ALPHA1 = re.compile(
    rf"^Phase-1 volume fraction = {_NUM}\s+Min\((?P<name>[\w.-]+)\) = {_LO}"
    rf"\s+Max\([\w.-]+\) = {_HI}"
)
_UMAX = re.compile(rf"max\(mag\(U\)\) = {_NUM}")


@dataclass(frozen=True)
class Limits:
    """Thresholds of the failure checks (module docstring)."""

    dt_collapse: float = 0.05
    courant_factor: float = 10.0
    velocity_factor: float = 5.0
    alpha_tolerance: float = 1e-2


def _larger(so_far: float, value: str) -> float:
    """The larger of ``so_far`` (nan: none yet) and ``value`` (a nan Courant number fails the
    run by the Courant check)."""
    v = float(value)
    return v if math.isnan(so_far) or not v <= so_far else so_far


@dataclass(frozen=True)
class Failure:
    """Which check failed, at which simulated time, with the numbers."""

    mode: str  # "dt collapse", "Courant", "velocity" or "alpha"
    time: float
    message: str


@dataclass
class SolverMonitor:
    """Fed log lines by :meth:`feed`; ``velocity_ref`` in m/s, ``dx`` in m, times in s."""

    end_time: float
    time_step: float
    dx: float
    velocity_ref: float
    limits: Limits = field(default_factory=Limits)
    start_time: float = 0.0
    time: float = 0.0
    delta_t: float = math.nan
    courant: float = math.nan
    max_velocity: float = math.nan
    largest_courant: float = math.nan  # over the run so far
    largest_interface_courant: float = math.nan
    courant_trace: list[tuple[float, float]] = field(default_factory=list)  # (t s, max Co)
    steps: int = 0
    clock_start: float = field(default_factory=monotonic)
    failure: Failure | None = None

    @property
    def courant_bound(self) -> float:
        """``courant_factor`` x the physical Courant number ``U_ref dt / dx``."""
        dt = self.delta_t if math.isfinite(self.delta_t) else self.time_step
        return self.limits.courant_factor * self.velocity_ref * dt / self.dx

    def largest_courant_until(self, time: float) -> float:
        """The largest Courant number of the steps up to ``time`` (s); nan before any step,
        or when one of them logged nan (which fails the Courant check, like a large one)."""
        co = [c for t, c in self.courant_trace if t <= time]
        return math.nan if not co or any(math.isnan(c) for c in co) else max(co)

    def _fail(self, mode: str, message: str) -> Failure:
        self.failure = Failure(mode, self.time, f"{mode} at t = {self.time:.6g} s: {message}")
        return self.failure

    def feed(self, line: str) -> Failure | None:
        """Read one log line; return the first failure found (and keep it), else None."""
        if self.failure is not None:
            return self.failure
        line = line.strip()
        if m := _TIME.match(line):
            self.time = float(m.group(1))
            self.steps += 1
        elif m := _DT.match(line):
            self.delta_t = float(m.group(1))
            if not self.delta_t >= self.limits.dt_collapse * self.time_step:
                return self._fail(
                    "dt collapse",
                    f"deltaT = {self.delta_t:.3g} s < {self.limits.dt_collapse:g} x the set "
                    f"{self.time_step:.3g} s",
                )
        elif m := _ICO.match(line):
            self.largest_interface_courant = _larger(self.largest_interface_courant, m.group(2))
        elif m := _CO.match(line):
            self.courant = float(m.group(2))
            self.courant_trace.append((self.time, self.courant))
            self.largest_courant = _larger(self.largest_courant, m.group(2))
            if not self.courant <= max(self.courant_bound, 1e-12):
                return self._fail(
                    "Courant",
                    f"max Courant number {self.courant:.3g} > {self.courant_bound:.3g} "
                    f"({self.limits.courant_factor:g} x the physical U dt/dx)",
                )
        elif m := _ALPHA.match(line) or _ALPHA1.match(line):
            lo, hi = float(m.group("lo")), float(m.group("hi"))
            tol = self.limits.alpha_tolerance
            if not (lo >= -tol and hi <= 1.0 + tol):
                return self._fail(
                    "alpha",
                    f"{m.group('name')} min {lo:.3g}, max {hi:.3g} outside [-{tol:g}, 1+{tol:g}]",
                )
        elif m := _UMAX.search(line):
            self.max_velocity = float(m.group(1))
            bound = self.limits.velocity_factor * self.velocity_ref
            if not self.max_velocity <= bound:
                return self._fail(
                    "velocity", f"max |U| = {self.max_velocity:.3g} m/s > {bound:.3g} m/s"
                )
        return None

    @property
    def fraction(self) -> float:
        span = self.end_time - self.start_time
        return min(max((self.time - self.start_time) / span, 0.0), 1.0) if span > 0 else 1.0

    def eta(self) -> float:
        """Seconds of wall clock left at the rate so far (nan before the first step)."""
        done = self.fraction
        elapsed = monotonic() - self.clock_start
        return elapsed * (1.0 - done) / done if done > 0 else math.nan

    def progress(self) -> str:
        """One line: simulated time / end time, Courant number, max |U|, ETA."""
        return (
            f"t = {self.time:.4g} / {self.end_time:.4g} s ({100 * self.fraction:.0f} %), "
            f"Co {self.courant:.3g}, max|U| {self.max_velocity:.3g} m/s, ETA {self.eta():.0f} s"
        )
