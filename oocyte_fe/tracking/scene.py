"""Is the box showing the tracked object, or only the static scene it was passing over?

The reliability ``r`` of :mod:`.update` compares the response with the track's own first
frames, and the adaptive template learns whatever the box shows. A box that stops on static
structure while the object it followed moves on (a template pulled by the background it
learned, docs/tracking.md "A box left on the static scene") keeps learning that structure,
and ``r`` rises (1.1-1.9 on such a box against 1.0-1.4 on the moving target, an outside
tester's clip); the contrast-to-noise factor of :mod:`.evidence` is 1 on any textured
background. Neither can tell "the target stopped here" from "the target left and the box
stayed".

What can: the scene without the target. :class:`SceneMemory` keeps a running mean of every
pixel outside the search window about the tracked centre (the target is inside it), learnt
only while the target is tracked (while it is lost nobody knows where it is, and a target at
rest would be learnt as scene)::

    S(x) <- S(x) + (I(x) - S(x)) / min(n(x), N),   n(x) the frames x was learnt (N = 20)

A box whose pixels were all learnt at least ``n_min`` times is then compared with that
memory (a gain ``g`` fitted on the window's learnt pixels cancels the illumination)::

    s_fg = rms_box( G_1 * (I - g S) ) / (k_1 sigma_n)

with the smoothing ``G_1``, ``k_1`` and the pixel noise ``sigma_n`` of :mod:`.evidence`, so
``s_fg`` is about 1 when the box shows the scene as it was before the target came (noise
only) and grows with whatever the box holds that the scene did not (the target, a droplet
that drifted in). It is mapped to a factor with the same levels as the contrast-to-noise
factor (:func:`.evidence.confidence_factor`: 1.3 -> 0, 2.0 -> 1), which multiplies the
confidence; at 0 (the box indistinguishable from the remembered scene) the target is
declared lost (:mod:`.tracker`). Where the scene was never seen without the target (the
target's first place) the factor is 1: no evidence either way.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oocyte_fe.tracking import evidence
from oocyte_fe.tracking.window_stats import median, smooth

PAD_PX = int(4 * evidence.SMOOTH_PX + 0.5)
"""The smoothing kernel's reach, px: the residual is smoothed over the box plus this margin."""


@dataclass(frozen=True)
class SceneModel:
    """Settings of :class:`SceneMemory` (see module doc).

    frames: ``N``, the memory's length in frames once a pixel has been seen that often (a
        drifting droplet at rest is part of the scene after about ``N`` frames).
    n_min: frames a pixel must have been learnt before the box is compared with it.
    coverage: fraction of the box's in-frame pixels that must have been learnt.
    """

    frames: int = 20
    n_min: int = 5
    coverage: float = 0.9

    def __post_init__(self) -> None:
        if self.frames < 1 or not 1 <= self.n_min <= self.frames or not 0 < self.coverage <= 1:
            raise ValueError(f"expected frames >= n_min >= 1 and 0 < coverage <= 1, got {self}")


class SceneMemory:
    """Running mean of the scene outside the tracked window, and the box's excess over it."""

    def __init__(self, shape: tuple[int, int], model: SceneModel) -> None:
        self.model = model
        self.mean = np.zeros(shape)
        self.count = np.zeros(shape)  # frames learnt, at most ``frames``

    def learn(
        self, frame: np.ndarray, centre: tuple[float, float], window: tuple[int, int]
    ) -> None:
        """Fold the frame's pixels outside the (rows, cols) ``window`` about ``centre`` (x, y)
        px into the memory."""
        (y0, y1), (x0, x1) = _span(frame.shape, centre, window)
        inner = (slice(y0, y1), slice(x0, x1))
        kept = self.count[inner].copy(), self.mean[inner].copy()
        np.add(self.count, 1.0, out=self.count)
        np.minimum(self.count, self.model.frames, out=self.count)
        step = frame - self.mean
        step /= self.count
        self.mean += step
        self.count[inner], self.mean[inner] = kept

    def excess(
        self,
        frame: np.ndarray,
        centre: tuple[float, float],
        size: tuple[float, float],
        window: tuple[int, int],
        sigma_n: float,
    ) -> float | None:
        """``s_fg`` of the (w, h) box ``size`` about ``centre`` px (module doc; the gain from
        the learnt pixels of the (rows, cols) ``window``), or None where the memory does not
        cover the box."""
        (y0, y1), (x0, x1) = _span(frame.shape, centre, size[::-1])
        learnt = self.count[y0:y1, x0:x1] >= self.model.n_min
        if learnt.size < 4 or learnt.mean() < self.model.coverage or sigma_n <= 0:
            return None
        (wy0, wy1), (wx0, wx1) = _span(frame.shape, centre, window)
        known = self.count[wy0:wy1, wx0:wx1] >= self.model.n_min
        level = median(self.mean[wy0:wy1, wx0:wx1][known])
        gain = median(frame[wy0:wy1, wx0:wx1][known]) / level if level > 0 else 1.0
        # smoothed over the box plus the kernel's reach (no reflected edge inside the box)
        (py0, py1), (px0, px1) = _span(
            frame.shape, centre, (size[1] + 2 * PAD_PX, size[0] + 2 * PAD_PX)
        )
        around = (slice(py0, py1), slice(px0, px1))
        residual = frame[around] - gain * self.mean[around]
        residual[self.count[around] < self.model.n_min] = 0.0
        residual = smooth(residual, evidence.SMOOTH_PX)[y0 - py0 : y1 - py0, x0 - px0 : x1 - px0]
        return float(np.sqrt(np.mean(residual[learnt] ** 2))) / (evidence.K_SMOOTH * sigma_n)


def _span(
    shape: tuple[int, ...], centre: tuple[float, float], extent: tuple[float, float]
) -> tuple[tuple[int, int], tuple[int, int]]:
    """((y0, y1), (x0, x1)): the rows and columns of the (rows, cols) ``extent`` about
    ``centre`` (x, y) px, clipped to the frame."""
    return tuple(
        (min(max(round(c - n / 2), 0), m), min(max(round(c + n / 2), 0), m))
        for c, n, m in zip((centre[1], centre[0]), extent, shape[:2], strict=True)
    )
