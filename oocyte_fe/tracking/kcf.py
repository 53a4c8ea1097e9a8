"""Kernelized correlation filter (Henriques, Caseiro, Martins and Batista 2015, "High-speed
tracking with kernelized correlation filters", IEEE TPAMI 37(3):583-596).

A ridge regression over all cyclic shifts of a feature patch ``x`` (``h x w`` cells, ``c``
channels). With the Gaussian kernel ``kappa(a, b) = exp(-||a - b||^2 / (sigma^2 n))``
(``n = h w c``, the per-element normalisation of the authors' code), the kernel matrix over
the shifts is circulant, so the dual coefficients solve in the Fourier domain (their eq 17)::

    alpha_hat = y_hat / (k_hat^{xx} + lambda)

and the response over all shifts of a test patch ``z`` is (their eq 22)::

    f(z) = F^-1( k_hat^{xz} . alpha_hat )

where the kernel correlation of two patches is (their eq 31)::

    k^{xz} = exp( -(||x||^2 + ||z||^2 - 2 F^-1( sum_c x_hat_c . conj(z_hat_c) )) / (sigma^2 n) )

Index convention (checked against a direct ridge regression in tests/test_tracking_kcf.py):
the training samples are ``x_j = roll(x, -j)`` and ``f(z)[d]`` scores ``roll(z, -d)``, so a
target whose content moved by ``d`` cells inside the window answers at index ``d`` (wrapped).

Labels ``y`` are a Gaussian of standard deviation ``sigma_y`` cells peaked at zero shift; the
feature patches are multiplied by a Hann (cosine) window before the transform. Henriques et
al.'s HOG settings: padding 1.5 (window = 2.5 x target), ``sigma_y = 0.1 sqrt(w h) / cell``,
``sigma = 0.5``, ``lambda = 1e-4``, learning rate 0.02.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft


def cosine_window(shape: tuple[int, int]) -> np.ndarray:
    """Hann window ``w(i, j) = sin^2(pi i / (h - 1)) sin^2(pi j / (w - 1))``, shape (h, w)."""
    return np.outer(np.hanning(shape[0]), np.hanning(shape[1]))


def gaussian_labels(shape: tuple[int, int], sigma: float) -> np.ndarray:
    """Regression target ``y(d) = exp(-|d|^2 / (2 sigma^2))`` over wrapped shifts d (cells)."""
    rows = np.fft.fftfreq(shape[0]) * shape[0]
    cols = np.fft.fftfreq(shape[1]) * shape[1]
    return np.exp(-(rows[:, None] ** 2 + cols[None, :] ** 2) / (2.0 * sigma**2))


def fft_features(x: np.ndarray) -> np.ndarray:
    """2-D DFT of each channel of an ``(h, w, c)`` feature map."""
    return fft.fft2(x, axes=(0, 1))


def fft_feature_maps(maps: list[np.ndarray]) -> list[np.ndarray]:
    """:func:`fft_features` of several ``(h, w, c_k)`` maps on one grid, in one call (each
    channel is transformed alone: the same numbers), each returned as its own array."""
    if len(maps) == 1:
        return [fft_features(maps[0])]
    stacked = fft_features(np.concatenate(maps, axis=2))
    ends = np.cumsum([m.shape[2] for m in maps])
    return [np.ascontiguousarray(f) for f in np.split(stacked, ends[:-1], axis=2)]


def gaussian_correlations(
    xfs: list[np.ndarray], zfs: list[np.ndarray], sigma: float
) -> list[np.ndarray]:
    """DFTs of ``k^{xz}(d) = kappa(roll(x, -d), z)`` (eq 31 above) for each pair of DFTs
    ``(xfs[k], zfs[k])`` on the same ``h x w`` grid (one pair per feature; channels may differ).

    The pairs' inverse and forward 2-D DFTs are taken in one call each: pocketfft transforms
    each slice of a stack alone, so the numbers are those of one call per pair to the last bit,
    at a fraction of the calls' overhead (a tracked frame makes about a dozen of them).
    """
    h, w = xfs[0].shape[:2]
    n_px = h * w
    cross = np.real(
        fft.ifft2(
            np.array([np.sum(xf * np.conj(zf), axis=2) for xf, zf in zip(xfs, zfs, strict=True)])
        )
    )
    kernels = []
    for xf, zf, xz in zip(xfs, zfs, cross, strict=True):
        xx = np.real(np.vdot(xf, xf)) / n_px
        zz = np.real(np.vdot(zf, zf)) / n_px
        dist = np.maximum(0.0, xx + zz - 2.0 * xz) / (n_px * xf.shape[2])
        kernels.append(np.exp(-dist / sigma**2))
    return list(fft.fft2(np.array(kernels)))


def gaussian_correlation(xf: np.ndarray, zf: np.ndarray, sigma: float) -> np.ndarray:
    """DFT of ``k^{xz}(d) = kappa(roll(x, -d), z)`` from the DFTs of x and z (eq 31 above)."""
    return gaussian_correlations([xf], [zf], sigma)[0]


def train(xf: np.ndarray, yf: np.ndarray, sigma: float, lam: float) -> np.ndarray:
    """Dual coefficients ``alpha_hat = y_hat / (k_hat^{xx} + lambda)`` (eq 17 above)."""
    return yf / (gaussian_correlation(xf, xf, sigma) + lam)


def respond(alphaf: np.ndarray, model_xf: np.ndarray, zf: np.ndarray, sigma: float) -> np.ndarray:
    """Response map ``f(z) = F^-1(k_hat^{zx} . alpha_hat)`` over all cyclic shifts (eq 22)."""
    return respond_all([alphaf], [model_xf], [zf], sigma)[0]


def respond_all(
    alphafs: list[np.ndarray], model_xfs: list[np.ndarray], zfs: list[np.ndarray], sigma: float
) -> list[np.ndarray]:
    """:func:`respond` of each filter (one per feature) to its feature's DFT, the DFTs of all
    filters taken together (:func:`gaussian_correlations`)."""
    kernels = gaussian_correlations(zfs, model_xfs, sigma)
    return list(
        np.real(fft.ifft2(np.array([a * k for a, k in zip(alphafs, kernels, strict=True)])))
    )


def subpixel_peak(response: np.ndarray) -> tuple[float, float, float]:
    """Wrapped shift (rows, cols) of the response maximum refined on each axis.

    With ``r_-, r_0, r_+`` the values beside the peak and ``g = log r`` (the response is close
    to the Gaussian label, whose logarithm is a parabola), the offset is
    ``(g_- - g_+) / (2 (g_- - 2 g_0 + g_+))`` cells; where a neighbour is not positive the
    parabola is fitted to ``r`` itself. Returns (dy, dx, peak value).
    """
    h, w = response.shape
    i, j = np.unravel_index(int(np.argmax(response)), response.shape)
    r0 = response[i, j]

    def refine(rm: float, rp: float) -> float:
        g0 = r0
        if rm > 0 and rp > 0 and r0 > 0:
            rm, g0, rp = np.log(rm), np.log(r0), np.log(rp)
        den = rm - 2.0 * g0 + rp
        return float(0.5 * (rm - rp) / den) if den < 0 else 0.0

    dy = i + refine(response[(i - 1) % h, j], response[(i + 1) % h, j])
    dx = j + refine(response[i, (j - 1) % w], response[i, (j + 1) % w])
    dy = dy - h if dy > h / 2 else dy
    dx = dx - w if dx > w / 2 else dx
    return dy, dx, float(r0)


@dataclass
class KcfModel:
    """One feature's filter: the model patch DFT ``x_hat`` and its ``alpha_hat``.

    The template update is the linear interpolation of Henriques et al. (their Section 6)::

        x_hat <- (1 - eta) x_hat + eta x_hat_new,  alpha_hat <- (1 - eta) alpha_hat + eta alpha_new
    """

    xf: np.ndarray
    alphaf: np.ndarray
    sigma: float
    lam: float

    @classmethod
    def fit(cls, xf: np.ndarray, yf: np.ndarray, sigma: float, lam: float) -> KcfModel:
        return cls(xf, train(xf, yf, sigma, lam), sigma, lam)

    def respond(self, zf: np.ndarray) -> np.ndarray:
        return respond(self.alphaf, self.xf, zf, self.sigma)

    def update(self, xf: np.ndarray, yf: np.ndarray, eta: float) -> None:
        update_models([self], [xf], yf, eta)


def _shared_sigma(models: list[KcfModel]) -> float:
    sigma = models[0].sigma
    if any(m.sigma != sigma for m in models):
        raise ValueError("filters answered together must share one kernel width sigma")
    return sigma


def respond_models(models: list[KcfModel], zfs: list[np.ndarray]) -> list[np.ndarray]:
    """``[m.respond(zf) for m, zf in zip(models, zfs)]`` with the DFTs of all filters taken
    together (:func:`respond_all`; the same numbers)."""
    return respond_all(
        [m.alphaf for m in models], [m.xf for m in models], zfs, _shared_sigma(models)
    )


def update_models(
    models: list[KcfModel], xfs: list[np.ndarray], yf: np.ndarray, eta: float
) -> None:
    """``m.update(xf, yf, eta)`` for each filter and its feature's DFT, the training DFTs of
    all filters taken together (:func:`gaussian_correlations`; the same numbers)."""
    if eta <= 0.0:
        return
    kernels = gaussian_correlations(xfs, xfs, _shared_sigma(models))
    for model, xf, k in zip(models, xfs, kernels, strict=True):
        alphaf = yf / (k + model.lam)
        model.xf = (1.0 - eta) * model.xf + eta * xf
        model.alphaf = (1.0 - eta) * model.alphaf + eta * alphaf
