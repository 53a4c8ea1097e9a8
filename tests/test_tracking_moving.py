"""``moving_relax``: lower loss thresholds while the tracked target moves (issue 29).

The reliability ``r`` is measured against the first, still frames, where the static cytoplasm
around the spindle answers the filter too; on the benchmark's ``occ2_light0_c8_fast`` the
spindle is declared lost in the fast push although the peak is still on it, and is never
taken back (docs/tracking.md, "Losses in the fast push")."""

from __future__ import annotations

import numpy as np
import pytest

from oocyte_fe.tracking import metrics
from oocyte_fe.tracking.synthetic import Sequence, benchmark_grid, generate
from oocyte_fe.tracking.tracker import MFAKCF, MFAKCF_MOVING, TrackerConfig, track


@pytest.fixture(scope="module")
def fast_push() -> Sequence:
    [spec] = [s for s in benchmark_grid() if s.name == "occ2_light0_c8_fast"]
    return generate(spec)


@pytest.mark.parametrize(
    "fields", [{"moving_relax": 0.0}, {"moving_relax": 1.5}, {"moving_relax": float("nan")},
               {"moving_speed_px": -1.0}, {"moving_speed_px": float("nan")},
               {"moving_relax": 0.5}],  # no motion model: its speed is what the option reads
)  # fmt: skip
def test_moving_thresholds_refuse_nonsense(fields: dict) -> None:
    with pytest.raises(ValueError, match="moving_relax"):
        TrackerConfig(**fields)


def test_a_still_target_is_tracked_as_without_the_option(fast_push: Sequence) -> None:
    # frames 0-39: the spindle waits for the pipette; the motion model's speed stays < 1 px/frame
    still = fast_push.frames[:40]
    box = tuple(fast_push.boxes[0])
    np.testing.assert_array_equal(
        track(still, box, MFAKCF_MOVING).boxes, track(still, box, MFAKCF).boxes
    )


def test_the_spindle_is_kept_through_the_fast_push(fast_push: Sequence) -> None:
    box = tuple(fast_push.boxes[0])
    plain = track(fast_push.frames, box, MFAKCF)
    moving = track(fast_push.frames, box, MFAKCF_MOVING)
    # measured 0.317 and 0.983 (docs/tracking.md); the margins hold against round-off
    assert metrics.precision_at(metrics.centre_error(plain.boxes, fast_push.boxes)) < 0.5
    assert metrics.precision_at(metrics.centre_error(moving.boxes, fast_push.boxes)) > 0.9
