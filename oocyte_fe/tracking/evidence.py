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

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from oocyte_fe.tracking.window_stats import median, smooth

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
    return float(1.4826 * median(np.abs(d - median(d))) / np.sqrt(2.0))


def contrast_to_noise(box_patch: np.ndarray, sigma_n: float) -> float:
    """``s``: the smoothed box's standard deviation over that of smoothed white noise of
    ``sigma_n``; 0 for a constant box (to rounding), inf for structure without noise."""
    patch = np.asarray(box_patch, dtype=float)
    spread = float(smooth(patch, SMOOTH_PX).std())
    if spread <= 1e-9 * (abs(float(patch.mean())) + 1.0):
        return 0.0
    return spread / (K_SMOOTH * sigma_n) if sigma_n > 0 else float("inf")


def confidence_factor(s: float) -> float:
    """``e = clip((s - s_0) / (s_1 - s_0), 0, 1)``."""
    return min(max((s - S0) / (S1 - S0), 0.0), 1.0)


def _gradient_noise_gain(sigma_px: float) -> float:
    """Variance of ``d/dx (G_sigma * n)`` (central differences) per unit variance of white
    noise ``n``: the sum of the squared kernel."""
    delta = np.zeros((33, 33))
    delta[16, 16] = 1.0
    gx = np.gradient(ndimage.gaussian_filter(delta, sigma_px), axis=1)
    return float(np.sum(gx**2))


ORIENT_SMOOTH_PX = 1.5
GRAD_NOISE_GAIN = _gradient_noise_gain(ORIENT_SMOOTH_PX)


def coherence(box_patch: np.ndarray, sigma_n: float) -> float:
    """Orientation coherence of the box's smoothed gradients, with the noise's share removed::

        J = sum_box (g_x^2, g_y^2, g_x g_y),  g = grad(G_1.5 * I)
        J_xx' = J_xx - N k_g sigma_n^2,  J_yy' = J_yy - N k_g sigma_n^2
        kappa = sqrt((J_xx' - J_yy')^2 + 4 J_xy^2) / (J_xx' + J_yy')

    (N pixels; ``k_g`` the gradient variance of unit white noise after the smoothing).
    ``kappa`` is 0 for an isotropic pattern (a round droplet centred in the box, noise) and
    near 1 for a pattern of one orientation (a barrel with fibres along its axis); it does
    not change when the pattern turns. 0 when no gradient energy is left above the noise."""
    img = smooth(box_patch, ORIENT_SMOOTH_PX)
    gy, gx = np.gradient(img)
    noise = img.size * GRAD_NOISE_GAIN * sigma_n**2
    jxx = float(np.sum(gx * gx)) - noise
    jyy = float(np.sum(gy * gy)) - noise
    jxy = float(np.sum(gx * gy))
    total = jxx + jyy
    if total <= 0:
        return 0.0
    return float(min(1.0, np.sqrt((jxx - jyy) ** 2 + 4 * jxy * jxy) / total))


def brightness(box_patch: np.ndarray, level: float) -> float:
    """``b = mean_box(I) / level - 1``: the box's mean relative to the window's median
    ``level`` (a gain of the illumination cancels)."""
    return float(np.mean(box_patch)) / level - 1.0 if level > 0 else 0.0


