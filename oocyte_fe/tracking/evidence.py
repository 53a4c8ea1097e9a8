"""Is there something to track in the box? The contrast-to-noise ratio of a box and the
confidence factor it gives.

The reliability ``r`` of :mod:`.update` is relative: the response is compared with its own
running means, which the first frames set. On a blank clip or a box drawn on a featureless
area those first frames are as empty as the rest, every response is alike and ``r`` stays
about ``1 / beta_1`` = 1.43, the value of a good track. The contrast-to-noise ratio is
absolute::

    s = std_box(G_1 * I) / (k_1 sigma_n),   k_1 = sqrt(sum g_1^2),
    sigma_n = 1.4826 median |d - median d| / sqrt(2),   d = I(x + 1, y) - I(x, y)

``G_1 * I`` is the image smoothed by a unit Gaussian (px), ``sigma_n`` the pixel noise from
the median absolute deviation of horizontal differences over the search window (the
differences of smooth structure are small; shot noise dominates them; the disjoint pairs
of every other row are used), and ``k_1`` the factor
by which the same smoothing divides the standard deviation of white noise (0.28). So ``s`` is
about 1 for pure noise whatever its level, 0 for a constant image, and grows with the
structure in the box. The confidence factor maps it linearly::

    e = clip((s - s_0) / (s_1 - s_0), 0, 1),   s_0 = 1.3,  s_1 = 2.0

and the confidence written per frame is ``r e`` (:class:`.tracker.FrameEstimate`). Measured
on 8 of the 24 benchmark sequences (every third, 120 frames; docs/tracking.md): white noise
1.14, a box on the textured cytoplasm 1.3-1.7, the 4 % spindle 1.8-2.6 (so ``e`` >= 0.7 on
it), the 8 % spindle 3.1-5. ``s_0``, ``s_1`` sit between those levels; they are not tuned on
tracking figures (``e`` does not change the track).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

S0 = 1.3
S1 = 2.0
SMOOTH_PX = 1.0
K_SMOOTH = float(np.sqrt(np.sum(ndimage.gaussian_filter(np.pad([[1.0]], 8), SMOOTH_PX) ** 2)))
"""``k_1``: standard deviation of unit-variance white noise after the unit Gaussian."""


def noise_sigma(window: np.ndarray) -> float:
    """``sigma_n``: robust pixel noise of a window from its horizontal differences (on every
    other row and column pair: the median needs no more)."""
    w = np.asarray(window, dtype=float)[::2]
    d = (w[:, 1::2] - w[:, : w.shape[1] - 1 : 2]).ravel()
    if d.size == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0))


def contrast_to_noise(box_patch: np.ndarray, sigma_n: float) -> float:
    """``s``: the smoothed box's standard deviation over that of smoothed white noise of
    ``sigma_n``; 0 for a constant box (to rounding), inf for structure without noise."""
    patch = np.asarray(box_patch, dtype=float)
    spread = float(ndimage.gaussian_filter(patch, SMOOTH_PX).std())
    if spread <= 1e-9 * (abs(float(patch.mean())) + 1.0):
        return 0.0
    return spread / (K_SMOOTH * sigma_n) if sigma_n > 0 else float("inf")


def confidence_factor(s: float) -> float:
    """``e = clip((s - s_0) / (s_1 - s_0), 0, 1)``."""
    return float(np.clip((s - S0) / (S1 - S0), 0.0, 1.0))
