"""Median and Gaussian smoothing of a search window, equal to the last bit to ``np.median``
and ``scipy.ndimage.gaussian_filter`` (reflect mode, truncated at 4 sigma), at a fraction of
their call cost on windows of a few thousand pixels.

A tracked frame takes about six medians and three smoothings of windows of 10^3-10^4 px; at
that size the library calls cost more in argument handling than in arithmetic
(``np.median`` of 2 304 values: 46 us, of which the partition is 8 us; the smoothing of a
30 x 44 box: 79 us, of which the two 1-D correlations are 20 us; measured 2026-12-07). Both
functions below do the same arithmetic in the same order as the library (the median of an
even count is ``(a + b) / 2`` of the two middle values, as ``np.median``'s mean of two; a
NaN anywhere gives NaN), so a track does not change by a bit
(``tests/test_tracking_window_stats.py``).
"""

from __future__ import annotations

import functools

import numpy as np
from scipy import ndimage


def median(values: np.ndarray) -> float:
    """Median of all elements (``np.median(values)``); NaN if any element is NaN."""
    flat = np.asarray(values, dtype=np.float64).ravel()
    n = flat.size
    if n == 0:
        return float("nan")
    k = n // 2
    part = np.partition(flat, (k - 1, k, n - 1) if n % 2 == 0 else (k, n - 1))
    if np.isnan(part[-1]):
        return float("nan")
    return float(part[k]) if n % 2 else float((part[k - 1] + part[k]) / 2.0)


@functools.lru_cache(maxsize=8)
def _weights(sigma: float) -> np.ndarray:
    """The Gaussian of ``sigma`` px sampled on ``-r..r``, ``r = int(4 sigma + 0.5)``, over its
    sum (``ndimage.gaussian_filter``'s kernel; symmetric, so correlation = convolution)."""
    radius = int(4.0 * sigma + 0.5)
    x = np.arange(-radius, radius + 1)
    phi = np.exp(-0.5 / (sigma * sigma) * x**2)
    weights = (phi / phi.sum())[::-1].copy()
    weights.flags.writeable = False
    return weights


def smooth(image: np.ndarray, sigma: float) -> np.ndarray:
    """``G_sigma * I`` of a 2-D image, px (``ndimage.gaussian_filter(image, sigma)``)."""
    image = np.asarray(image, dtype=np.float64)
    weights = _weights(float(sigma))
    out = np.empty_like(image)
    ndimage.correlate1d(image, weights, 0, out, "reflect", 0.0, 0)
    ndimage.correlate1d(out, weights, 1, out, "reflect", 0.0, 0)
    return out
