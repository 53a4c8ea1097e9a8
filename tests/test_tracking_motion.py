"""The Kalman motion prediction of the tracker's centre, on cases with known answers."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy import ndimage

from oocyte_fe.tracking.motion import CentreFilter, MotionModel
from oocyte_fe.tracking.tracker import MFAKCF, MFAKCF_HOLD, Tracker


def test_constant_velocity_is_learnt_and_coasted_exactly() -> None:
    """With rho = 1 (constant velocity) the filter's velocity converges to that of exact
    constant-velocity measurements, and without measurements the centre moves n v."""
    v = np.array([1.7, -0.6])
    kf = CentreFilter((10.0, 20.0), MotionModel(rho=1.0, q=0.01))
    for t in range(1, 60):
        kf.predict()
        kf.correct(tuple(np.array([10.0, 20.0]) + v * t))
    np.testing.assert_allclose(kf.velocity, v, atol=1e-3)
    start = np.array(kf.centre)
    for _ in range(15):
        kf.predict()
    np.testing.assert_allclose(np.array(kf.centre) - start, 15 * v, atol=0.02)


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.8])
def test_damped_coasting_distance(rho: float) -> None:
    """Coasting n frames from velocity v moves the centre by v (1 - rho^n) / (1 - rho)
    and widens the validation gate (the predicted position's variance grows)."""
    kf = CentreFilter((0.0, 0.0), MotionModel(rho=rho))
    kf.state[:, 1] = (3.0, -2.0)
    v = np.array(kf.velocity)
    near = (1.0, 0.0)
    gate0 = kf.gate_distance(near)
    n = 7
    for _ in range(n):
        kf.predict()
    expected = v * (1 - rho**n) / (1 - rho)
    np.testing.assert_allclose(kf.centre, expected, atol=1e-12)
    assert kf.gate_distance(tuple(np.array(kf.centre) + near)) < gate0


def test_motion_model_rejects_bad_settings() -> None:
    with pytest.raises(ValueError, match="rho"):
        MotionModel(rho=1.5)


def _moving_target_sequence(n: int, hidden: range, v: tuple[float, float]):
    """A textured 40 x 40 px square moving at v px/frame over a flat, noisy background; on
    the ``hidden`` frames the square is not drawn (a full occlusion). Returns the frames and
    the square's centres."""
    rng = np.random.default_rng(5)
    tex = 100.0 + 30.0 * ndimage.gaussian_filter(rng.normal(size=(40, 40)), 1.5)
    frames, centres = [], []
    for t in range(n):
        cx, cy = 70.0 + v[0] * t, 90.0 + v[1] * t
        img = 100.0 + rng.normal(scale=1.0, size=(220, 260))
        if t not in hidden:
            x0, y0 = int(round(cx - 20)), int(round(cy - 20))
            img[y0 : y0 + 40, x0 : x0 + 40] = tex + rng.normal(scale=1.0, size=(40, 40))
        frames.append(img)
        centres.append((float(round(cx - 20) + 20), float(round(cy - 20) + 20)))
    return frames, np.array(centres)


def test_prediction_follows_constant_velocity_target_through_occlusion() -> None:
    """The square moves 2 px/frame and vanishes for 12 frames. Holding the last position
    (MFAKCF_HOLD) leaves the box 24 px behind when it reappears; the constant-velocity
    prediction (rho = 1) is within 3 px then; all find it again afterwards (MFAKCF, rho = 0.8,
    coasts 1 / (1 - rho) = 5 frames' worth and re-finds it in its gate)."""
    hidden = range(25, 37)
    frames, truth = _moving_target_sequence(60, hidden, (2.0, 0.0))
    box = (truth[0, 0] - 20, truth[0, 1] - 20, 40.0, 40.0)
    cv = dataclasses.replace(MFAKCF, motion=MotionModel(rho=1.0, q=0.01))
    errors = {}
    for name, config in (("hold", MFAKCF_HOLD), ("cv", cv), ("mfakcf", MFAKCF)):
        tracker = Tracker(frames[0], box, config)
        ests = [tracker.step(f) for f in frames[1:]]
        centres = np.array([e.centre for e in ests])
        errors[name] = np.linalg.norm(centres - truth[1:], axis=1)
        assert ests[hidden[-1] - 1].lost
    end = hidden[-1] - 1  # index of the last hidden frame in the estimates
    assert errors["hold"][end] > 20.0
    assert errors["cv"][end] < 3.0
    assert errors["cv"][-1] < 1.0
    assert errors["hold"][-1] < 1.0
    assert errors["mfakcf"][-1] < 1.0
