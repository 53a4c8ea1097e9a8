"""The MFAKCF tracker (seed 000, Algorithm 1) and the single-feature KCF it is compared with.

Per frame (Algorithm 1, lines 5-9): cut the search window (target box x (1 + padding)) at the
last position, compute each feature map (:mod:`.features`) under the cosine window, answer
each feature's filter (:mod:`.kcf`), fuse the responses with APCE weights (:mod:`.fusion`),
move to the sub-cell peak, then cut the window again at the new position and update each
filter with the adaptive learning rate (:mod:`.update`). When the reliability falls below
``r_lost`` the target is lost: the position is held and each frame a grid of
``(2 k + 1)^2`` windows, spaced half a window apart around the last position, is searched;
the best candidate is taken back when its reliability reaches ``r_found``. With a motion
model (:mod:`.motion`, as in ``MFAKCF``) the window is cut at the predicted centre, a lost
target coasts on the prediction, and the grid is centred on the prediction, plus one window
where the target was lost (the spindle may have stopped under the droplet); a peak with
``r_lost <= r < r_stop`` is doubtful and the centre coasts, and a lost target is taken back
inside the motion model's validation gate at ``r >= r_lost``. In ``MFAKCF`` the grid widens
the longer the target is lost, and a candidate is taken back only if the anchor template
(the first reliable frames, :mod:`.anchor`) also recognises it. The motion model's form and
settings were chosen on the benchmark's 6-sequence tuning subset (:mod:`.motion`,
docs/tracking.md); ``r_lost`` / ``r_found`` on 5 sequences by the first version
(:mod:`.update`).

Options of issue 29 (docs/tracking.md): a reach gate from the largest push speed
(``max_step_px``: a lost target is searched for and taken back only where it could have got
to), a rotation-free signature check (:mod:`.evidence`, ``MFAKCF_SIGNATURE``), a box size
from the spindle's moments (:mod:`.extent`) or from a DSST-style 1-D scale filter
(:mod:`.scale`, ``MFAKCF_SCALE``), an anchor bank over orientations for a spindle that turns
(:mod:`.rotation`, ``MFAKCF_ROTATION``), lower loss thresholds while the target moves
(``moving_relax``, ``MFAKCF_MOVING``); each frame's confidence is ``r`` times the box's
contrast-to-noise factor (on a frame the bank keeps, ``max(r, B / <B>)`` times it) and, with
``scene`` (MFAKCF and its options), times the factor of the box's excess over the
remembered static scene (:mod:`.scene`: a box that shows only that scene declares the target
lost).

With ``features=("hog",)``, ``adaptive=False`` the same code is the "original KCF" of the
seed: HOG only, fixed learning rate, no loss handling (Henriques et al. 2015). The target
size is fixed unless ``extent`` or ``scale`` is set (the translation window keeps the first
size in any case).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from oocyte_fe.tracking import evidence, kcf
from oocyte_fe.tracking.anchor import Anchor
from oocyte_fe.tracking.context import CONTEXT_OFFSETS, ContextKcfModel
from oocyte_fe.tracking.evidence import Signature, SignatureCheck
from oocyte_fe.tracking.extent import BoxExtent, ExtentModel
from oocyte_fe.tracking.features import FEATURES
from oocyte_fe.tracking.fusion import apce, fuse, fusion_weights
from oocyte_fe.tracking.motion import CentreFilter, MotionModel
from oocyte_fe.tracking.rotation import BankScore, RotationBank, RotationModel, folded
from oocyte_fe.tracking.scale import ScaleFilter, ScaleModel
from oocyte_fe.tracking.scene import SceneMemory, SceneModel
from oocyte_fe.tracking.update import ReliabilityHistory, UpdatePolicy
from oocyte_fe.tracking.window_stats import smooth


@dataclass(frozen=True)
class TrackerConfig:
    """Tracker settings (lengths in pixels or cells; Henriques et al. 2015 HOG defaults).

    features: feature names of :data:`.features.FEATURES`, each with its own filter.
    cell: HOG / histogram cell size, px.  padding: window = target x (1 + padding).
    label_sigma_factor: ``sigma_y = factor sqrt(w h) / cell``, cells.
    kernel_sigma, lam: Gaussian kernel width and ridge term of :mod:`.kcf`.
    smooth_px: Gaussian smoothing of the window before the features, px (0: none).
    adaptive: APCE fusion weights, adaptive learning rate and re-detection (MFAKCF); False
        gives a fixed learning rate ``policy.eta0`` and equal weights.
    redetect_radius: k of the ``(2k+1)^2`` re-detection grid, windows.
    redetect_grow, redetect_max: while lost, k grows by one every ``redetect_grow`` frames
        (0: never) up to ``redetect_max``, so the search widens the longer the target is
        lost (a spindle pushed out of the window by the pipette).
    verify, anchor_frames: a re-detected candidate is taken back only if the anchor
        template (the mean filter of the first ``anchor_frames`` reliable frames) scores it
        at least ``verify`` times its mean on tracked frames (:mod:`.anchor`; 0: no check).
    motion: Kalman prediction of the centre (:mod:`.motion`; adaptive trackers only): the
        window is cut at the predicted centre and a lost target coasts on the prediction;
        None holds the last position.
    signature: rotation-free appearance check of :mod:`.evidence` (None: off). A peak with
        ``r < 1`` that lies in the motion model's gate and passes the check is taken (the
        filter learns at ``signature.learn`` x ``eta0``, at least the rate ``r`` gives)
        instead of coasting or being declared lost: a turning spindle lowers ``r`` while the
        template catches up. A re-detected candidate must pass it, and then is taken back if
        the anchor accepts it or it lies in the motion gate (the anchor fails a turned
        spindle).
    extent: the box's size from the spindle's excess-brightness moments (:mod:`.extent`;
        None: the first box's size throughout, as KCF). Only the reported box changes; the
        filter's window keeps the first size.
    scale: the box's size from the 1-D scale filter (:mod:`.scale`, DSST-style; None: the
        first box's size throughout). Run after the translation estimate on frames with
        ``r >= scale.min_r`` that are not a re-detection; only the reported box changes.
    rotation: the anchor bank over orientations of :mod:`.rotation` (None: the anchor alone).
        A frame with ``r < 1`` whose window the bank finds turned (``B >= hold <B>``, best
        orientation >= ``min_turn`` from 0 deg and ``margin`` above the 0-deg member, peak
        in the motion gate) is kept and the adaptive filters relearn it at
        ``rotation.relearn``; a candidate in the gate that the anchor refuses is taken if
        the bank finds it turned, and a lost target is re-found the same way at the
        prediction or where it was lost (learnt at ``rotation.refind``).
    max_step_px: the farthest the target can move in one frame, px (the largest push speed
        over the frame rate and the pixel size, :func:`max_step_px`; 0: no limit). While
        lost for ``n`` frames only candidates within ``n max_step_px`` + half the box's
        diagonal of where the target was lost are searched and taken back.
    context, context_offset: lambda_2 of the context-aware filter (:mod:`.context`: four
        context windows ``context_offset`` target sizes up, down, left and right are
        regressed to zero; 0: the plain KCF). Off in every tracker here: on the tuning
        cells it lost accuracy at every setting tried and cost about 5 x the time per frame
        (docs/tracking.md).
    moving_relax, moving_speed_px: while the tracked target moves faster than
        ``moving_speed_px`` px/frame (the motion model's velocity), the loss and doubtful
        thresholds are ``moving_relax`` x ``policy.r_lost`` and x ``policy.r_stop`` (1: as at
        rest). ``r`` is measured against the peaks and APCEs of the first, mostly still frames,
        where the static cytoplasm around the spindle answers the filter as well as the
        spindle; once the spindle moves over that texture the true peak loses that part (at
        the true centre ``r`` fell from 1.2 to 0.34 within 12 frames of a fast push,
        docs/tracking.md). The learning rate still follows ``r`` and ``policy.r_stop``.
    scene: the memory of the static scene of :mod:`.scene` (adaptive trackers only; None:
        off). A box that shows only the remembered scene (its excess over it at the noise
        level) does not hold the target: the target is declared lost and such a re-detected
        candidate is not taken back; the excess's factor multiplies the confidence.
    """

    features: tuple[str, ...] = ("hog", "gray")
    cell: int = 4
    padding: float = 1.5
    label_sigma_factor: float = 0.1
    kernel_sigma: float = 0.5
    lam: float = 1e-4
    adaptive: bool = True
    smooth_px: float = 0.0
    redetect_radius: int = 1
    redetect_grow: int = 0
    redetect_max: int = 1
    verify: float = 0.0
    anchor_frames: int = 30
    motion: MotionModel | None = None
    signature: SignatureCheck | None = None
    extent: ExtentModel | None = None
    scale: ScaleModel | None = None
    rotation: RotationModel | None = None
    max_step_px: float = 0.0
    context: float = 0.0
    context_offset: float = 1.0
    moving_relax: float = 1.0
    moving_speed_px: float = 1.0
    scene: SceneModel | None = None
    policy: UpdatePolicy = field(default_factory=UpdatePolicy)

    def __post_init__(self) -> None:
        unknown = [f for f in self.features if f not in FEATURES]
        if unknown or not self.features:
            raise ValueError(f"features must be among {sorted(FEATURES)}, got {self.features}")
        if self.cell < 1 or self.padding < 0:
            raise ValueError("cell must be >= 1 px and padding >= 0")
        if self.context < 0 or self.context_offset <= 0:
            raise ValueError("context (lambda_2) must be >= 0 and context_offset > 0")
        if self.extent is not None and self.scale is not None:
            raise ValueError("choose one box-size estimate: extent or scale, not both")
        if self.rotation is not None and (self.verify <= 0 or self.motion is None):
            raise ValueError("the rotation bank needs the anchor check (verify > 0) and motion")
        if not 0 < self.moving_relax <= 1 or not self.moving_speed_px >= 0:
            raise ValueError("expected 0 < moving_relax <= 1 and moving_speed_px >= 0")
        if self.moving_relax < 1 and (self.motion is None or not self.adaptive):
            raise ValueError("moving_relax < 1 needs the motion model's speed (motion, adaptive)")
        if not self.max_step_px >= 0:
            raise ValueError(f"max_step_px must be >= 0, got {self.max_step_px}")


def max_step_px(speed_um_s: float, fps: float, pixel_um: float) -> float:
    """The farthest a target moving at ``speed_um_s`` um/s goes between two frames, px:
    ``d = v / (f p)`` (frame rate f in frames/s, pixel size p in um/px)."""
    return speed_um_s / (fps * pixel_um)


MFAKCF = TrackerConfig(
    smooth_px=1.0,
    motion=MotionModel(),
    redetect_grow=10,
    redetect_max=3,
    verify=0.6,
    anchor_frames=30,
    scene=SceneModel(),
    policy=UpdatePolicy(eta0=0.01),
)
"""The seed's tracker: HOG + grayscale histogram, APCE fusion, adaptive update (full
learning rate 0.01, half KCF's 0.02: the template absorbs less of the static structure
around a faint spindle; chosen on the tuning cells, docs/tracking.md); the window
is smoothed over 1 px first (shot noise otherwise dominates the faint spindle's gradients),
and the centre is predicted by the damped constant-velocity Kalman filter of :mod:`.motion`
(window cut at the prediction; on a doubtful peak and while lost the centre coasts, and the
lost target is searched for around the prediction and where it was lost). The search
widens by one ring of windows every 10 lost frames up to 7 x 7 windows, and a candidate is
taken back only if the anchor template of the first 30 reliable frames scores it at least
0.6 times its mean (:mod:`.anchor`; chosen on the tuning subset, docs/tracking.md). A box
that shows nothing but the static scene remembered outside the tracked window (:mod:`.scene`)
declares the target lost and lowers the confidence to 0 (an outside tester's box left on a
textured background while the target moved on; the benchmark's figures unchanged,
docs/tracking.md "A box left on the static scene")."""

MFAKCF_RATE_002 = replace(MFAKCF, policy=UpdatePolicy())
"""MFAKCF with KCF's full learning rate 0.02 (the previous default); the benchmark script
reports it as ``MFAKCF (rate 0.02)``."""

MFAKCF_NO_ANCHOR = TrackerConfig(smooth_px=1.0, motion=MotionModel())
"""MFAKCF before the anchor check and the widening search (with the rate 0.02); the
benchmark script reports it as ``MFAKCF (no anchor)``."""

MFAKCF_HOLD = TrackerConfig(smooth_px=1.0)
"""MFAKCF without the motion model (the lost target's position is held), as first built;
the benchmark reports it as ``MFAKCF (no motion)``."""

MFAKCF_SIGNATURE = replace(
    MFAKCF, signature=SignatureCheck(), max_step_px=max_step_px(20.0, fps=10.0, pixel_um=0.227)
)
"""MFAKCF with the rotation-free signature check of :mod:`.evidence` (a doubtful peak in the
gate that passes it is taken and learnt at 2 x ``eta0``; a re-detected candidate must pass
it) and the reach gate for a largest speed of 20 um/s at the benchmark's 10 frames/s and
0.227 um/px; the benchmark reports it as ``MFAKCF (signature)``. ``band`` = 1.6 and
``min_coherence`` = 0.2 were set from the brightness and coherence measured at the true
spindle and 15-45 px from it on the 6 tuning cells (docs/tracking.md); ``learn`` = 2 chosen
among 0.5, 1, 2, 3 on two draws of turning sequences (seeds 101, 102)."""

MFAKCF_SCALE = replace(MFAKCF, scale=ScaleModel())
"""MFAKCF with the 1-D scale filter of :mod:`.scale` (gain 0.1, learning rate 0.005,
lambda 0.1, chosen on the tuning draws; 17 scales of step 1.02, region 1.5 boxes); the
benchmark reports it as ``MFAKCF (scale)``. Not the default: it lowered the success AUC on
the tuning cells and did not win on the held-out draws (docs/tracking.md, "Scale filter")."""

MFAKCF_ROTATION = replace(MFAKCF, rotation=RotationModel())
"""MFAKCF with the anchor bank over orientations of :mod:`.rotation` (12 orientations 15 deg
apart built from the anchor's first frames, grayscale channel only; hold at 0.6 of its
reference for a turn of 30 deg or more that beats the unturned member by 25 %; relearn and
re-find rates 0.1; docs/tracking.md, "Rotation"); the benchmark reports it as
``MFAKCF (rotation)``."""

MFAKCF_MOVING = replace(MFAKCF, moving_relax=0.5, moving_speed_px=1.0)
"""MFAKCF whose loss and doubtful thresholds are halved while the target moves faster than
1 px/frame (``moving_relax``; 0.5 and 1 px/frame chosen among 0.4-0.7 and 0.5-2 px/frame on
the own grid's draws s0 and s1000 and model 2's s50000); the benchmark reports it as
``MFAKCF (moving)``. Not the default: on fresh draws its gain (+0.012 / +0.013 pooled over 84
sequences) is below the draw-to-draw spread (docs/tracking.md, "Losses in the fast push")."""

SINGLE_KCF = TrackerConfig(features=("hog",), adaptive=False)
"""The seed's "original KCF": HOG only, fixed learning rate 0.02."""

TRACKERS: dict[str, tuple[str, TrackerConfig]] = {
    "mfakcf": ("MFAKCF", MFAKCF),
    "signature": ("MFAKCF (signature)", MFAKCF_SIGNATURE),
    "rotation": ("MFAKCF (rotation)", MFAKCF_ROTATION),
    "scale": ("MFAKCF (scale)", MFAKCF_SCALE),
    "moving": ("MFAKCF (moving)", MFAKCF_MOVING),
}
"""The trackers ``oocyte-fe track --tracker NAME`` offers: NAME -> (label, configuration).
The default first; the others are the options docs/tracking.md recommends for spindles that
turn (signature, rotation), grow or shrink (scale) or are pushed fast (moving)."""


@dataclass(frozen=True)
class FrameEstimate:
    """What the tracker says about one frame (px; reliability r of :mod:`.update`).

    confidence: ``r e``, with ``e`` the box's contrast-to-noise factor of :mod:`.evidence`
    (low on a blank frame or a featureless box, where ``r`` alone stays high).
    redetected_from: on the frame a lost target is taken back, where it had been lost (x, y)
    px; None on other frames.
    """

    centre: tuple[float, float]
    box: tuple[float, float, float, float]
    reliability: float
    learning_rate: float
    weights: tuple[float, ...]
    lost: bool
    confidence: float
    redetected_from: tuple[float, float] | None = None


def window_shape(box_wh: tuple[float, float], padding: float, cell: int) -> tuple[int, int]:
    """Search window (rows, cols) px: target x (1 + padding), a multiple of cell, >= 4 cells."""
    w, h = box_wh
    rows = max(4 * cell, int(round(h * (1 + padding) / cell)) * cell)
    cols = max(4 * cell, int(round(w * (1 + padding) / cell)) * cell)
    return rows, cols


def window_origin(centre: tuple[float, float], shape: tuple[int, int]) -> tuple[int, int]:
    """(top, left) px of the window of ``shape`` about (x, y) px, on whole pixels."""
    return int(round(centre[1] - shape[0] / 2)), int(round(centre[0] - shape[1] / 2))


def cut_window(
    frame: np.ndarray, centre: tuple[float, float], shape: tuple[int, int]
) -> tuple[np.ndarray, tuple[float, float]]:
    """Window of ``shape`` about (x, y) px on whole pixels, and its exact centre (x, y) px.

    Pixels outside the frame repeat the edge.
    """
    top, left = window_origin(centre, shape)
    at = (left + shape[1] / 2, top + shape[0] / 2)
    if top >= 0 and left >= 0 and top + shape[0] <= frame.shape[0]:
        if left + shape[1] <= frame.shape[1]:
            return frame[top : top + shape[0], left : left + shape[1]], at
    rows = np.clip(np.arange(shape[0]) + top, 0, frame.shape[0] - 1)
    cols = np.clip(np.arange(shape[1]) + left, 0, frame.shape[1] - 1)
    return frame[rows[:, None], cols[None, :]], at


class Tracker:
    """Single-target tracker (see module doc); ``Tracker(frame0, box0).step(frame)``."""

    def __init__(
        self,
        frame: np.ndarray,
        box: tuple[float, float, float, float],
        config: TrackerConfig = MFAKCF,
    ) -> None:
        x, y, w, h = (float(v) for v in box)
        if w <= 0 or h <= 0:
            raise ValueError(f"box width and height must be > 0 px, got {box}")
        self.config = config
        self.size = (w, h)
        self.centre = (x + w / 2, y + h / 2)
        self.shape = window_shape(self.size, config.padding, config.cell)
        grid = (self.shape[0] // config.cell, self.shape[1] // config.cell)
        self.cos = kcf.cosine_window(grid)[..., None]
        sigma_y = config.label_sigma_factor * np.sqrt(w * h) / config.cell
        self.yf = np.fft.fft2(kcf.gaussian_labels(grid, sigma_y))
        self.lost = False
        self.lost_at = self.centre
        frame = np.asarray(frame, dtype=np.float64)
        self._window_cache: tuple = (None, None, None)
        feats, _ = self._features(frame, self.centre)
        plain = [kcf.KcfModel.fit(xf, self.yf, config.kernel_sigma, config.lam) for xf in feats]
        self.models = plain
        if config.context > 0:
            self.models = [
                ContextKcfModel.fit(xfs, self.yf, config.kernel_sigma, config.lam, config.context)
                for xfs in self._with_context(frame, self.centre, feats)
            ]
        self.history = ReliabilityHistory(config.policy)
        self.anchor = Anchor(plain, config.anchor_frames) if config.verify > 0 else None
        self.bank = None
        if config.rotation is not None and self.anchor is not None and config.adaptive:
            self.bank_index = [config.features.index(f) for f in config.rotation.features]
            self.bank = RotationBank(config.rotation, self.shape, config.anchor_frames, self.size)
            self._bank_learn(frame)
        self.n_lost = 0
        self.n_frame = 0
        self._last: tuple = (-1, None, None, None)
        self._turned_refind = False
        self.apce_ref = np.zeros(len(feats))
        self.apce_n = 0
        use_motion = config.motion is not None and config.adaptive
        self.motion = CentreFilter(self.centre, config.motion) if use_motion else None
        self.signature = None
        if config.signature is not None and config.adaptive:
            self.signature = Signature(config.signature, self.size, self.shape[::-1])
            self.signature.learn(frame, self.centre)
        self.extent = None
        if config.extent is not None and config.adaptive:
            self.extent = BoxExtent(frame, self.centre, self.size, config.extent)
        self.scale = None
        if config.scale is not None and config.adaptive:
            self.scale = ScaleFilter(frame, self.centre, self.size, config.scale)
        self.scene = None
        if config.scene is not None and config.adaptive:
            self.scene = SceneMemory(frame.shape, config.scene)
            self.scene.learn(frame, self.centre, self.shape)

    def _features(
        self, frame: np.ndarray, centre: tuple[float, float]
    ) -> tuple[list[np.ndarray], tuple[float, float]]:
        """Feature DFTs of the window about ``centre`` and the window's exact centre, px.

        The last window's are kept: a window cut on the same whole pixels of the same frame
        (the training window after a peak within half a pixel of the prediction) reuses them.
        """
        key = window_origin(centre, self.shape)
        cached_frame, cached_key, cached = self._window_cache
        if cached_frame is frame and cached_key == key:
            return cached
        patch, at = cut_window(frame, centre, self.shape)
        found = self._patch_features(patch), at
        self._window_cache = (frame, key, found)
        return found

    def _patch_features(
        self, patch: np.ndarray, names: tuple[str, ...] | None = None
    ) -> list[np.ndarray]:
        """Feature DFTs (``names``, default the tracker's) of a window-sized patch (smoothed
        first, under the cosine window)."""
        if self.config.smooth_px > 0:
            patch = smooth(patch, self.config.smooth_px)
        maps = [FEATURES[name](patch, self.config.cell) for name in (names or self.config.features)]
        return kcf.fft_feature_maps([m * self.cos for m in maps])

    def _bank_learn(self, frame: np.ndarray) -> None:
        """Keep the square crop about the centre for the bank; when there are enough, build
        each orientation's filters as the mean over the turned windows (:mod:`.rotation`)."""
        crop, _ = cut_window(frame, self.centre, (self.bank.side, self.bank.side))
        if not self.bank.learn(crop):
            return
        cfg = self.config
        members = []
        for angle in self.bank.model.angles:
            mean = None
            for i, patch in enumerate(self.bank.turned_windows(angle)):
                feats = self._patch_features(patch, cfg.rotation.features)
                if mean is None:
                    mean = [
                        kcf.KcfModel.fit(xf, self.yf, cfg.kernel_sigma, cfg.lam) for xf in feats
                    ]
                    continue
                for model, xf in zip(mean, feats, strict=True):
                    model.update(xf, self.yf, 1.0 / (i + 1))
            members.append(mean)
        self.bank.build(members)

    def _bank_feats(self, feats: list[np.ndarray]) -> list[np.ndarray]:
        """The features the bank uses (``rotation.features``), of the tracker's list."""
        return [feats[i] for i in self.bank_index]

    def _turned(self, feats: list[np.ndarray], at: tuple[float, float], reach: int):
        """The bank's test of a window (its features, its centre px): its best orientation
        scores ``B >= hold <B>``, is at least ``min_turn`` from 0 deg and beats the 0-deg
        member by ``margin``; returns (the peak px, ``B / <B>``) or None (:mod:`.rotation`)."""
        bank, rot = self.bank, self.config.rotation
        value, j, dy, dx, value0 = bank.best(self._bank_feats(feats), reach)
        if value < rot.hold * bank.reference or abs(folded(bank.model.angles[j])) < rot.min_turn:
            return None
        if value < (1.0 + rot.margin) * value0:
            return None
        return (
            at[0] + dx * self.config.cell,
            at[1] + dy * self.config.cell,
        ), value / bank.reference

    def _bank_hold(self, frame: np.ndarray, centres: list[tuple[float, float]]):
        """The first of the windows at ``centres`` px whose bank peak passes :meth:`_turned`
        inside the motion gate, as (position px, B / <B>), or None."""
        bank = self.bank
        if bank is None or not bank.complete or bank.reference is None:
            return None
        for centre in centres:
            if self._last[:2] == (self.n_frame, centre):  # the detection's own window
                feats, at = self._last[2:]
            else:
                feats, at = self._features(frame, centre)
            found = self._turned(feats, at, self.config.rotation.reach)
            if found is not None and self._in_gate(found[0]):
                return found
        return None

    def orientation(self, frame: np.ndarray, centre: tuple[float, float]) -> BankScore | None:
        """The orientation bank's and the anchor's scores of the window at ``centre`` px,
        relative to their references (:class:`.rotation.BankScore`); None before the bank is
        complete and has a reference."""
        bank = self.bank
        if bank is None or bank.reference is None or self.anchor.reference is None:
            return None
        feats, _ = self._features(np.asarray(frame, dtype=np.float64), centre)
        value, j, _, _, value0 = bank.best(self._bank_feats(feats), 1)
        return BankScore(
            value / bank.reference,
            folded(bank.model.angles[j]),
            value0 / bank.reference,
            self.anchor.score(feats) / self.anchor.reference,
        )

    def _with_context(
        self, frame: np.ndarray, centre: tuple[float, float], feats: list[np.ndarray]
    ) -> list[np.ndarray]:
        """Per feature, the target window's DFT ``feats`` stacked with the context windows'
        (:data:`.context.CONTEXT_OFFSETS`, target sizes away from ``centre``)."""
        w, h = self.size
        w, h = w * self.config.context_offset, h * self.config.context_offset
        around = [
            self._features(frame, (centre[0] + ox * w, centre[1] + oy * h))[0]
            for ox, oy in CONTEXT_OFFSETS
        ]
        return [np.array([xf] + [c[k] for c in around]) for k, xf in enumerate(feats)]

    def _detect(self, frame: np.ndarray, centre: tuple[float, float]):
        """Fused response at ``centre``: (new centre, peak, APCE, r, weights, feature APCEs)."""
        feats, at = self._features(frame, centre)
        self._last = (self.n_frame, centre, feats, at)
        if self.config.context > 0:
            responses = [m.respond(zf) for m, zf in zip(self.models, feats, strict=True)]
        else:
            responses = kcf.respond_models(self.models, feats)
        apces = np.array([apce(r) for r in responses])
        if self.config.adaptive:
            ref = self.apce_ref / self.apce_n if self.apce_n else apces
            weights = fusion_weights(apces, ref)
        else:
            weights = np.full(len(responses), 1.0 / len(responses))
        fused = fuse(responses, weights)
        dy, dx, peak = kcf.subpixel_peak(fused)
        cell = self.config.cell
        new = (at[0] + dx * cell, at[1] + dy * cell)
        a = apce(fused)
        return new, peak, a, self.history.reliability(peak, a), weights, apces

    def _reach(self) -> float:
        """How far from where it was lost the target can be now, px (``max_step_px``)."""
        w, h = self.size
        return self.config.max_step_px * self.n_lost + 0.5 * np.hypot(w, h)

    def _in_gate(self, point: tuple[float, float]) -> bool:
        """True if the point lies inside the motion model's validation gate (:mod:`.motion`)."""
        return self.motion is not None and self.motion.gate_distance(point) < self.motion.model.gate

    def _verified(self, frame: np.ndarray, cands: list):
        """The best candidate (by r) that is within reach (``max_step_px``), passes the
        re-find thresholds (``r_found``, or ``r_lost`` in the motion gate), the signature
        check, and the anchor check ``A(z) >= verify <A>`` (:mod:`.anchor`) unless the
        signature check passed in the gate; with the orientation bank, a candidate in the
        gate that the anchor fails is taken at the bank's peak if the bank finds it turned
        (:meth:`_turned`); None if none does."""
        p = self.config.policy
        for cand in cands:
            if cand[3] < p.r_lost:
                return None
            if self.config.max_step_px > 0:
                if np.hypot(*np.subtract(cand[0], self.lost_at)) > self._reach():
                    continue
            in_gate = self._in_gate(cand[0])
            if cand[3] < p.r_found and not in_gate:
                continue
            if self.scene_factor(frame, cand[0]) == 0.0:  # only the remembered scene
                continue
            if self.signature is not None:
                if not self.signature.passes(frame, cand[0]):
                    continue
                if in_gate:
                    return cand
            reference = self.anchor.reference if self.anchor else None
            if reference is None:
                return cand
            feats, at = self._features(frame, cand[0])
            if self.anchor.score(feats) >= self.config.verify * reference:
                return cand
            if self.bank is not None and self.bank.reference is not None and in_gate:
                turned = self._turned(feats, at, 1)  # the anchor failed it: turned?
                if turned is not None:
                    self._turned_refind = True  # relearn at rotation.refind (step)
                    return (turned[0],) + tuple(cand[1:])
        return None

    def _redetect(self, frame: np.ndarray, around: tuple[float, float]):
        """Candidates (best first by r) from the ``(2k+1)^2`` windows around ``around`` px
        and the window at the position where the target was lost (module doc); with
        ``max_step_px`` only the windows that can hold a centre within reach."""
        cfg = self.config
        k = cfg.redetect_radius
        if cfg.redetect_grow > 0:
            k = min(k + self.n_lost // cfg.redetect_grow, max(cfg.redetect_max, k))
        step_y, step_x = self.shape[0] / 2, self.shape[1] / 2
        reach = self._reach() + 0.5 * np.hypot(*self.shape) if cfg.max_step_px > 0 else np.inf
        cands = []
        if self.motion is not None:
            cands.append(self._detect(frame, self.lost_at))
        for i in range(-k, k + 1):
            for j in range(-k, k + 1):
                c = (around[0] + j * step_x, around[1] + i * step_y)
                if np.hypot(*np.subtract(c, self.lost_at)) <= reach:
                    cands.append(self._detect(frame, c))
        cands.sort(key=lambda c: -c[3])
        return cands

    def step(self, frame: np.ndarray) -> FrameEstimate:
        """Track one frame (Algorithm 1, lines 5-9)."""
        frame = np.asarray(frame, dtype=np.float64)
        cfg = self.config
        self.n_frame += 1
        predicted = self.motion.predict() if self.motion else self.centre
        rejected = note = False
        found_from = None
        self._turned_refind = False
        checks = self.anchor or self.signature or self.scene or cfg.max_step_px > 0
        if self.lost:
            self.n_lost += 1
            cands = self._redetect(frame, predicted)
            chosen = self._verified(frame, cands) if checks else cands[0]
            rejected = chosen is None
            new, peak, a, r, weights, apces = cands[0] if rejected else chosen
        else:
            new, peak, a, r, weights, apces = self._detect(frame, predicted)
        turned = None
        if self.bank is not None and (rejected if self.lost else r < 1.0):
            where = [predicted, self.lost_at] if self.lost else [predicted]
            turned = self._bank_hold(frame, where)
        if turned is not None:  # the same target, turned: take its peak, relearn
            pos = new if not self.lost and r >= cfg.policy.r_stop else turned[0]
            r = max(r, turned[1])
            if self.lost:
                found_from = self.lost_at
                self.motion.reset(pos)
                self.centre = pos
            else:
                self.centre = self.motion.correct(pos)
            eta = cfg.rotation.refind if self.lost else cfg.rotation.relearn
            self.lost = False
            self.n_lost = 0
        elif cfg.adaptive:
            p = cfg.policy
            r_lost, r_stop = p.r_lost, p.r_stop
            if cfg.moving_relax < 1 and self.motion is not None and not self.lost:
                if np.hypot(*self.motion.velocity) > cfg.moving_speed_px:
                    r_lost, r_stop = r_lost * cfg.moving_relax, r_stop * cfg.moving_relax
            in_gate = self._in_gate(new)
            held = (
                not self.lost
                and r < 1.0
                and self.signature is not None
                and in_gate
                and self.signature.passes(frame, new)
            )
            if held:  # a turning spindle: take the peak, let the template catch up
                self.centre = self.motion.correct(new)
                eta = max(self.history.learning_rate(r), cfg.signature.learn * p.eta0)
                if self.extent is not None:
                    self.extent.update(frame, self.centre)
            elif (
                rejected
                or (self.lost and r < p.r_found and not in_gate)
                or r < r_lost
                or (not self.lost and self.scene_factor(frame, new) == 0.0)
            ):
                if not self.lost:
                    self.lost_at = self.centre
                self.lost = True  # coast on the prediction (hold without motion model)
                self.centre = predicted
                eta = 0.0
            else:
                if self.lost:
                    found_from = self.lost_at
                if self.motion is None:
                    self.centre = new
                elif self.lost:
                    self.motion.reset(new)
                    self.centre = new
                elif r >= r_stop:
                    self.centre = self.motion.correct(new)
                else:  # doubtful peak (a droplet drags it): coast, keep the target
                    self.centre = predicted
                self.lost = False
                self.n_lost = 0
                eta = self.history.learning_rate(r)
                if self._turned_refind:
                    eta = max(eta, cfg.rotation.refind)
                anchor = self.anchor
                note = anchor and anchor.complete and r >= 1.0 and self.n_frame % 4 == 0
                if r >= 1.0 or self.history.n < cfg.policy.warmup:
                    self.apce_ref = self.apce_ref + apces
                    self.apce_n += 1
                if self.signature is not None and r >= 1.0 and found_from is None:
                    self.signature.learn(frame, self.centre)
                if self.extent is not None and r >= p.r_stop and found_from is None:
                    self.extent.update(frame, self.centre)
                if self.scale is not None and r >= cfg.scale.min_r and found_from is None:
                    self.scale.update(frame, self.centre)
                self.history.accept(peak, a, r)
        else:
            self.centre = new
            eta = cfg.policy.eta0
        if eta > 0:
            feats, _ = self._features(frame, self.centre)
            if cfg.context > 0:
                train = self._with_context(frame, self.centre, feats)
                for model, xf in zip(self.models, train, strict=True):
                    model.update(xf, self.yf, eta)
            else:
                kcf.update_models(self.models, feats, self.yf, eta)
            if note:  # the anchor's reference <A>, on the window just learnt from
                self.anchor.note(self.anchor.score(feats))
                if self.bank is not None and self.bank.due():
                    self.bank.note(self.bank.score(self._bank_feats(feats)))
            if self.anchor and r >= 1.0 and turned is None:
                if self.bank is not None and not self.anchor.complete:
                    self._bank_learn(frame)
                self.anchor.learn(feats, self.yf)
        if self.scene is not None and not self.lost:
            self.scene.learn(frame, self.centre, self.shape)
        sizer = self.extent or self.scale
        w, h = self.size if sizer is None else sizer.size
        box = (self.centre[0] - w / 2, self.centre[1] - h / 2, w, h)
        conf = r * self.contrast_factor(frame) * self.scene_factor(frame, self.centre)
        return FrameEstimate(self.centre, box, r, eta, tuple(weights), self.lost, conf, found_from)

    def contrast_factor(self, frame: np.ndarray) -> float:
        """``e`` of :mod:`.evidence` for the part of the box at the current centre that lies
        in the frame (noise from the same part of the search window); 0 if under half the box
        is in the frame (the target has left the field)."""
        patch = evidence.inside(frame, self.centre, self.size)
        if min(patch.shape) < 2 or patch.size < 0.5 * self.size[0] * self.size[1]:
            return 0.0
        window = evidence.inside(frame, self.centre, self.shape[::-1])
        s = evidence.contrast_to_noise(patch, evidence.noise_sigma(window))
        return evidence.confidence_factor(s)

    def scene_factor(self, frame: np.ndarray, centre: tuple[float, float]) -> float:
        """The box at ``centre`` px against the remembered static scene (:mod:`.scene`):
        ``e`` of :mod:`.evidence` applied to its excess over the scene, 0 if the box shows only
        the scene; 1 without the memory or where it does not cover the box."""
        if self.scene is None:
            return 1.0
        window = evidence.inside(frame, centre, self.shape[::-1])
        sigma_n = evidence.noise_sigma(window)
        s = self.scene.excess(frame, centre, self.size, self.shape, sigma_n)
        return 1.0 if s is None else evidence.confidence_factor(s)


@dataclass(frozen=True)
class TrackResult:
    """A tracked sequence: boxes (T, 4) px as (x, y, w, h), per-frame reliability, rate,
    confidence, and where a re-detected target had been lost ((T, 2) px, NaN on frames
    that are not a re-detection; :class:`FrameEstimate`)."""

    boxes: np.ndarray
    reliability: np.ndarray
    learning_rate: np.ndarray
    weights: np.ndarray
    lost: np.ndarray
    confidence: np.ndarray
    redetected_from: np.ndarray
    seconds: float
    cpu_seconds: float = 0.0
    frame_cpu_seconds: np.ndarray | None = None

    @property
    def centres(self) -> np.ndarray:
        """Box centres (T, 2) px as (x, y)."""
        return self.boxes[:, :2] + 0.5 * self.boxes[:, 2:]

    @property
    def fps(self) -> float:
        """Frames per wall-clock second of the tracking loop (frame 0 excluded)."""
        n = len(self.boxes) - 1
        return n / self.seconds if self.seconds > 0 else float("inf")

    @property
    def cpu_fps(self) -> float:
        """Frames per second of this process's CPU time (what one core does, whatever else
        the machine runs)."""
        n = len(self.boxes) - 1
        return n / self.cpu_seconds if self.cpu_seconds > 0 else float("inf")

    @property
    def tracking(self) -> np.ndarray:
        """Per frame, True where the step began on a tracked target (the previous frame not
        lost): one search window; the others search up to ``(2k + 1)^2`` (frame 0 False)."""
        began = np.zeros(len(self.lost), dtype=bool)
        began[1:] = ~self.lost[:-1]
        return began

    def cpu_split(self) -> tuple[int, float, int, float]:
        """(frames, CPU s) of the steps that began tracked, then of those that searched."""
        if self.frame_cpu_seconds is None:
            raise ValueError("no per-frame CPU times in this result")
        t = self.tracking
        s = ~t
        s[0] = False
        cpu = self.frame_cpu_seconds
        return int(t.sum()), float(cpu[t].sum()), int(s.sum()), float(cpu[s].sum())

    @property
    def tracking_cpu_fps(self) -> float:
        """Frames per CPU second while tracking (the steps that began on a tracked target)."""
        n, cpu, _, _ = self.cpu_split()
        return n / cpu if cpu > 0 else float("inf")


def track(
    frames: np.ndarray, box: tuple[float, float, float, float], config: TrackerConfig = MFAKCF
) -> TrackResult:
    """Track a (T, H, W) sequence from the box (x, y, w, h) px on frame 0."""
    tracker = Tracker(frames[0], box, config)
    n_feat = len(config.features)
    first = tracker.contrast_factor(np.asarray(frames[0], dtype=np.float64))
    out = [
        FrameEstimate(tracker.centre, tuple(box), 1.0, 0.0, (1.0 / n_feat,) * n_feat, False, first)
    ]
    t0 = time.perf_counter()
    c0 = time.process_time()
    ticks = [c0]
    for frame in frames[1:]:
        out.append(tracker.step(frame))
        ticks.append(time.process_time())
    seconds = time.perf_counter() - t0
    cpu_seconds = ticks[-1] - c0
    return TrackResult(
        boxes=np.array([e.box for e in out], dtype=float),
        reliability=np.array([e.reliability for e in out]),
        learning_rate=np.array([e.learning_rate for e in out]),
        weights=np.array([e.weights for e in out]),
        lost=np.array([e.lost for e in out]),
        confidence=np.array([e.confidence for e in out]),
        redetected_from=np.array([e.redetected_from or (np.nan, np.nan) for e in out]),
        seconds=seconds,
        cpu_seconds=cpu_seconds,
        frame_cpu_seconds=np.diff(ticks, prepend=c0),
    )
