"""OpenCV's KCF and CSRT trackers as baselines (optional extra ``tracking-opencv``:
opencv-contrib-python-headless).

OpenCV 4.5.1 and later (5.x included) expose ``cv2.TrackerKCF_create`` and
``cv2.TrackerCSRT_create`` in the main namespace, with ``update`` returning integer boxes;
the 3.x / 4.x-contrib API lives in ``cv2.legacy``. :func:`opencv_api` says which one the
installed version has; the main one is used when present.
"""

from __future__ import annotations

import time

import numpy as np


def opencv_api() -> str | None:
    """``"cv2.TrackerKCF_create (OpenCV x.y)"``, ``"cv2.legacy ..."`` or None if absent."""
    try:
        import cv2
    except ImportError:
        return None
    if hasattr(cv2, "TrackerKCF_create") and hasattr(cv2, "TrackerCSRT_create"):
        return f"cv2.TrackerKCF_create / cv2.TrackerCSRT_create (OpenCV {cv2.__version__})"
    if hasattr(cv2, "legacy") and hasattr(cv2.legacy, "TrackerKCF_create"):
        return f"cv2.legacy.TrackerKCF_create (OpenCV {cv2.__version__})"
    return None


def _create(name: str):
    import cv2

    factory = f"Tracker{name}_create"
    if hasattr(cv2, factory):
        return getattr(cv2, factory)()
    return getattr(cv2.legacy, factory)()


def to_uint8(frames: np.ndarray) -> np.ndarray:
    """8-bit 3-channel frames (OpenCV's KCF fails on one channel) with one fixed scale
    (2 x the first frame's median = 255), so the illumination drift stays in the data as it
    does for our trackers."""
    scale = 127.5 / max(float(np.median(frames[0])), 1e-12)
    gray = np.clip(np.asarray(frames) * scale, 0, 255).astype(np.uint8)
    return np.repeat(gray[..., None], 3, axis=-1)


def track_opencv(
    name: str, frames: np.ndarray, box: tuple[float, float, float, float]
) -> tuple[np.ndarray, float]:
    """Boxes (T, 4) px of OpenCV's ``name`` ("KCF" or "CSRT") and its frames per second.

    A frame where OpenCV reports a failure keeps the previous box (OTB's convention of
    scoring every frame).
    """
    images = to_uint8(frames)
    tracker = _create(name)
    tracker.init(images[0], tuple(int(round(v)) for v in box))
    boxes = [np.asarray(box, dtype=float)]
    t0 = time.perf_counter()
    for image in images[1:]:
        ok, found = tracker.update(image)
        boxes.append(np.asarray(found, dtype=float) if ok else boxes[-1])
    seconds = time.perf_counter() - t0
    return np.array(boxes), (len(images) - 1) / seconds if seconds > 0 else float("inf")
