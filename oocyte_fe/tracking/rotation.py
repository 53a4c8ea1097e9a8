"""An anchor bank over orientations: the first-frames target, turned, for the loss test, the
anchor check and the re-detection of a spindle that turns (issue 29, item 2).

The frozen anchor of :mod:`.anchor` is the target as it looked in its first reliable
frames; a spindle pushed by the pipette turns by 60 deg or more, the anchor then scores it
like clutter (0.24-0.36 of its reference at 60-90 deg), and the adaptive template (learning
rate 0.01, a time constant of 100 frames) lags the turn until the reliability ``r`` falls
below the loss threshold while the box is still near the spindle (docs/tracking.md).

The bank keeps square crops ``C_i`` (side: the search window's diagonal) about the tracked
centre on every ``crop_every``-th of the anchor's first ``n`` reliable frames. When the
anchor is complete, every crop is flattened to its median ``m_i`` outside the target's
ellipse (``w`` of :func:`ellipse_weight`: the static cytoplasm around the target does not
turn with it), turned by each angle ``phi_j = j step`` (``j = 0 .. 180 / step - 1``; a
spindle is symmetric under a half turn) about its centre (bilinear) and cut to the search
window; the orientation's filter is the anchor's mean over those windows (the tracker's own
features, ``features``: the grayscale channel; cosine window and labels, :mod:`.kcf`)::

    C_i'    = m_i + w (C_i - m_i)
    x_hat_j = mean_i F(R_phi_j C_i'),   alpha_hat_j = mean_i y_hat / (k_hat^{x_i x_i} + lambda)
    B(z)    = max_j max_{|d| <= D} (1/K) sum_k f_j,k(z)[d],   j*, d* its argmax

(``B_0`` the 0-deg member's best; ``D = 1`` cell for a candidate, ``reach`` cells for a
hold). Turning each crop, not their mean, keeps the anchor's noise statistics (a filter of
the noise-free mean crop scored the spindle's own noisy frames at 0.6-0.7). The reference
``<B>`` is the mean of ``B`` (``D = 1``) on every ``note_every``-th of the anchor's
reference frames. A window is *turned* if ``B >= hold <B>``, its best orientation is at
least ``min_turn`` from 0 deg and ``B >= (1 + margin) B_0`` (an occluded or blurred target
lowers every orientation alike). How the tracker (:mod:`.tracker`,
``TrackerConfig.rotation``) uses it:

- hold: on a frame with ``r < 1`` (not lost) whose window at the prediction is turned, with
  the bank's peak in the motion gate, the target is kept (at the adaptive peak if
  ``r >= r_stop``, else at the bank's) and the adaptive filters learn at ``relearn``;
- anchor check: a re-detected candidate in the gate that the anchor refuses is taken at the
  bank's peak if its window is turned (the filters learn it at ``refind``);
- re-detection: a lost target whose window at the prediction or where it was lost is turned
  is taken back there (the adaptive filter, trained on the unturned spindle, does not score
  a turned one high enough to be a candidate).

Cost: 180 / ``step`` kernel correlations of the grayscale channel per score (12 at 15 deg),
on frames with ``r < 1``, lost frames and every 16th reference frame; building the bank
(12 orientations x 10 crops) about 0.13 CPU s once. Assumption, as the anchor's: the
first ``n`` reliable frames show the target. Settings chosen on the choice draws, and the
held-out figures: docs/tracking.md, "Rotation".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from oocyte_fe.tracking.anchor import ScoreReference
from oocyte_fe.tracking.kcf import KcfModel
from oocyte_fe.tracking.window_stats import median

TAPER_PX = 2.0
"""Width of the soft edge of the target's ellipse in the bank's windows, px."""
ELLIPSE = 1.15
"""The ellipse's semi-axes over the first box's half-sides (it holds a barrel's corners)."""


def ellipse_weight(side: int, axes: tuple[float, float]) -> np.ndarray:
    """Soft mask of a centred ellipse of semi-axes ``axes`` (x, y) px on a ``side``-square:
    1 inside, falling linearly to 0 over ``TAPER_PX`` px outside (along the radius)."""
    y, x = np.indices((side, side), dtype=float) - (side - 1) / 2
    rho = np.hypot(x / axes[0], y / axes[1])
    scale = TAPER_PX / min(axes)
    return np.clip((1.0 + scale - rho) / scale, 0.0, 1.0)


@dataclass(frozen=True)
class RotationModel:
    """Settings of :class:`RotationBank` (module doc).

    step: angle between orientations, deg (180 / step orientations, 0 deg included).
    hold: ``B >= hold <B>`` holds a doubtful or lost peak, or re-finds a lost target.
    relearn: the adaptive filters' learning rate on a held frame.
    refind: their learning rate on the frame a lost target is re-found by the bank (1:
        the adaptive filters start again from the re-found window).
    reach: largest shift of the bank's peak on a hold, cells.
    min_turn: hold only when the best orientation is at least this far from 0 deg, deg (an
        unturned target is left to the adaptive filter's own loss test, as without the
        bank; the best orientation of an unturned spindle in noise is often one step off).
    margin: and only when the best orientation scores at least ``1 + margin`` times the
        0-deg member (evidence of a turn: an occluded or blurred target lowers all
        orientations alike).
    features: the tracker's features the bank uses (the grayscale histogram: HOG's local
        energy normalisation gives the 1 % cytoplasm texture the weight of the spindle, and
        the texture does not turn with it).
    crop_every: every ``crop_every``-th of the anchor's frames gives a crop (cost).
    note_every: ``<B>`` takes every ``note_every``-th of the anchor's reference frames
        (cost; 4: every 16th reliable frame).
    """

    step: float = 15.0
    hold: float = 0.5
    relearn: float = 0.1
    refind: float = 0.1
    reach: int = 3
    min_turn: float = 30.0
    margin: float = 0.25
    features: tuple[str, ...] = ("gray",)
    crop_every: int = 3
    note_every: int = 4

    def __post_init__(self) -> None:
        if not 0 < self.step <= 90 or not 0 < self.hold or not 0 <= self.relearn <= 1:
            raise ValueError(f"expected 0 < step <= 90, hold > 0, 0 <= relearn <= 1: {self}")
        if not 0 <= self.min_turn <= 90:
            raise ValueError(f"min_turn must be in [0, 90] deg, got {self.min_turn}")
        if self.crop_every < 1 or self.note_every < 1:
            raise ValueError(f"crop_every and note_every must be >= 1: {self}")
        if self.reach < 1:
            raise ValueError(f"reach must be >= 1 cell, got {self.reach}")

    @property
    def angles(self) -> np.ndarray:
        """The orientations, deg, in [0, 180)."""
        return np.arange(0.0, 180.0 - 1e-9, self.step)


@dataclass(frozen=True)
class BankScore:
    """What the bank and the anchor say of one window (:meth:`.tracker.Tracker.orientation`).

    relative: ``B / <B>`` (best orientation, within one cell).  turn_deg: that orientation,
    deg in (-90, 90] from the first frames' (towards +y, image rows down).  unturned:
    the 0-deg member's score over ``<B>``.  anchor: the frozen anchor's ``A / <A>``.
    """

    relative: float
    turn_deg: float
    unturned: float
    anchor: float


def folded(angle_deg: float) -> float:
    """An orientation of a half-turn-symmetric target folded into (-90, 90] deg."""
    return 90.0 - (90.0 - angle_deg) % 180.0


class RotationBank(ScoreReference):
    """Mean first-frames crop, the turned filters built from it, and the reference ``<B>``."""

    def __init__(
        self, model: RotationModel, window: tuple[int, int], n_frames: int, box: tuple[float, float]
    ) -> None:
        self.model = model
        self.window = window
        self.axes = (ELLIPSE * box[0] / 2, ELLIPSE * box[1] / 2)
        self.side = int(np.ceil(np.hypot(*window))) + 2
        self.n_frames = n_frames
        self.crops: list[np.ndarray] = []
        self.n_seen = 0
        self.filters: list[list[KcfModel]] = []
        super().__init__()
        self.n_offered = 0

    @property
    def complete(self) -> bool:
        return bool(self.filters)

    def learn(self, crop: np.ndarray) -> bool:
        """Offer one of the anchor's reliable frames' square crops (every ``crop_every``-th
        is kept); True at the anchor's last frame (then :meth:`build` is due)."""
        if self.complete or self.n_seen >= self.n_frames:
            return False
        if self.n_seen % self.model.crop_every == 0:
            self.crops.append(np.array(crop, dtype=np.float64))
        self.n_seen += 1
        return self.n_seen >= self.n_frames

    def turned_windows(self, angle: float) -> list[np.ndarray]:
        """Every kept crop flattened to its median level outside the target's ellipse
        (``m + w (C - m)``, :func:`ellipse_weight`), turned by ``angle`` deg and cut to the
        search window: the static cytoplasm around the target does not turn with it."""
        rows, cols = self.window
        top, left = (self.side - rows) // 2, (self.side - cols) // 2
        weight = ellipse_weight(self.side, self.axes)
        out = []
        for c in self.crops:
            level = median(c)
            flat = level + weight * (c - level)
            # ndimage turns counter-clockwise on (row, col) arrays: -angle turns the target
            # by +angle from the x axis towards +y (image rows down), the frame's convention
            turned = ndimage.rotate(flat, -angle, reshape=False, order=1) if angle else flat
            out.append(turned[top : top + rows, left : left + cols])
        return out

    def build(self, models_per_angle: list[list[KcfModel]]) -> None:
        """Install the filters (one list of per-feature models per angle, 0 deg first)."""
        self.filters = models_per_angle
        self.crops = []

    def best(self, feats: list[np.ndarray], reach: int) -> tuple[float, int, float, float, float]:
        """``(B, j*, dy, dx, B_0)``: the best mean response within ``reach`` cells of zero
        shift over the orientations, its orientation index, its shift (cells, sub-cell) and
        the 0-deg member's best within the same reach."""
        best = (-np.inf, 0, 0.0, 0.0)
        first = -np.inf
        for j, models in enumerate(self.filters):
            response = sum(m.respond(zf) for m, zf in zip(models, feats, strict=True))
            response = response / len(models)
            near = np.roll(response, (reach, reach), axis=(0, 1))[: 2 * reach + 1, : 2 * reach + 1]
            i, k = np.unravel_index(int(np.argmax(near)), near.shape)
            value = float(near[i, k])
            if j == 0:
                first = value
            if value > best[0]:
                dy, dx = _refine(near, i, k)
                best = (value, j, dy - reach, dx - reach)
        return best + (first,)

    def score(self, feats: list[np.ndarray]) -> float:
        """``B(z)`` with ``D = 1`` (the anchor check)."""
        return self.best(feats, 1)[0]

    def due(self) -> bool:
        """Count one of the anchor's reference frames; True on every ``note_every``-th."""
        self.n_offered += 1
        return (self.n_offered - 1) % self.model.note_every == 0


def _refine(near: np.ndarray, i: int, k: int) -> tuple[float, float]:
    """Sub-cell peak (parabola through the peak and its neighbours, inside ``near``)."""

    def step(rm: float, r0: float, rp: float) -> float:
        den = rm - 2.0 * r0 + rp
        return float(np.clip(0.5 * (rm - rp) / den, -0.5, 0.5)) if den < 0 else 0.0

    h, w = near.shape
    dy = step(near[i - 1, k], near[i, k], near[i + 1, k]) if 0 < i < h - 1 else 0.0
    dx = step(near[i, k - 1], near[i, k], near[i, k + 1]) if 0 < k < w - 1 else 0.0
    return i + dy, k + dx
