"""The anchor check and the widening re-detection of MFAKCF, on cases with known answers."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from oocyte_fe.tracking import kcf, metrics
from oocyte_fe.tracking.anchor import Anchor
from oocyte_fe.tracking.benchmark import reseeded
from oocyte_fe.tracking.synthetic import benchmark_grid, generate
from oocyte_fe.tracking.tracker import MFAKCF, MFAKCF_NO_ANCHOR, track

SIGMA, LAM = 0.5, 1e-4


def _patch(seed: int, shape: tuple[int, int] = (12, 16), channels: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = ndimage.gaussian_filter(rng.normal(size=shape + (channels,)), (1.0, 1.0, 0))
    return kcf.fft_features(x * kcf.cosine_window(shape)[..., None])


def test_anchor_is_the_mean_of_its_first_frames_then_frozen() -> None:
    """After frames 1..n the anchor's x_hat and alpha_hat are the plain means of the n
    frames' (x_hat, alpha_hat), to rounding; the (n+1)-th frame changes nothing."""
    yf = np.fft.fft2(kcf.gaussian_labels((12, 16), 1.0))
    xs = [_patch(s) for s in range(4)]
    anchor = Anchor([kcf.KcfModel.fit(xs[0], yf, SIGMA, LAM)], n_frames=3)
    for xf in xs[1:3]:
        anchor.learn([xf], yf)
    assert anchor.complete
    np.testing.assert_allclose(anchor.models[0].xf, np.mean(xs[:3], axis=0), atol=1e-12)
    alphas = [kcf.train(xf, yf, SIGMA, LAM) for xf in xs[:3]]
    np.testing.assert_allclose(anchor.models[0].alphaf, np.mean(alphas, axis=0), atol=1e-12)
    anchor.learn([xs[3]], yf)
    np.testing.assert_allclose(anchor.models[0].xf, np.mean(xs[:3], axis=0), atol=1e-12)


def test_anchor_score_is_the_label_on_its_own_frame_and_low_elsewhere() -> None:
    """A one-frame anchor answers its own frame with its label's peak, y(0) = 1 (kernel
    ridge regression with lambda = 1e-4 refits its labels within 1 %; 0.994 measured), and
    an unrelated texture at most 0.5 of that; the reference is the mean of the noted scores."""
    yf = np.fft.fft2(kcf.gaussian_labels((12, 16), 1.0))
    xf = _patch(0)
    anchor = Anchor([kcf.KcfModel.fit(xf, yf, SIGMA, LAM)], n_frames=1)
    assert anchor.score([xf]) == pytest.approx(1.0, abs=0.01)
    assert anchor.score([_patch(7)]) < 0.5
    assert anchor.reference is None
    anchor.note(0.8)
    anchor.note(0.6)
    assert anchor.reference == pytest.approx(0.7, abs=1e-12)
    with pytest.raises(ValueError, match="n_frames"):
        Anchor([kcf.KcfModel.fit(xf, yf, SIGMA, LAM)], n_frames=0)


@pytest.mark.slow
def test_anchor_refinds_spindle_pushed_away_at_low_contrast() -> None:
    """A 4 % contrast spindle pushed 35 um in 60 frames past one droplet (the benchmark's
    occ1_light0_c4_fast cell, drawn with seed + 1000: not one of the benchmark's 24): the
    previous MFAKCF loses it in the push and never finds it again (precision @20 px 0.25
    measured), MFAKCF re-finds it once the widening search reaches it and the anchor
    confirms it (0.92 measured). Asserted with margins: < 0.40 and > 0.85."""
    cell = next(s for s in benchmark_grid() if s.name == "occ1_light0_c4_fast")
    seq = generate(reseeded([cell], 1000)[0])
    box = tuple(seq.boxes[0])
    p20 = {}
    for name, config in (("old", MFAKCF_NO_ANCHOR), ("new", MFAKCF)):
        result = track(seq.frames, box, config)
        p20[name] = metrics.precision_at(metrics.centre_error(result.boxes, seq.boxes), 20.0)
    assert p20["old"] < 0.40
    assert p20["new"] > 0.85