@dataclass(frozen=True)
class SignatureCheck:
    """Does a window look like the tracked spindle rather than a droplet, the pipette or bare
    cytoplasm? Rotation-free appearance measured on the central ``inner`` fraction of the box
    (less of a neighbouring droplet or the pipette's mouth gets in):

    - brightness ``b`` (:func:`brightness`, relative to the window's median): the
      birefringent spindle is a few % brighter than the cytoplasm; bare cytoplasm is at 0, a
      dark droplet or the pipette's glass below, a bright droplet far above;
    - coherence ``kappa`` (:func:`coherence`): the fibres and the barrel's long edges give
      one orientation; a round droplet or noise give none.

    References ``b_ref``, ``kappa_ref`` follow the target while it is tracked reliably
    (:class:`Signature`). A window passes if ``b_ref / band <= b <= band b_ref`` and
    ``kappa >= min_coherence kappa_ref``. Neither quantity changes when the spindle turns, so
    a turned spindle passes where the first frames' template (:mod:`.anchor`) fails it.

    band: allowed factor on ``b`` either way.  min_coherence: fraction of ``kappa_ref``.
    inner: side of the measured box as a fraction of the target box.  rate: exponential
    weight of a new reliable frame in the references (after the first ``warmup`` frames,
    their mean).  every: the references are updated on every ``every``-th reliable frame.
    learn: the filter's learning rate on a peak with ``r < 1`` the check holds
    (:mod:`.tracker`), as a multiple of the full rate ``eta0`` (at least the rate ``r``
    gives).
    """

    band: float = 1.6
    min_coherence: float = 0.2
    inner: float = 0.5
    rate: float = 0.05
    warmup: int = 5
    every: int = 2
    learn: float = 2.0

    def __post_init__(self) -> None:
        if self.band <= 1 or not 0 <= self.min_coherence <= 1 or not 0 < self.inner <= 1:
            raise ValueError(f"expected band > 1, 0 <= min_coherence <= 1, 0 < inner <= 1: {self}")
        if not 0 < self.rate <= 1 or self.warmup < 1 or self.every < 1 or self.learn < 0:
            raise ValueError(f"expected 0 < rate <= 1, learn >= 0, warmup, every >= 1: {self}")


def measure(
    frame: np.ndarray,
    centre: tuple[float, float],
    size: tuple[float, float],
    window: tuple[float, float],
) -> tuple[float, float]:
    """``(b, kappa)`` of the (w, h) box ``size`` px at ``centre`` px, with the median level
    and the noise taken over the (w, h) window ``window`` px (in-frame pixels only)."""
    box = inside(frame, centre, size)
    around = inside(frame, centre, window)
    if min(box.shape) < 3 or min(around.shape) < 3:
        return 0.0, 0.0
    level = median(around[::2, ::2])
    return brightness(box, level), coherence(box, noise_sigma(around))


def inside(frame: np.ndarray, centre: tuple[float, float], size: tuple[float, float]):
    """The frame's pixels inside the (w, h) rectangle ``size`` px about ``centre`` px."""
    rows, cols = frame.shape
    (x0, x1), (y0, y1) = (
        (min(max(round(c - n / 2), 0), m), min(max(round(c + n / 2), 0), m))
        for c, n, m in zip(centre, size, (cols, rows), strict=True)
    )
    return frame[y0:y1, x0:x1]


class Signature:
    """The target's reference ``(b_ref, kappa_ref)`` and the check of :class:`SignatureCheck`."""

    def __init__(
        self, check: SignatureCheck, size: tuple[float, float], window: tuple[float, float]
    ) -> None:
        self.check = check
        self.size = (max(3.0, size[0] * check.inner), max(3.0, size[1] * check.inner))
        self.window = window
        self.n = 0
        self.ref = np.zeros(2)

    def learn(self, frame: np.ndarray, centre: tuple[float, float]) -> None:
        """Fold a reliably tracked frame into the references (mean, then exponential)."""
        self.n += 1
        if self.n > self.check.warmup and self.n % self.check.every:
            return
        value = np.array(measure(frame, centre, self.size, self.window))
        rate = 1.0 / self.n if self.n <= self.check.warmup else self.check.rate
        self.ref += rate * (value - self.ref)

    def passes(self, frame: np.ndarray, centre: tuple[float, float]) -> bool:
        """True if the window at ``centre`` matches the references (always before any)."""
        if self.n == 0:
            return True
        b, kappa = measure(frame, centre, self.size, self.window)
        b_ref, kappa_ref = self.ref
        band = self.check.band
        lo, hi = sorted((b_ref / band, b_ref * band))
        return lo <= b <= hi and kappa >= self.check.min_coherence * kappa_ref
