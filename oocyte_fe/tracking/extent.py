"""The box's size from the spindle's own extent: second moments of its excess brightness.

The correlation filter (:mod:`.kcf`) finds where the target is, not how big it looks: KCF's
box keeps the first frame's size, and the success overlap (:mod:`.metrics`) is capped when
the spindle grows, shrinks, or turns (an axis-aligned box of a turned barrel changes both
sides). The spindle is brighter than the cytoplasm around it (birefringence under crossed
polarizers), so its extent along each image axis can be read from the image itself. In a
region of ``region`` x the box about the tracked centre, with ``m`` the region's median::

    x_i = (G_1 * I)_i / m - 1                  (excess brightness, smoothed over 1 px)
    w_i = max(x_i - x_half, 0),   x_half = 0.5 quantile_q(x over the inner half box)
    sigma_x^2 = sum w_i (u_i - u_bar)^2 / sum w_i,   sigma_y^2 likewise (u, v: pixel x, y)

(the half-maximum weights keep the cytoplasm's granules, the noise and dark objects out).
The box's sides scale with these spreads against those of the first frame::

    W_t = W_0 sigma_x,t / sigma_x,0,   H_t = H_0 sigma_y,t / sigma_y,0

smoothed over reliable frames, ``s <- s + rate (s_t - s)``, and held while the target is
lost or doubtful. The ratios stay in ``[1 / limit, limit]``. For an ellipse-like barrel of
semi-axes a, b at angle theta, ``sigma_x^2`` is proportional to ``a^2 cos^2 theta + b^2
sin^2 theta``, as the square of the half-width of its axis-aligned bounding box, so the
ratio follows growth and turning alike. Assumption: the spindle is the brightest structure
inside the inner half of its box (true once it is tracked; a droplet's bright rim in the
region lowers the estimate, hence the smoothing and limits).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oocyte_fe.tracking.evidence import inside
from oocyte_fe.tracking.window_stats import median, smooth


@dataclass(frozen=True)
class ExtentModel:
    """Settings of :class:`BoxExtent` (module doc).

    region: measured region, in box sizes.  quantile: q of the peak level in the inner box.
    rate: weight of a new reliable frame.  limit: largest scale factor either way.
    dark: a region with a pixel below ``dark`` x its median (the pipette's glass, a droplet's
    core) is not measured: it would lower the median and lift the cytoplasm into the weights.
    """

    region: float = 1.6
    quantile: float = 0.9
    rate: float = 0.1
    limit: float = 1.5
    dark: float = 0.7

    def __post_init__(self) -> None:
        if self.region < 1 or not 0 < self.quantile <= 1 or not 0 < self.rate <= 1:
            raise ValueError(f"expected region >= 1, 0 < quantile <= 1, 0 < rate <= 1: {self}")
        if self.limit < 1:
            raise ValueError(f"expected limit >= 1, got {self.limit}")


def spreads(
    frame: np.ndarray, centre: tuple[float, float], size: tuple[float, float], model: ExtentModel
) -> tuple[float, float] | None:
    """``(sigma_x, sigma_y)`` px of the excess brightness about ``centre`` (module doc);
    None if the region holds no bright structure or something dark (``model.dark``)."""
    region = inside(frame, centre, (size[0] * model.region, size[1] * model.region))
    if min(region.shape) < 4:
        return None
    level = median(region)
    if level <= 0 or float(region.min()) < model.dark * level:
        return None
    excess = smooth(region, 1.0) / level - 1.0
    rows, cols = region.shape
    ci, cj = rows // 2, cols // 2
    hi, hj = max(1, int(size[1] / 4)), max(1, int(size[0] / 4))
    core = excess[max(ci - hi, 0) : ci + hi + 1, max(cj - hj, 0) : cj + hj + 1]
    half = 0.5 * float(np.quantile(core, model.quantile))
    if half <= 0:
        return None
    weights = np.maximum(excess - half, 0.0)
    total = float(weights.sum())
    if total <= 0:
        return None
    v, u = np.indices(region.shape)
    mu_u = float(np.sum(weights * u)) / total
    mu_v = float(np.sum(weights * v)) / total
    sx = np.sqrt(float(np.sum(weights * (u - mu_u) ** 2)) / total)
    sy = np.sqrt(float(np.sum(weights * (v - mu_v) ** 2)) / total)
    return (sx, sy) if sx > 0 and sy > 0 else None


class BoxExtent:
    """The tracked box's size (w, h) px from :func:`spreads` (module doc)."""

    def __init__(
        self, frame: np.ndarray, centre: tuple[float, float], size: tuple[float, float],
        model: ExtentModel,
    ) -> None:  # fmt: skip
        self.model = model
        self.size0 = size
        self.scale = np.ones(2)
        self.ref = spreads(frame, centre, size, model)

    @property
    def size(self) -> tuple[float, float]:
        return self.size0[0] * float(self.scale[0]), self.size0[1] * float(self.scale[1])

    def update(self, frame: np.ndarray, centre: tuple[float, float]) -> None:
        """Fold a reliable frame's spreads into the scale (no-op without a reference)."""
        if self.ref is None:
            return
        now = spreads(frame, centre, self.size0, self.model)
        if now is None:
            return
        ratio = np.clip(np.divide(now, self.ref), 1 / self.model.limit, self.model.limit)
        self.scale += self.model.rate * (ratio - self.scale)
