"""Baseline: offset and tilt of the force on the non-contact part, fitted and removed.

Far from the sample the force should be zero; an offset (deflection not zeroed) and a tilt
(optical interference, drag) remain. A straight line ``F0 + b * piezo`` is fitted by least
squares to the non-contact part and subtracted from the whole curve. The non-contact part is
found in two passes: a line through the first ``start_fraction`` of the piezo range gives the
noise level; the contact estimate by deviation from that line ends the non-contact part, less a
safety margin, and the line is fitted again on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from afm.contact_point import deviation_index
from afm.curve import ForceCurve
from afm.numerics import dot
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class Baseline:
    """Fitted baseline ``F = offset + slope * piezo``, noise = SD of its residual."""

    offset_nN: float
    slope_nN_per_um: float
    noise_nN: float
    n_points: int

    def __call__(self, piezo_um: np.ndarray) -> np.ndarray:
        return self.offset_nN + self.slope_nN_per_um * piezo_um


def _line(piezo: np.ndarray, force: np.ndarray) -> Baseline:
    # closed-form least-squares line (centred sums)
    pm, fm = float(np.mean(piezo)), float(np.mean(force))
    dp = piezo - pm
    slope = float(dot(dp, force - fm) / dot(dp, dp))
    offset = fm - slope * pm
    residual = force - (offset + slope * piezo)
    noise = float(np.sqrt(dot(residual, residual) / (force.size - 2))) if force.size > 2 else 0.0
    return Baseline(float(offset), float(slope), noise, int(force.size))


def fit_baseline(
    curve: ForceCurve, start_fraction: float = 0.2, margin_fraction: float = 0.1
) -> Baseline:
    """Fit the baseline line on the non-contact part of ``curve`` (two passes, see module)."""
    piezo, force = curve.piezo_um, curve.force_nN
    span = piezo[-1] - piezo[0]
    first = piezo <= piezo[0] + start_fraction * span
    if np.count_nonzero(first) < 3:
        raise InputError(curve.source, "baseline", "at least 3 points before contact")
    guess = _line(piezo[first], force[first])
    contact = deviation_index(force - guess(piezo), guess.noise_nN, source=curve.source)
    end = piezo[0] + (1.0 - margin_fraction) * (piezo[contact] - piezo[0])
    free = piezo <= end
    if np.count_nonzero(free) < 3:
        return guess
    return _line(piezo[free], force[free])


def baseline_before(
    curve: ForceCurve, contact_piezo_um: float, margin_fraction: float = 0.1
) -> Baseline:
    """The baseline line fitted on the points before a known contact (less the margin).

    Used to refine the baseline once a model fit has placed the contact point: the first
    estimate (:func:`fit_baseline`) ends at the deviation contact, which lags the true contact
    by the depth needed to rise above the noise, so its line can take in contact points.
    """
    piezo = curve.piezo_um
    end = piezo[0] + (1.0 - margin_fraction) * (contact_piezo_um - piezo[0])
    free = piezo <= end
    if np.count_nonzero(free) < 3:
        raise InputError(curve.source, "baseline", "at least 3 points before contact")
    return _line(piezo[free], curve.force_nN[free])


def remove_baseline(curve: ForceCurve, baseline: Baseline) -> ForceCurve:
    """The curve with the baseline subtracted from its force."""
    return curve.with_force(curve.force_nN - baseline(curve.piezo_um))
