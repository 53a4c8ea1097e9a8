"""OTB metrics, the synthetic sequence generator and the spindle_tracking kind's input check."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from oocyte_fe.tracking import metrics
from oocyte_fe.tracking.synthetic import SequenceSpec, benchmark_grid, generate, gt_box


def test_precision_and_success_known_answers() -> None:
    truth = np.array([[0.0, 0.0, 2.0, 2.0]] * 3)
    boxes = np.array([[0.0, 0.0, 2.0, 2.0], [1.0, 0.0, 2.0, 2.0], [30.0, 0.0, 2.0, 2.0]])
    e = metrics.centre_error(boxes, truth)
    np.testing.assert_allclose(e, [0.0, 1.0, 30.0])
    assert metrics.precision_at(e, 20.0) == pytest.approx(2 / 3)
    curve = metrics.precision_curve(e, np.array([0.0, 1.0, 29.9, 30.0]))
    np.testing.assert_allclose(curve, [1 / 3, 2 / 3, 2 / 3, 1.0])
    o = metrics.iou(boxes, truth)
    np.testing.assert_allclose(o, [1.0, 2.0 / 6.0, 0.0])  # overlap 1 x 2 over union 6
    assert metrics.success_rate(o) == pytest.approx(1 / 3)
    # S(o) over 0, 0.05, ..., 1: IoU 1 counts for 20 thresholds, IoU 1/3 for 7 (o < 1/3)
    assert metrics.success_auc(o) == pytest.approx((20 + 7 + 0) / (3 * 21))


def test_frames_to_recover() -> None:
    occluded = np.zeros(20, dtype=bool)
    occluded[3:6] = True
    occluded[12:14] = True
    errors = np.full(20, 50.0)
    errors[:3] = 1.0
    errors[8:] = 1.0  # back 2 frames after the first occlusion ends (frame 6)
    errors[14:] = 50.0  # never back after the second
    assert metrics.frames_to_recover(errors, occluded, 5.0) == [2, -1]


def test_gt_box_of_a_rotated_ellipse() -> None:
    """Axis-aligned extents of an ellipse: a cos / b sin combined in quadrature."""
    box = gt_box(np.array([50.0, 40.0]), np.radians(90.0), 20.0, 10.0)
    np.testing.assert_allclose(box, [45.0, 30.0, 10.0, 20.0], atol=1e-12)


SMALL = SequenceSpec(
    name="small",
    seed=4,
    n_frames=40,
    enter_frames=5,
    approach_frames=30,
    displacement_um=6.0,
    n_occluders=1,
    occlusion_frames=8,
    light_drift=0.3,
    shape=(160, 160),
    read_noise=0.0,
)


def test_spindle_drawn_where_the_ground_truth_box_is() -> None:
    """Two renders that differ only in spindle contrast: their difference is the spindle
    alone (plus a small noise term); its centroid sits at the box centre within 0.5 px."""
    lo = generate(replace(SMALL, n_occluders=0, contrast=0.10, photons=20000.0))
    hi = generate(replace(SMALL, n_occluders=0, contrast=0.30, photons=20000.0))
    np.testing.assert_allclose(lo.boxes, hi.boxes)
    for k in (0, 20, 39):
        diff = hi.frames[k].astype(float) - lo.frames[k].astype(float)
        x, y, w, h = hi.boxes[k]
        rows, cols = np.indices(diff.shape) + 0.5  # pixel centres
        inside = (np.abs(cols - x - w / 2) < w) & (np.abs(rows - y - h / 2) < h)
        weight = np.where(inside, np.clip(diff, 0, None), 0.0)
        centroid = np.array([np.sum(weight * cols), np.sum(weight * rows)]) / weight.sum()
        np.testing.assert_allclose(centroid, [x + w / 2, y + h / 2], atol=0.5)


def test_occlusion_flags_and_light_drift() -> None:
    seq = generate(SMALL)
    assert seq.frames.shape == (40, 160, 160)
    assert 3 <= seq.occluded.sum() <= 15
    level = np.median(seq.frames.reshape(40, -1), axis=1)
    spread = level / level.mean()
    assert spread.max() - spread.min() > 0.15  # the light moves
    assert np.all(np.abs(spread - 1) < 0.35)  # within +-30 % (plus the pipette's shadow)


def test_benchmark_grid_has_24_distinct_sequences() -> None:
    grid = benchmark_grid()
    assert len(grid) == 24 and len({s.name for s in grid}) == 24
    assert len({s.seed for s in grid}) == 24
    assert all(s.n_frames == 300 for s in grid)


def test_benchmark_summary_pools_frames_and_gains() -> None:
    """Two short sequences, our two trackers: the summary is the metric over the pooled
    frames, the gain is 100 (a - b) / b, and the table has one row per tracker and group."""
    from oocyte_fe.tracking import benchmark as bench

    specs = [replace(SMALL, name="a", n_occluders=0, light_drift=0.0), replace(SMALL, name="b")]
    result = bench.run_benchmark(specs, use_opencv=False)
    chosen = result.select("MFAKCF")
    errors = np.concatenate([s.errors_px for s in chosen])
    summary = result.summary("MFAKCF")
    assert summary["precision_20px"] == metrics.precision_at(errors, 20.0)
    assert summary["n_frames"] == 2 * SMALL.n_frames
    assert result.summary("MFAKCF", bench.is_occlusion)["n_frames"] == SMALL.n_frames
    a, b = summary["precision_20px"], result.summary("KCF (HOG)")["precision_20px"]
    assert bench.gains(result)["precision_gain_all_pct"] == pytest.approx(100 * (a - b) / b)
    assert bench.gain_pct(0.5, 0.25) == pytest.approx(100.0)
    # all, occlusion, light drift, held out; no row for the (here empty) tuning subset
    assert bench.table(result).count("| MFAKCF |") == 4


def test_tuning_subset_is_six_balanced_grid_sequences() -> None:
    """The motion model's tuning subset: indices 1, 6, 10, 13, 16, 23 of the grid, two per
    occluder level, and each level of light drift, contrast and speed three times."""
    from oocyte_fe.tracking import benchmark as bench

    specs = benchmark_grid(300)
    tune = [i for i, s in enumerate(specs) if bench.is_tuning(s)]
    assert tune == [1, 6, 10, 13, 16, 23]
    assert sum(bench.is_held_out(s) for s in specs) == 18
    chosen = [specs[i] for i in tune]
    assert sorted(s.n_occluders for s in chosen) == [0, 0, 1, 1, 2, 2]
    for level in (0.0, 0.3):
        assert sum(s.light_drift == level for s in chosen) == 3
    for level in (0.04, 0.08):
        assert sum(s.contrast == level for s in chosen) == 3
    assert sum(s.name.endswith("fast") for s in chosen) == 3
