"""The tracker's fast paths give the library's numbers to the last bit: the window median and
smoothing (:mod:`oocyte_fe.tracking.window_stats`) against ``np.median`` and
``ndimage.gaussian_filter``, and the filters answered together (:func:`kcf.respond_models`,
:func:`kcf.update_models`, :func:`kcf.fft_feature_maps`) against one filter at a time by the
equations of :mod:`oocyte_fe.tracking.kcf` written out here."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy import fft, ndimage

from oocyte_fe.tracking import kcf
from oocyte_fe.tracking.window_stats import median, smooth

values = hnp.arrays(
    np.float64,
    hnp.array_shapes(min_dims=1, max_dims=2, min_side=1, max_side=60),
    elements=st.floats(-1e6, 1e6, allow_nan=False) | st.sampled_from([np.nan, 0.0, -0.0, 1.0]),
)


@settings(max_examples=300, deadline=None)
@given(values)
def test_median_is_numpys_to_the_last_bit(a: np.ndarray) -> None:
    want = np.median(a)
    got = median(a)
    assert (np.isnan(want) and np.isnan(got)) or got == want, (got, want)


@pytest.mark.parametrize("sigma", [0.5, 1.0, 1.3, 2.0])
@pytest.mark.parametrize("shape", [(1, 1), (3, 17), (40, 30), (96, 96)])
def test_smooth_is_gaussian_filter_to_the_last_bit(sigma: float, shape: tuple[int, int]) -> None:
    image = 1000.0 + 50.0 * np.random.default_rng(3).standard_normal(shape)
    np.testing.assert_array_equal(smooth(image, sigma), ndimage.gaussian_filter(image, sigma))


def _correlation(xf: np.ndarray, zf: np.ndarray, sigma: float) -> np.ndarray:
    """Eq. 31 of the kcf module for one pair, as written there."""
    h, w, c = xf.shape
    xx = np.real(np.vdot(xf, xf)) / (h * w)
    zz = np.real(np.vdot(zf, zf)) / (h * w)
    xz = np.real(fft.ifft2(np.sum(xf * np.conj(zf), axis=2)))
    return fft.fft2(np.exp(-np.maximum(0.0, xx + zz - 2.0 * xz) / (h * w * c) / sigma**2))


@pytest.mark.parametrize("grid", [(24, 24), (18, 27), (26, 20)])
def test_filters_answered_together_equal_one_at_a_time(grid: tuple[int, int]) -> None:
    """Two features (9 and 8 channels) on one grid: the stacked DFTs, responses and updates
    equal the one-pair equations exactly (pocketfft transforms each slice alone)."""
    rng = np.random.default_rng(11)
    maps = [rng.random(grid + (9,)), rng.random(grid + (8,))]
    new = [rng.random(grid + (9,)), rng.random(grid + (8,))]
    xfs = kcf.fft_feature_maps(maps)
    for got, m in zip(xfs, maps, strict=True):
        np.testing.assert_array_equal(got, fft.fft2(m, axes=(0, 1)))
    zfs = [fft.fft2(m, axes=(0, 1)) for m in new]
    yf = fft.fft2(kcf.gaussian_labels(grid, 2.0))
    sigma, lam, eta = 0.5, 1e-4, 0.02
    alphas = [yf / (_correlation(xf, xf, sigma) + lam) for xf in xfs]
    models = [kcf.KcfModel.fit(xf, yf, sigma, lam) for xf in xfs]
    for model, alpha in zip(models, alphas, strict=True):
        np.testing.assert_array_equal(model.alphaf, alpha)
    for got, xf, zf, alpha in zip(kcf.respond_models(models, zfs), xfs, zfs, alphas, strict=True):
        np.testing.assert_array_equal(got, np.real(fft.ifft2(alpha * _correlation(zf, xf, sigma))))
    kcf.update_models(models, zfs, yf, eta)
    for model, xf, zf, alpha in zip(models, xfs, zfs, alphas, strict=True):
        np.testing.assert_array_equal(model.xf, (1 - eta) * xf + eta * zf)
        alpha_new = yf / (_correlation(zf, zf, sigma) + lam)
        np.testing.assert_array_equal(model.alphaf, (1 - eta) * alpha + eta * alpha_new)
    models[1].sigma = 0.6
    with pytest.raises(ValueError, match="share one kernel width"):
        kcf.respond_models(models, zfs)
