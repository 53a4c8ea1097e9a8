"""Per-frame CPU time of a track: the split between steps that began on a tracked target and
steps that searched (the issue 29 speed goal is "while tracking")."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from oocyte_fe.tracking.tracker import MFAKCF, TrackResult, track


def _result(lost: list[bool], cpu: list[float]) -> TrackResult:
    n = len(lost)
    return TrackResult(
        boxes=np.zeros((n, 4)),
        reliability=np.ones(n),
        learning_rate=np.zeros(n),
        weights=np.zeros((n, 2)),
        lost=np.array(lost),
        confidence=np.ones(n),
        redetected_from=np.full((n, 2), np.nan),
        seconds=1.0,
        cpu_seconds=float(np.sum(cpu)),
        frame_cpu_seconds=np.array(cpu),
    )


def test_split_counts_the_step_after_a_lost_frame_as_search() -> None:
    # frame 0 is the set-up; frame 3 is declared lost, so the step of frame 4 searched
    r = _result([False, False, False, True, False, False], [9.0, 1.0, 1.0, 1.0, 5.0, 2.0])
    assert r.cpu_split() == (4, 5.0, 1, 5.0)
    assert r.tracking_cpu_fps == pytest.approx(4 / 5.0)


def test_split_needs_the_per_frame_times() -> None:
    r = _result([False, False], [0.0, 1.0])
    r = TrackResult(**{**r.__dict__, "frame_cpu_seconds": None})
    with pytest.raises(ValueError, match="per-frame"):
        r.cpu_split()


def test_searching_costs_more_per_frame_than_tracking() -> None:
    """A textured target that vanishes: the tracker loses it and searches its 3 x 3 grid (9
    windows or more) each frame, so a searching step costs several tracked ones (3x at the
    least); the per-frame times add up to the loop's CPU time."""
    rng = np.random.default_rng(3)
    base = 1000.0 + 40.0 * ndimage.gaussian_filter(rng.normal(size=(200, 200)), 2.0)
    blank = np.full((200, 200), 1000.0)
    frames = np.array([np.roll(base, k // 2, axis=1) for k in range(25)] + [blank] * 15)
    r = track(frames, (80.0, 80.0, 40.0, 40.0), MFAKCF)
    n_track, cpu_track, n_search, cpu_search = r.cpu_split()
    assert n_track + n_search == len(frames) - 1
    assert n_search >= 5
    assert r.frame_cpu_seconds.sum() == pytest.approx(r.cpu_seconds, rel=1e-9)
    assert cpu_search / n_search > 3.0 * cpu_track / n_track
