"""A force ramp in time: approach and (optionally) retract of one curve, on a uniform grid.

Convention as :mod:`afm.curve`: the piezo travels towards the sample during the approach,
force positive when pressing; tip position ``x = piezo - F/k`` [um], time t [s]. The retract
follows the approach in time (the travel turns at its farthest point). Ting's convolution
needs a uniform time grid: samples whose steps vary by more than ``UNIFORM_TOLERANCE`` are
interpolated linearly onto one (step: the median step).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from afm.baseline import fit_baseline
from afm.curve import MIN_POINTS, ForceCurve
from oocyte_fe.checks import float_array, increasing, positive
from oocyte_fe.errors import InputError

TURN_SIGMAS = 4.0
"""Tip positions within this many noise SDs of the farthest one still belong to the approach."""
HOLD_TIME_FRACTION = 0.05
"""A run near the farthest tip position longer than this fraction of the record is a hold."""
HOLD_FRACTION = 0.01
"""Tip positions within this fraction of the travel of the farthest one are the hold (dwell)."""
UNIFORM_TOLERANCE = 1e-3
"""Largest deviation of a time step from the median step (relative) taken as uniform."""


@dataclass(frozen=True)
class RampCurve:
    """Time [s], tip position [um] and force [nN] (baseline removed) of one ramp.

    ``turn`` is the end of the approach (the last point within noise of the farthest tip
    position, after any hold there); points after it are the retract. ``resampled`` tells
    whether the times were made uniform.
    """

    time_s: np.ndarray
    tip_position_um: np.ndarray
    force_nN: np.ndarray
    source: str = "<input>"
    resampled: bool = False

    def __post_init__(self) -> None:
        src = self.source
        t = float_array(src, "time_s", self.time_s)
        x = float_array(src, "tip_position_um", self.tip_position_um)
        f = float_array(src, "force_nN", self.force_nN)
        if t.ndim != 1 or x.shape != t.shape or f.shape != t.shape:
            raise InputError(src, "force_nN", "one time, tip position and force per row (1-D)")
        if t.size < MIN_POINTS:
            raise InputError(src, "time_s", f"at least {MIN_POINTS} points", t.size)
        t = increasing(src, "time_s", t)  # names the first bad data row
        for name, values, bound in (("tip_position_um", x, 1e6), ("force_nN", f, 1e12)):
            if not np.all(np.isfinite(values) & (np.abs(values) <= bound)):
                raise InputError(src, name, f"finite numbers of magnitude at most {bound:g}")
        steps = np.diff(t)
        step = float(np.median(steps))
        resampled = self.resampled
        if float(np.max(np.abs(steps - step))) > UNIFORM_TOLERANCE * step:
            grid = t[0] + step * np.arange(int(np.floor((t[-1] - t[0]) / step + 1e-9)) + 1)
            x, f, t, resampled = np.interp(grid, t, x), np.interp(grid, t, f), grid, True
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "tip_position_um", x)
        object.__setattr__(self, "force_nN", f)
        object.__setattr__(self, "resampled", resampled)

    @property
    def step_s(self) -> float:
        """Time step h of the uniform grid, s."""
        return float((self.time_s[-1] - self.time_s[0]) / (self.time_s.size - 1))

    @property
    def turn(self) -> int:
        """Index of the last approach point: the last within noise of the farthest tip position.

        Noise: sigma = 1.4826 MAD(second differences) / sqrt(6). When the points within
        :data:`TURN_SIGMAS` sigma of the farthest tip position span more than
        :data:`HOLD_TIME_FRACTION` of the record (a hold at the farthest travel:
        stress relaxation, the contact not shrinking), the last of them ends the approach: the
        turn is where the travel reverses, or the last point when it never does. Otherwise
        (a ramp turning at once) the turn is the farthest point.
        """
        x, t = self.tip_position_um, self.time_s
        d2 = np.diff(x, 2)
        sigma = 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / math.sqrt(6.0)
        farthest = int(np.argmax(x))
        near = np.flatnonzero(x >= x[farthest] - TURN_SIGMAS * sigma)
        last = int(near[-1])
        held = t[last] - t[near[0]] > HOLD_TIME_FRACTION * (t[-1] - t[0])
        return last if held else farthest

    @property
    def hold_start(self) -> int:
        """First index within :data:`HOLD_FRACTION` of the tip's travel of its farthest
        position: with :attr:`turn`, the hold (dwell) at the farthest travel, if any."""
        x = self.tip_position_um
        return int(np.argmax(x >= x.max() - HOLD_FRACTION * float(np.ptp(x))))

    def approach(self) -> RampCurve:
        """The approach alone (points up to the turn)."""
        end = self.turn + 1
        return RampCurve(
            self.time_s[:end], self.tip_position_um[:end], self.force_nN[:end], self.source
        )


def ramp_from_piezo(
    time_s: np.ndarray,
    piezo_um: np.ndarray,
    force_nN: np.ndarray,
    spring_constant_nN_per_um: float,
    source: str = "<input>",
) -> RampCurve:
    """A ramp from recorded piezo travel, force and time (approach, then retract if any).

    The baseline (a line ``F0 + b z`` on the non-contact part of the approach,
    :func:`afm.baseline.fit_baseline`) is removed from both segments and the tip position is
    ``piezo - F/k``. The approach and the retract share the line: a viscous drag on the
    cantilever, which changes sign with the direction of travel, is not removed (docs/afm.md).
    """
    t = float_array(source, "time_s", time_s)
    piezo = float_array(source, "piezo_um", piezo_um)
    force = float_array(source, "force_nN", force_nN)
    k = positive(source, "spring_constant", spring_constant_nN_per_um)
    if piezo.shape != force.shape or piezo.ndim != 1:
        raise InputError(source, "force_nN", "one force per piezo position (1-D columns)")
    end = int(np.argmax(piezo)) + 1
    approach = ForceCurve(piezo[:end], force[:end], k, source)
    baseline = fit_baseline(approach)
    corrected = force - baseline(piezo)
    return RampCurve(t, piezo - corrected / k, corrected, source)
