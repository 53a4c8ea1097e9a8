"""A 1-D scale filter (DSST, Danelljan, Haeger, Khan and Felsberg 2014, BMVC; 2017, TPAMI
39:1561): the box's size from a separate filter over scale samples of the target.

The translation filter (:mod:`.kcf`) finds where the target is; its box keeps the first size.
Around the tracked centre, ``S`` (odd) samples of the target at the scales

    c_n = c a^n,   n = -(S - 1)/2 ... (S - 1)/2        (a: the scale step, c: the current scale)

are taken, each a region of ``region`` x the first box x ``c_n`` resampled (a box average
over the template spacing, then bilinear) onto a fixed template of about
``template`` pixels with the box's aspect ratio. Each sample's features (the excess
brightness ``I / m - 1`` over the region's median ``m``, its gradient magnitude and / or the
doubled-angle gradient, :attr:`ScaleModel.features`) are one column ``f(n)`` of ``d``
values. The filter ``w`` (d values) is the ridge regression of the label ``g(n) = exp(-n^2 /
(2 sigma^2))`` (``sigma = sigma_factor S / sqrt(33)`` samples, DSST's value for S = 33) on the
model's samples ``F_m = [f_m(n)]``, learned with its own rate ``eta``::

    F_m <- (1 - eta) F_m + eta F_t
    w    = F_m (F_m^T F_m + lambda' I)^-1 g,   lambda' = lambda tr(F_m^T F_m) / S
    y(n) = z(n)^T w                          (z: the samples of a new frame, current scale)

A target grown by ``a^m`` answers at ``n = m``. The peak ``n*`` is refined by a parabola
through the maximum and its neighbours, less the peak of the model's answer to its own
samples ``F_m^T w`` (the ridge fit is not exact; its offset drifted a repeated frame's scale
to 1.030 in 40 frames), and applied with a gain ``beta``::

    c <- c a^{beta n*},   c in [1 / limit, limit]

The model then learns from the same samples re-indexed to the new scale (``f(n + beta n*)``,
interpolated along ``n``): one set of samples per frame, where DSST takes a second set.

Two departures from DSST, both measured on this video. (1) DSST solves the regression over
the *circular* shifts of the samples along ``n`` in the Fourier domain (a Hann window over
``n``, ``A = conj(G) F``, ``B = sum |F|^2``). Built first: the features of a smooth, bright
barrel change smoothly and nearly linearly with ``n``, so the circular filter's answer was
dominated by the window and the wrap-around and stayed near ``n = 0`` (a clear spindle 1.20
x its first size, one update: 1.00-1.05 found); the direct ``S x S`` system has no
wrap-around and finds 1.13-1.15. (2) The gain (DSST: ``beta = 1``): at 4-6 % contrast the
per-frame peak is noisy and, as the model follows ``c``, its errors add up (a 6 % spindle
growing by 20 %, sampled at its true centre, ended at 1.7 x its size with ``beta = 1``;
within 3-9 % of it with ``beta`` 0.1-0.2 and ``eta`` 0.005).

The tracker runs the filter after the translation estimate and only on reliable frames
(``r >= min_r``, not a re-detection); lost or doubtful frames keep the scale. The box keeps
its aspect ratio (a turning spindle's axis-aligned box changes shape, which one scale cannot
follow), and the translation filter's window keeps its first size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from oocyte_fe.tracking.window_stats import median


@dataclass(frozen=True)
class ScaleModel:
    """Settings of :class:`ScaleFilter` (module doc). DSST's are ``n_scales`` 33, ``step``
    1.02, ``rate`` 0.025, ``lam`` 0.01, ``gain`` 1; ``gain``, ``rate`` and ``lam`` here were
    chosen on the tuning draws (docs/tracking.md, "Scale filter").

    n_scales: S (odd).  step: a.  region: sampled region in box sizes.  template: pixels of
    the fixed template.  rate: eta.  lam: lambda.  sigma_factor: label width (DSST 1/4).
    limit: largest scale either way.  min_r: the tracker's reliability ``r`` needed to run
    the filter (below it the scale is kept).  gain: beta, the fraction of the measured
    change applied per frame.  features: of ``excess``, ``gradient``, ``orientation``.
    normalise: each sample zero-mean and unit-RMS.
    """

    n_scales: int = 17
    step: float = 1.02
    region: float = 1.5
    template: int = 512
    rate: float = 0.005
    lam: float = 0.1
    sigma_factor: float = 0.25
    limit: float = 2.0
    min_r: float = 0.6
    gain: float = 0.1
    features: tuple[str, ...] = ("excess", "gradient")
    normalise: bool = False

    def __post_init__(self) -> None:
        if self.n_scales < 3 or self.n_scales % 2 == 0:
            raise ValueError(f"n_scales must be odd and >= 3, got {self.n_scales}")
        if not self.step > 1 or self.region < 1 or self.template < 16:
            raise ValueError(f"expected step > 1, region >= 1, template >= 16: {self}")
        unknown = set(self.features) - {"excess", "gradient", "orientation"}
        if unknown or not self.features:
            raise ValueError(f"scale features must be among excess, gradient, orientation: {self}")
        if not 0 < self.gain <= 1:
            raise ValueError(f"gain must be in (0, 1], got {self.gain}")
        if not 0 < self.rate <= 1 or self.lam <= 0 or self.sigma_factor <= 0 or self.limit < 1:
            raise ValueError(f"expected 0 < rate <= 1, lam > 0, sigma_factor > 0: {self}")


def _taps(at: float, lengths: np.ndarray, n_out: int, n_in: int):
    """Linear-interpolation taps for ``n_out`` template pixels spanning ``lengths[s]`` px
    about ``at`` px: the lower index (S, n_out) and the upper tap's weight."""
    pos = at + lengths[:, None] * ((np.arange(n_out) + 0.5) / n_out - 0.5)
    pos = np.clip(pos - 0.5, 0.0, n_in - 1.000001)
    lo = np.floor(pos).astype(int)
    return lo, pos - lo


