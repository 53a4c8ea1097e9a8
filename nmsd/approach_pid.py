"""Incremental PID approach of the pipette to the removal point (eqs 9-10 of seed 000).

Per axis, sampled every T (s):

    e(t) = x_d(t) - x(t)                                                        (eq 9)
    u(t) = u(t-T) + Kp [e(t) - e(t-T)] + Ki e(t) + Kd [e(t) - 2 e(t-T) + e(t-2T)]   (eq 10)

``u`` is the position command (um) sent to the micromanipulator, which moves in steps of
its positioning resolution (0.04 um, Sutter MP285) and follows the quantised command with a
first-order lag ``tau dx/dt = u_q - x`` (tau in s, stepped exactly over T). ``x_d`` runs
along the line from the mouth's start to the current target at ``speed`` (um/s) and then
stays at the target; the target may move (updated from the model as the spindle moves).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class PidGains:
    """Gains of eq 10 (dimensionless), sampling period T (s), actuator lag tau (s)."""

    kp: float = 0.2
    ki: float = 0.3
    kd: float = 0.0
    period_s: float = 0.01
    lag_s: float = 0.02
    resolution_um: float = 0.04

    def __post_init__(self) -> None:
        for name in ("kp", "ki", "kd", "lag_s", "resolution_um"):
            checks.number("PidGains", name, getattr(self, name), ge=0, le=1e9)
        checks.number("PidGains", "period_s", self.period_s, gt=0, le=1e6)


@dataclass(frozen=True)
class ApproachTrace:
    """Time (s), position (k, 2) um, reference (k, 2) um, target (k, 2) um; summary figures."""

    time_s: np.ndarray
    position_um: np.ndarray
    reference_um: np.ndarray
    target_um: np.ndarray
    final_error_um: float
    overshoot_um: float
    settling_time_s: float


MAX_PERIODS = 1_000_000
"""Most controller periods one approach may simulate."""


def _goal(target: Callable[[float], np.ndarray], progress_um: float) -> np.ndarray:
    """``target(progress_um)`` checked: a finite (x, y) point in um (NaN would steer nowhere)."""
    goal = checks.float_array("pid_approach", "target", target(progress_um))
    if goal.shape != (2,) or not np.all(np.abs(goal) <= 1e9):
        raise InputError(
            "pid_approach",
            "target",
            "a callable returning a finite (x, y) point in um, |x|, |y| <= 1e9",
            got=goal.tolist(),
        )
    return goal


def pid_approach(
    target: Callable[[float], np.ndarray],
    gains: PidGains,
    start_um: tuple[float, float] = (0.0, 0.0),
    speed_um_s: float = 30.0,
    duration_s: float = 3.0,
    band_um: float = 0.1,
) -> ApproachTrace:
    """Simulate the approach; ``target(progress_um)`` is the removal point (paper frame, um)
    given how far the pipette has travelled, so the target can follow the moving spindle.

    The work is ``duration_s / period_s`` controller periods, at most :data:`MAX_PERIODS`.
    """
    speed_um_s = checks.number("pid_approach", "speed_um_s", speed_um_s, ge=1e-9, le=1e9)
    duration_s = checks.number("pid_approach", "duration_s", duration_s, gt=0, le=1e6)
    band_um = checks.number("pid_approach", "band_um", band_um, gt=0)
    if len(start_um) != 2:
        raise InputError("pid_approach", "start_um", "an (x, y) pair", got=start_um)
    for value in start_um:
        checks.number("pid_approach", "start_um", value, ge=-1e9, le=1e9)
    steps = int(round(duration_s / gains.period_s))
    if steps > MAX_PERIODS:
        raise InputError(
            "pid_approach",
            "duration_s/period_s",
            f"at most {MAX_PERIODS:,} controller periods (a longer period or a shorter approach)",
            got=f"{duration_s:g} s / {gains.period_s:g} s",
        )
    x = np.array(start_um, dtype=float)
    start = x.copy()
    u = x.copy()
    e1 = np.zeros(2)
    e2 = np.zeros(2)
    decay = np.exp(-gains.period_s / gains.lag_s) if gains.lag_s > 0 else 0.0
    ts, xs, rs, gs = [], [], [], []
    for k in range(steps + 1):
        t = k * gains.period_s
        goal = _goal(target, float(np.linalg.norm(x - start)))
        line = goal - start
        length = float(np.linalg.norm(line))
        reach = min(speed_um_s * t, length)
        xd = start + (line / length * reach if length > 0 else 0.0)
        e = xd - x
        u = u + gains.kp * (e - e1) + gains.ki * e + gains.kd * (e - 2 * e1 + e2)
        e2, e1 = e1, e
        ts.append(t)
        xs.append(x.copy())
        rs.append(xd)
        gs.append(goal)
        command = (
            gains.resolution_um * np.round(u / gains.resolution_um) if gains.resolution_um else u
        )
        x = command + (x - command) * decay
    time, pos, goals = np.array(ts), np.array(xs), np.array(gs)
    error = np.linalg.norm(pos - goals, axis=1)
    axis = (goals[-1] - start) / max(float(np.linalg.norm(goals[-1] - start)), 1e-12)
    overshoot = max(0.0, float(np.max((pos - goals[-1]) @ axis)))
    outside = np.flatnonzero(error > band_um)
    settling = (
        float(time[outside[-1] + 1])
        if len(outside) and outside[-1] + 1 < len(time)
        else (0.0 if not len(outside) else float("inf"))
    )
    return ApproachTrace(time, pos, np.array(rs), goals, float(error[-1]), overshoot, settling)
