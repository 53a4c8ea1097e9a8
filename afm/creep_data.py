"""The creep record of a force-clamp hold: time, force, indentation (data type only).

Module order (no cycles): this data type at the bottom, the readers above it
(:mod:`afm.curve_io`, :mod:`afm.instrument_io`), the fits above both (:mod:`afm.creep`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from oocyte_fe.errors import InputError

FORCE_CLAMP_TOLERANCE = 0.05
"""Largest relative spread (SD / mean) of the force during the hold accepted as clamped."""


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
        for name, values in (("time_s", t), ("force_nN", f), ("indentation_um", d)):
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                raise InputError(src, name, f"finite numbers (NaN/inf at row {bad[0]})")
        if np.any(np.diff(t) <= 0):
            raise InputError(src, "time_s", "strictly increasing time")
        if np.any(d <= 0):
            raise InputError(src, "indentation_um", "positive indentation during the hold")
        mean = float(np.mean(f))
        spread = float(np.std(f)) / mean if mean > 0 else math.inf
        if not spread <= FORCE_CLAMP_TOLERANCE:
            raise InputError(
                src,
                "force_nN",
                f"a clamped force (SD/mean <= {FORCE_CLAMP_TOLERANCE:g} over the hold)",
                f"SD/mean = {spread:.3g}",
            )
        object.__setattr__(self, "time_s", t - t[0])
        object.__setattr__(self, "force_nN", f)
        object.__setattr__(self, "indentation_um", d)

    @property
    def clamp_force_nN(self) -> float:
        """Mean force over the hold, nN (the F0 of Lee-Radok)."""
        return float(np.mean(self.force_nN))