def _peak(y: np.ndarray) -> float:
    """Sub-sample position of the maximum of ``y(n)``, relative to the middle sample
    (a parabola through the maximum and its neighbours)."""
    k = int(np.argmax(y))
    dn = float(k - (len(y) - 1) // 2)
    if 0 < k < len(y) - 1:
        den = y[k - 1] - 2 * y[k] + y[k + 1]
        if den < 0:
            dn += 0.5 * (y[k - 1] - y[k + 1]) / den
    return dn


class ScaleFilter:
    """The target's scale ``c`` (box = first box x ``c``) from the 1-D filter (module doc)."""

    def __init__(
        self, frame: np.ndarray, centre: tuple[float, float], size: tuple[float, float],
        model: ScaleModel = ScaleModel(),
    ) -> None:  # fmt: skip
        self.model = model
        self.size0 = (float(size[0]), float(size[1]))
        self.scale = 1.0
        s = model.n_scales
        self.n = np.arange(s) - (s - 1) // 2
        self.factors = model.step ** self.n.astype(float)
        sigma = model.sigma_factor * s / np.sqrt(33.0)
        g = np.exp(-0.5 * (self.n / sigma) ** 2)
        self.g = g
        aspect = self.size0[0] / self.size0[1]
        self.tw = max(2, int(round(np.sqrt(model.template * aspect))))
        self.th = max(2, int(round(model.template / self.tw)))
        self.fm = self.w = None
        self.learn(self.samples(frame, centre), rate=1.0)

    @property
    def size(self) -> tuple[float, float]:
        """The box's (w, h) px at the current scale."""
        return self.size0[0] * self.scale, self.size0[1] * self.scale

    def samples(self, frame: np.ndarray, centre: tuple[float, float]) -> np.ndarray:
        """The samples' features ``[f(n)]``, shape (d, S), about ``centre`` px."""
        extent = self.scale * self.factors * self.model.region
        half_w = 0.5 * extent[-1] * self.size0[0] + 2
        half_h = 0.5 * extent[-1] * self.size0[1] + 2
        rows, cols = frame.shape
        top, left = int(np.floor(centre[1] - half_h)), int(np.floor(centre[0] - half_w))
        r = np.clip(np.arange(top, int(np.ceil(centre[1] + half_h)) + 1), 0, rows - 1)
        c = np.clip(np.arange(left, int(np.ceil(centre[0] + half_w)) + 1), 0, cols - 1)
        patch = frame[r[:, None], c[None, :]]
        level = median(patch[::2, ::2])
        box = max(1, int(round(self.scale * self.model.region * self.size0[0] / self.tw)))
        patch = ndimage.uniform_filter(patch, box, mode="nearest") if box > 1 else patch
        y0, fy = _taps(centre[1] - top, extent * self.size0[1], self.th, len(r))
        x0, fx = _taps(centre[0] - left, extent * self.size0[0], self.tw, len(c))
        across = patch[y0] * (1 - fy[..., None]) + patch[y0 + 1] * fy[..., None]  # (S, th, C)
        x0, fx = x0[:, None, :], fx[:, None, :]
        left_tap = np.take_along_axis(across, np.broadcast_to(x0, (*y0.shape, self.tw)), 2)
        right_tap = np.take_along_axis(across, np.broadcast_to(x0 + 1, left_tap.shape), 2)
        stack = left_tap * (1 - fx) + right_tap * fx
        stack = stack / (level if level > 0 else 1.0) - 1.0
        return self.features(stack).reshape(self.model.n_scales, -1).T

    def features(self, stack: np.ndarray) -> np.ndarray:
        """Feature maps (S, th, tw, d) of the resampled excess brightness ``stack`` (S, th,
        tw): the excess itself, the gradient magnitude, the doubled-angle gradient
        ``|g| (cos 2 theta, sin 2 theta)`` (per :attr:`ScaleModel.features`); with
        ``normalise`` each sample is made zero-mean and unit-RMS."""
        gx = np.zeros_like(stack)
        gy = np.zeros_like(stack)
        gx[:, :, 1:-1] = 0.5 * (stack[:, :, 2:] - stack[:, :, :-2])
        gy[:, 1:-1, :] = 0.5 * (stack[:, 2:, :] - stack[:, :-2, :])
        mag = np.hypot(gx, gy)
        maps = []
        for name in self.model.features:
            if name == "excess":
                maps.append(stack)
            elif name == "gradient":
                maps.append(mag)
            else:
                angle = 2.0 * np.arctan2(gy, gx)
                maps += [mag * np.cos(angle), mag * np.sin(angle)]
        f = np.stack(maps, axis=-1)
        if self.model.normalise:
            f = f - f.mean(axis=(1, 2), keepdims=True)
            f = f / np.sqrt(np.mean(f * f, axis=(1, 2, 3), keepdims=True) + 1e-12)
        return f

    def learn(self, f: np.ndarray, rate: float) -> None:
        """Fold the samples ``f`` (d, S) into ``F_m`` with ``rate`` and solve for ``w``."""
        self.fm = f if self.fm is None else (1 - rate) * self.fm + rate * f
        k = self.fm.T @ self.fm
        lam = self.model.lam * np.trace(k) / len(k)
        alpha = np.linalg.solve(k + lam * np.eye(len(k)), self.g)
        self.w = self.fm @ alpha
        self.offset = _peak(k @ alpha)

    def peak(self, f: np.ndarray) -> float:
        """``n*``: the sub-sample peak of ``y(n) = f(n)^T w`` for the samples ``f`` (d, S),
        less the peak of the model's answer to its own samples (``F_m^T w``, the ridge fit's
        offset, which would otherwise drift the scale of a static target)."""
        return _peak(f.T @ self.w) - self.offset

    def update(self, frame: np.ndarray, centre: tuple[float, float]) -> float:
        """Estimate the scale change ``a^{n*}`` at ``centre``, apply it (within the limit),
        and learn from the same samples re-indexed to the new scale (``f(n + n*)``, linear
        interpolation along ``n``, the ends repeated); returns the new scale ``c``."""
        f = self.samples(frame, centre)
        dn = self.model.gain * self.peak(f)
        lim = self.model.limit
        self.scale = float(np.clip(self.scale * self.model.step**dn, 1 / lim, lim))
        pos = np.clip(np.arange(f.shape[1]) + dn, 0, f.shape[1] - 1)
        lo = np.minimum(np.floor(pos).astype(int), f.shape[1] - 2)
        frac = pos - lo
        self.learn(f[:, lo] * (1 - frac) + f[:, lo + 1] * frac, self.model.rate)
        return self.scale
