"""The kernel correlation filter and the adaptive update on cases with known answers."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy import ndimage

from oocyte_fe.tracking import kcf
from oocyte_fe.tracking.tracker import MFAKCF, MFAKCF_HOLD, SINGLE_KCF, Tracker


def _kappa(a: np.ndarray, b: np.ndarray, sigma: float) -> float:
    """Gaussian kernel with the per-element normalisation, from the distance itself."""
    return float(np.exp(-np.sum((a - b) ** 2) / (sigma**2 * a.size)))


def test_fourier_solution_equals_direct_ridge_regression() -> None:
    """alpha from eq 17 equals (K + lambda I)^-1 y with K built from explicit cyclic shifts,
    and the response of eq 22 equals sum_j alpha_j kappa(shifted z, x_j)."""
    rng = np.random.default_rng(3)
    h, w, c = 5, 6, 3
    sigma, lam = 0.7, 0.05
    x = rng.normal(size=(h, w, c))
    z = rng.normal(size=(h, w, c))
    y = kcf.gaussian_labels((h, w), 1.2)
    shifts = [(i, j) for i in range(h) for j in range(w)]
    samples = [np.roll(x, (-i, -j), axis=(0, 1)) for i, j in shifts]
    gram = np.array([[_kappa(a, b, sigma) for b in samples] for a in samples])
    alpha_direct = np.linalg.solve(gram + lam * np.eye(len(shifts)), y.ravel())
    alphaf = kcf.train(kcf.fft_features(x), np.fft.fft2(y), sigma, lam)
    alpha_fourier = np.fft.ifft2(alphaf)
    assert np.max(np.abs(alpha_fourier.imag)) < 1e-10
    np.testing.assert_allclose(alpha_fourier.real.ravel(), alpha_direct, rtol=0, atol=1e-8)
    response_direct = np.array(
        [
            sum(
                a * _kappa(np.roll(z, (-i, -j), axis=(0, 1)), s, sigma)
                for a, s in zip(alpha_direct, samples, strict=True)
            )
            for i, j in shifts
        ]
    )
    response = kcf.respond(alphaf, kcf.fft_features(x), kcf.fft_features(z), sigma)
    np.testing.assert_allclose(response.ravel(), response_direct, rtol=0, atol=1e-8)


def _texture(seed: int, shape: tuple[int, int] = (240, 240)) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return 100.0 + 20.0 * ndimage.gaussian_filter(rng.normal(size=shape), 2.0)


@pytest.mark.parametrize(
    "config",
    [MFAKCF_HOLD, SINGLE_KCF, replace(MFAKCF_HOLD, context=0.01, context_offset=1.75)],
    ids=["mfakcf_hold", "kcf", "mfakcf_hold_context"],
)
@pytest.mark.parametrize("shift", [(2.6, -1.3), (-5.2, 3.7), (7.5, 6.25)])
def test_translated_image_found_to_subpixel_accuracy(config, shift) -> None:
    """A band-limited texture moved by a non-integer shift (Fourier shift theorem): the
    tracker's centre moves by the shift within 0.5 px (a quarter of a 4 px cell). MFAKCF
    without its motion model: with it, the centre is the Kalman estimate, which follows a
    single jump only in part (tests/test_tracking_motion.py)."""
    img = _texture(7)
    dx, dy = shift
    moved = ndimage.fourier_shift(np.fft.fft2(img), (dy, dx))
    moved = np.real(np.fft.ifft2(moved))
    box = (100.0, 105.0, 40.0, 32.0)
    tracker = Tracker(img, box, config)
    start = np.array(tracker.centre)
    est = tracker.step(moved)
    err = np.array(est.centre) - start - np.array([dx, dy])
    assert np.linalg.norm(err) < 0.5, err


def test_update_rate_drops_on_occlusion_and_resumes() -> None:
    """A dark disc (a lipid droplet) covers the target for 10 frames: the learning rate is
    the full 0.02 before, falls to 0 (update stopped) while covered, and is back after."""
    img = _texture(11)
    box = (100.0, 100.0, 40.0, 40.0)
    yy, xx = np.mgrid[: img.shape[0], : img.shape[1]]
    disc = (xx - 120.0) ** 2 + (yy - 120.0) ** 2 < 30.0**2
    frames = [img] * 10 + [np.where(disc, 60.0, img)] * 10 + [img] * 10
    tracker = Tracker(img, box, MFAKCF)
    rates = np.array([tracker.step(f).learning_rate for f in frames])
    assert np.all(rates[:10] == pytest.approx(MFAKCF.policy.eta0))
    assert np.all(rates[11:20] == 0.0)
    assert rates[-1] == pytest.approx(MFAKCF.policy.eta0)
    assert np.linalg.norm(np.array(tracker.centre) - 120.0) < 1.0
