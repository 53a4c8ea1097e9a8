"""The context-aware kernel correlation filter against a direct ridge regression."""

from __future__ import annotations

import numpy as np
import pytest

from oocyte_fe.tracking import context, kcf
from oocyte_fe.tracking.tracker import TrackerConfig


def _kappa(a: np.ndarray, b: np.ndarray, sigma: float) -> float:
    return float(np.exp(-np.sum((a - b) ** 2) / (sigma**2 * a.size)))


def test_dual_solution_equals_direct_ridge_regression_with_context_rows() -> None:
    """alpha from the per-frequency systems equals (B B^T + lambda_1 I)^-1 [y; 0; 0] with the
    kernel matrix of all cyclic shifts of the target window and of two context windows (rows
    scaled by sqrt(lambda_2)), and the response equals sum_r alpha_r kappa(row_r, shifted z)."""
    rng = np.random.default_rng(5)
    h, w, c = 4, 5, 2
    sigma, lam, lam2 = 0.8, 0.05, 0.7
    windows = rng.normal(size=(3, h, w, c))
    z = rng.normal(size=(h, w, c))
    y = kcf.gaussian_labels((h, w), 1.1)
    shifts = [(i, j) for i in range(h) for j in range(w)]
    rows = [(a, np.roll(windows[a], (-i, -j), axis=(0, 1))) for a in range(3) for i, j in shifts]
    scale = {0: 1.0, 1: np.sqrt(lam2), 2: np.sqrt(lam2)}
    gram = np.array([[scale[a] * scale[b] * _kappa(u, v, sigma) for b, v in rows] for a, u in rows])
    target = np.concatenate([y.ravel(), np.zeros(2 * h * w)])
    alpha_direct = np.linalg.solve(gram + lam * np.eye(len(rows)), target)
    xfs = np.array([kcf.fft_features(x) for x in windows])
    alphafs = context.train(xfs, np.fft.fft2(y), sigma, lam, lam2)
    alpha = np.fft.ifft2(alphafs, axes=(1, 2))
    assert np.max(np.abs(alpha.imag)) < 1e-10
    np.testing.assert_allclose(alpha.real.ravel(), alpha_direct, rtol=0, atol=1e-8)
    response_direct = np.array(
        [
            sum(
                coef * scale[a] * _kappa(np.roll(z, (-i, -j), axis=(0, 1)), u, sigma)
                for coef, (a, u) in zip(alpha_direct, rows, strict=True)
            )
            for i, j in shifts
        ]
    )
    response = context.respond(alphafs, xfs, kcf.fft_features(z), sigma, lam2)
    np.testing.assert_allclose(response.ravel(), response_direct, rtol=0, atol=1e-8)


def test_without_context_it_is_kcf() -> None:
    """k = 0 context windows (or lambda_2 = 0) gives KCF's alpha_hat = y_hat / (k_hat + lambda)."""
    rng = np.random.default_rng(6)
    x = rng.normal(size=(6, 7, 3))
    yf = np.fft.fft2(kcf.gaussian_labels((6, 7), 1.3))
    xf = kcf.fft_features(x)
    expected = kcf.train(xf, yf, 0.6, 1e-3)
    np.testing.assert_allclose(context.train(xf[None], yf, 0.6, 1e-3, 0.5)[0], expected, atol=1e-10)
    others = np.array([xf, kcf.fft_features(rng.normal(size=x.shape))])
    np.testing.assert_allclose(context.train(others, yf, 0.6, 1e-3, 0.0)[0], expected, atol=1e-10)


def test_context_suppresses_what_surrounds_the_target() -> None:
    """A window holding a target blob and a distractor blob; the distractor (alone) also fills
    a context window. The plain filter answers the distractor-only window at the distractor's
    shift; the context-aware filter's answer there is far smaller, while both still answer
    the training window at zero shift with nearly the label's peak."""
    h = w = 16
    yy, xx = np.mgrid[:h, :w]

    def blob(cy: float, cx: float) -> np.ndarray:
        return np.exp(-((yy - cy) ** 2 + (xx - cx) ** 2) / 4.0)

    target, distractor = blob(8, 8), blob(8, 13)
    window = np.stack([target, 0.5 * target + distractor], axis=2)
    ctx = np.stack([np.zeros_like(target), distractor], axis=2)
    probe = np.stack([np.zeros_like(target), blob(8, 8)], axis=2)  # distractor at the centre
    yf = np.fft.fft2(kcf.gaussian_labels((h, w), 1.0))
    xfs = np.array([kcf.fft_features(window), kcf.fft_features(ctx)])
    sigma, lam = 0.2, 1e-3
    plain = kcf.respond(kcf.train(xfs[0], yf, sigma, lam), xfs[0], kcf.fft_features(probe), sigma)
    aware = context.ContextKcfModel.fit(xfs, yf, sigma, lam, lam2=1.0)
    on_probe = aware.respond(kcf.fft_features(probe))
    assert aware.respond(xfs[0])[0, 0] > 0.9
    assert on_probe.max() < 0.1 * plain.max(), (on_probe.max(), plain.max())


def test_tracker_refuses_bad_context_settings() -> None:
    with pytest.raises(ValueError, match="context"):
        TrackerConfig(context=-0.1)
    with pytest.raises(ValueError, match="context_offset"):
        TrackerConfig(context=0.1, context_offset=0.0)
