"""Tracking metrics of the OTB benchmark (Wu, Lim and Yang 2013, "Online object tracking: a
benchmark", CVPR), the measures the KCF papers and seed 000 (Fig. 11) report.

- Centre error ``e_t = ||c_t - c_t^gt||`` (px) between the centres of the tracked and the
  ground-truth boxes.
- Precision curve ``P(tau) = #{t : e_t <= tau} / T`` over thresholds tau (px); the
  precision is ``P(20 px)``.
- Overlap ``IoU_t = |B_t ^ B_t^gt| / |B_t v B_t^gt|`` of axis-aligned boxes (x, y, w, h);
  success curve ``S(o) = #{t : IoU_t > o} / T``, the success rate is ``S(0.5)``, and the
  success-plot AUC is the mean of ``S`` over ``o = 0, 0.05, ..., 1`` (21 points, OTB).
- Frames to recover after an occlusion: for each run of occluded frames, the number of
  frames after its end until the centre error is back within the threshold (or -1 if never).
"""

from __future__ import annotations

import numpy as np

PRECISION_THRESHOLDS_PX = np.arange(0, 51, dtype=float)
SUCCESS_THRESHOLDS = np.linspace(0.0, 1.0, 21)


def centres(boxes: np.ndarray) -> np.ndarray:
    """Centres (T, 2) of boxes (T, 4) given as (x, y, w, h)."""
    b = np.asarray(boxes, dtype=float)
    return b[:, :2] + 0.5 * b[:, 2:4]


def centre_error(boxes: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """``e_t``, px, per frame."""
    return np.linalg.norm(centres(boxes) - centres(truth), axis=1)


def iou(boxes: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """Intersection over union of axis-aligned boxes (x, y, w, h), per frame."""
    a = np.asarray(boxes, dtype=float)
    b = np.asarray(truth, dtype=float)
    x0 = np.maximum(a[:, 0], b[:, 0])
    y0 = np.maximum(a[:, 1], b[:, 1])
    x1 = np.minimum(a[:, 0] + a[:, 2], b[:, 0] + b[:, 2])
    y1 = np.minimum(a[:, 1] + a[:, 3], b[:, 1] + b[:, 3])
    inter = np.clip(x1 - x0, 0, None) * np.clip(y1 - y0, 0, None)
    union = a[:, 2] * a[:, 3] + b[:, 2] * b[:, 3] - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1.0), 0.0)


def precision_curve(
    errors: np.ndarray, thresholds: np.ndarray = PRECISION_THRESHOLDS_PX
) -> np.ndarray:
    """``P(tau)`` for each threshold tau, px."""
    e = np.asarray(errors, dtype=float)
    return np.mean(e[None, :] <= np.asarray(thresholds)[:, None], axis=1)


def precision_at(errors: np.ndarray, threshold: float = 20.0) -> float:
    """``P(threshold)``: fraction of frames with centre error within threshold px."""
    return float(np.mean(np.asarray(errors) <= threshold))


def success_curve(overlaps: np.ndarray, thresholds: np.ndarray = SUCCESS_THRESHOLDS) -> np.ndarray:
    """``S(o)``: fraction of frames with IoU > o, for each o."""
    v = np.asarray(overlaps, dtype=float)
    return np.mean(v[None, :] > np.asarray(thresholds)[:, None], axis=1)


def success_rate(overlaps: np.ndarray, threshold: float = 0.5) -> float:
    """``S(0.5)``: fraction of frames with IoU > 0.5."""
    return float(np.mean(np.asarray(overlaps) > threshold))


def success_auc(overlaps: np.ndarray) -> float:
    """Area under the success plot: mean of ``S`` over 21 thresholds in [0, 1]."""
    return float(np.mean(success_curve(overlaps)))


def frames_to_recover(errors: np.ndarray, occluded: np.ndarray, threshold: float) -> list[int]:
    """For each run of occluded frames: frames after its end until ``e_t <= threshold``.

    0 means the first frame after the occlusion is already within the threshold; -1 that the
    tracker never came back before the sequence (or the next occlusion) ended.
    """
    e = np.asarray(errors, dtype=float)
    occ = np.asarray(occluded, dtype=bool)
    out = []
    t = 0
    n = len(e)
    while t < n:
        if not occ[t]:
            t += 1
            continue
        while t < n and occ[t]:
            t += 1
        end = t
        while t < n and not occ[t] and e[t] > threshold:
            t += 1
        if end < n:
            out.append(t - end if t < n and not occ[t] else -1)
    return out
