"""The 1-D scale filter (oocyte_fe/tracking/scale.py, DSST-style): a blob of known size
change, a static target, and a clean spindle that grows or shrinks by 20 % while pushed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from oocyte_fe.tracking.scale import ScaleFilter, ScaleModel
from oocyte_fe.tracking.synthetic import SequenceSpec, generate
from oocyte_fe.tracking.tracker import MFAKCF, TrackerConfig, track


def blob(scale: float) -> np.ndarray:
    """A bright Gaussian barrel (sigma 10 x 5 px times ``scale``, +10 %) on a flat field of
    1000 counts, centred at (100, 100) px."""
    v, u = np.mgrid[0:200, 0:200]
    r2 = ((u - 100) / (10 * scale)) ** 2 + ((v - 100) / (5 * scale)) ** 2
    return 1000.0 * (1.0 + 0.1 * np.exp(-0.5 * r2))


def test_static_target_keeps_scale_one() -> None:
    """The same frame 40 times: the scale stays 1 (to 1e-9; the model's own-sample offset is
    taken off the peak). A clear spindle in shot noise and moving texture, at its true
    centre over the 29 frames before the push: within 1.5 % of 1 (0.996-1.013 measured)."""
    frame = blob(1.0)
    f = ScaleFilter(frame, (100.0, 100.0), (44.0, 22.0))
    scales = [f.update(frame, (100.0, 100.0)) for _ in range(40)]
    np.testing.assert_allclose(scales, 1.0, atol=1e-9)
    assert f.size == pytest.approx((44.0, 22.0), rel=1e-9)
    seq = generate(replace(grown(0.0), n_frames=40, approach_frames=10))
    centres = seq.boxes[:, :2] + 0.5 * seq.boxes[:, 2:]
    f = ScaleFilter(seq.frames[0], tuple(centres[0]), tuple(seq.boxes[0, 2:]))
    scales = [f.update(seq.frames[k], tuple(centres[k])) for k in range(1, 30)]
    assert np.max(np.abs(np.array(scales) - 1.0)) < 0.015


def test_one_update_measures_a_known_size_change() -> None:
    """The target 0.90 / 0.95 / 1.05 / 1.10 x its size in the next frame. With the full step
    (gain 1, as DSST) one update gives 0.903 / 0.964 / 1.059 / 1.099 (measured; the 17
    samples of step 1.02 reach 0.85-1.17): within 0.015. With the default gain 0.1 it
    applies a tenth of the measured change in log scale: ``true^0.1`` within 0.0015."""
    for true in (0.9, 0.95, 1.05, 1.1):
        full = ScaleFilter(blob(1.0), (100.0, 100.0), (44.0, 22.0), ScaleModel(gain=1.0))
        assert full.update(blob(true), (100.0, 100.0)) == pytest.approx(true, abs=0.015)
        damped = ScaleFilter(blob(1.0), (100.0, 100.0), (44.0, 22.0))
        assert damped.update(blob(true), (100.0, 100.0)) == pytest.approx(true**0.1, abs=0.0015)


def grown(growth: float) -> SequenceSpec:
    """A clear (20 %) spindle pushed 20 um over 80 frames while its size changes by
    ``1 + growth``; no rotation, visible at every angle."""
    return SequenceSpec(
        name=f"grow{growth:g}", seed=4, n_frames=150, contrast=0.2, displacement_um=20.0,
        approach_frames=80, enter_frames=30, growth=growth, rotation_deg=0.0,
        polarizer_visibility=False,
    )  # fmt: skip


@pytest.mark.parametrize(("growth", "tol"), [(0.2, 0.05), (-0.2, 0.24)])
def test_box_follows_a_growing_or_shrinking_spindle(growth: float, tol: float) -> None:
    """MFAKCF with the scale filter (the chosen settings): over the last 10 frames the box's
    side (square root of the area) against the truth's is 0.99-1.01 for the growing spindle
    and 1.18-1.22 for the shrinking one (measured: the damped, slowly learning filter
    follows a shrink only partly); without it the box keeps the first box's area exactly
    and its side is 0.85-0.86 and 1.27-1.30 of the truth's. Asserted: within ``tol`` of the
    truth, and closer to it than the fixed box by more than 0.05 on every frame."""
    seq = generate(grown(growth))
    truth = np.sqrt(np.prod(seq.boxes[-10:, 2:], axis=1))
    box0 = tuple(seq.boxes[0])
    config: TrackerConfig = replace(MFAKCF, scale=ScaleModel())
    with_scale = track(seq.frames, box0, config).boxes
    fixed = track(seq.frames, box0, MFAKCF).boxes
    error = np.abs(np.sqrt(np.prod(with_scale[-10:, 2:], axis=1)) / truth - 1.0)
    error_fixed = np.abs(np.sqrt(box0[2] * box0[3]) / truth - 1.0)
    np.testing.assert_allclose(np.prod(fixed[:, 2:], axis=1), box0[2] * box0[3], rtol=1e-12)
    assert np.all(error < tol)
    assert np.all(error_fixed - error > 0.05)
