"""The creep record of a force-clamp hold: time, force, indentation (data type only).

Module order (no cycles): this data type at the bottom, the readers above it
(:mod:`afm.curve_io`, :mod:`afm.instrument_io`), the fits above both (:mod:`afm.creep`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from oocyte_fe.checks import QUANTITIES, finite_column, increasing, numbers_array
from oocyte_fe.errors import InputError

FORCE_CLAMP_TOLERANCE = 0.05
"""Largest relative spread (SD / mean) of the force during the hold accepted as clamped."""
SHRINK_SIGMAS = 4.0
"""A hold whose indentation falls by more than this many standard errors is refused."""


@dataclass(frozen=True)
class CreepData:
    """A force-clamp hold: time [s] from the start of the hold, force [nN], indentation [um]."""

    time_s: np.ndarray
    force_nN: np.ndarray
    indentation_um: np.ndarray
    source: str = "<input>"

    def __post_init__(self) -> None:
        src = self.source
        t = np.asarray(self.time_s, dtype=float)
        f = np.asarray(self.force_nN, dtype=float)
        d = np.asarray(self.indentation_um, dtype=float)
        if t.ndim != 1 or f.shape != t.shape or d.shape != t.shape:
            raise InputError(src, "time_s", "equal-length 1-D columns time, force, indentation")
        if t.size < 10:
            raise InputError(src, "time_s", "at least 10 samples", t.size)
        for name, values in (("force_nN", f), ("indentation_um", d)):
            finite_column(src, name, values)
        t = increasing(src, "time_s", t)
        if np.any(d <= 0):
            raise InputError(src, "indentation_um", "positive indentation during the hold")
        # physical magnitudes: the spread and noise below would overflow on 1e308 values
        numbers_array(src, "indentation_um", d, le=QUANTITIES["length_um"][1])
        force_max = QUANTITIES["force_nN"][1]
        numbers_array(src, "force_nN", f, ge=-force_max, le=force_max)
        mean = float(np.mean(f))
        if not mean > 0:
            raise InputError(
                src,
                "force_nN",
                "a positive clamped force (its mean over the hold > 0: the probe pushes on the "
                "cell)",
                f"mean = {mean:.3g} nN",
            )
        spread = float(np.std(f)) / mean
        if not spread <= FORCE_CLAMP_TOLERANCE:
            raise InputError(
                src,
                "force_nN",
                f"a clamped force (SD/mean <= {FORCE_CLAMP_TOLERANCE:g} over the hold)",
                f"SD/mean = {spread:.3g}",
            )
        check_creeping(d, src)
        object.__setattr__(self, "time_s", t - t[0])
        object.__setattr__(self, "force_nN", f)
        object.__setattr__(self, "indentation_um", d)

    @property
    def clamp_force_nN(self) -> float:
        """Mean force over the hold, nN (the F0 of Lee-Radok)."""
        return float(np.mean(self.force_nN))


def check_creeping(indentation_um: np.ndarray, source: str = "<input>") -> None:
    """Refuse a hold whose indentation shrinks: under a clamped force it can only grow.

    The mean indentation of the last fifth of the hold is compared with that of the first
    fifth; a fall larger than :data:`SHRINK_SIGMAS` standard errors (noise from the
    point-to-point differences, sigma = SD(diff) / sqrt(2)) is refused. Checked when a
    :class:`CreepData` is made, so every reader refuses such a record.
    """
    d = np.asarray(indentation_um, dtype=float)
    n = max(d.size // 5, 2)
    first, last = float(np.mean(d[:n])), float(np.mean(d[-n:]))
    sigma = float(np.std(np.diff(d))) / math.sqrt(2.0)
    if first - last > SHRINK_SIGMAS * sigma * math.sqrt(2.0 / n) + 1e-12 * first:
        raise InputError(
            source,
            "indentation_um",
            "an indentation that does not shrink during the hold (creep under a clamped "
            "force; check the sign of height/indentation and that the record is the hold)",
            f"mean {first:.4g} um over rows 1-{n}, "
            f"{last:.4g} um over rows {d.size - n + 1}-{d.size}",
        )
