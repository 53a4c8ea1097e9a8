"""Context-aware kernel correlation filter (Mueller, Smith and Ghanem 2017, "Context-aware
correlation filter tracking", CVPR, Section 3; the kernel case in its dual form).

The plain filter of :mod:`.kcf` regresses the cyclic shifts of the target window ``x_0`` to a
Gaussian label ``y``; structure that sits in the window next to the target (a droplet, the
zona's edge, the pipette's wall) is part of every training sample, so the filter may learn it
as much as the target. The context-aware filter adds ``k`` context windows ``x_1..x_k`` cut
around the target (here at one target size up, down, left and right) whose cyclic shifts are
regressed to zero, so what also appears around the target is learned as background.

Ridge regression in the kernel's feature space ``phi`` over the rows ``phi(P^j x_0)`` (label
``y_j``) and ``sqrt(lambda_2) phi(P^j x_i)`` (label 0), ``P^j x = roll(x, -j)``::

    min_w  sum_j (w . phi(P^j x_0) - y_j)^2 + lambda_2 sum_i sum_j (w . phi(P^j x_i))^2
           + lambda_1 ||w||^2

With ``B`` the matrix of those rows, ``w = B^T alpha`` and ``(B B^T + lambda_1 I) alpha =
y_bar`` (``y_bar = [y; 0; ...; 0]``). For a shift-invariant kernel the block ``(a, b)`` of
``B B^T`` is ``c_a c_b kappa(P^j x_a, P^l x_b) = c_a c_b k^{ab}(j - l)`` with ``c_0 = 1``,
``c_i = sqrt(lambda_2)`` and ``k^{ab}(d) = kappa(roll(x_a, -d), x_b)`` (the kernel
correlation of :func:`.kcf.gaussian_correlation`): each block is circulant, so the DFT
decouples the system into one ``(k+1) x (k+1)`` Hermitian system per frequency ``omega``::

    sum_b ( c_a c_b k_hat^{ab}(omega) + lambda_1 delta_ab ) alpha_hat_b(omega) = y_bar_hat_a(omega)

(``k_hat^{ba} = conj(k_hat^{ab})``). Without context (``k = 0``) it is KCF's
``alpha_hat = y_hat / (k_hat^{xx} + lambda)``. The response over the shifts of a test window
``z`` is ``f(z)[d] = w . phi(P^d z)``::

    f(z) = F^-1( sum_a c_a k_hat^{z x_a} . alpha_hat_a )

so a detection costs ``k + 1`` kernel correlations (computed in one batch). The template update
interpolates every ``x_hat_a`` and ``alpha_hat_a`` with the same rate (the linear interpolation
of :class:`.kcf.KcfModel`). ``tests/test_tracking_context.py`` checks ``alpha`` and ``f(z)``
against the direct ridge regression with explicit shift rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft

CONTEXT_OFFSETS = ((0.0, -1.0), (0.0, 1.0), (-1.0, 0.0), (1.0, 0.0))
"""Context window centres in target sizes (dx / w_t, dy / h_t): up, down, left, right
(Mueller et al. 2017 sample the target size away on each side)."""


def kernel_correlations(xfs: np.ndarray, zfs: np.ndarray, sigma: float) -> np.ndarray:
    """DFTs of ``k^{x_a z_b}(d) = kappa(roll(x_a, -d), z_b)`` for all pairs, shape
    ``(A, B, h, w)``, from stacked feature DFTs ``(A, h, w, c)`` and ``(B, h, w, c)``
    (Gaussian kernel of :func:`.kcf.gaussian_correlation`, in one batch)."""
    n_a, h, w, c = xfs.shape
    n_px = h * w
    xx = np.sum(np.abs(xfs) ** 2, axis=(1, 2, 3)) / n_px
    zz = np.sum(np.abs(zfs) ** 2, axis=(1, 2, 3)) / n_px
    # sum_c x_hat_a,c conj(z_hat_b,c) per frequency, as one batched (A x c) @ (c x B) product
    products = xfs.reshape(n_a, n_px, c).transpose(1, 0, 2) @ np.conj(
        zfs.reshape(zfs.shape[0], n_px, c).transpose(1, 2, 0)
    )
    cross = fft.ifft2(products.transpose(1, 2, 0).reshape(n_a, -1, h, w), axes=(2, 3)).real
    dist = np.maximum(0.0, xx[:, None, None, None] + zz[None, :, None, None] - 2.0 * cross)
    return fft.fft2(np.exp(-dist / (n_px * c * sigma**2)), axes=(2, 3))


def context_weights(n_context: int, lam2: float) -> np.ndarray:
    """Row scales ``c = (1, sqrt(lambda_2), ...)`` of the target and the context windows."""
    return np.concatenate([[1.0], np.full(n_context, np.sqrt(lam2))])


def train(xfs: np.ndarray, yf: np.ndarray, sigma: float, lam: float, lam2: float) -> np.ndarray:
    """Dual coefficients ``alpha_hat_a`` (shape ``(k+1, h, w)``) of the per-frequency system
    of the module doc; ``xfs[0]`` is the target window, ``xfs[1:]`` the context windows."""
    n = xfs.shape[0]
    c = context_weights(n - 1, lam2)
    gram = kernel_correlations(xfs, xfs, sigma) * (c[:, None] * c[None, :])[..., None, None]
    system = np.moveaxis(gram, (0, 1), (2, 3)) + lam * np.eye(n)
    rhs = np.zeros(yf.shape + (n, 1), dtype=complex)
    rhs[..., 0, 0] = yf
    return np.moveaxis(np.linalg.solve(system, rhs)[..., 0], 2, 0)


def respond(
    alphafs: np.ndarray, model_xfs: np.ndarray, zf: np.ndarray, sigma: float, lam2: float
) -> np.ndarray:
    """``f(z) = F^-1( sum_a c_a k_hat^{z x_a} . alpha_hat_a )`` over all cyclic shifts."""
    c = context_weights(model_xfs.shape[0] - 1, lam2)
    kzx = kernel_correlations(zf[None], model_xfs, sigma)[0]
    return fft.ifft2(np.einsum("a,ahw->hw", c, kzx * alphafs)).real


@dataclass
class ContextKcfModel:
    """One feature's context-aware filter: the window DFTs ``x_hat_a`` (target first, then
    the context windows) and their ``alpha_hat_a``; same interface as :class:`.kcf.KcfModel`
    but trained on the stacked windows ``(k+1, h, w, c)``."""

    xfs: np.ndarray
    alphafs: np.ndarray
    sigma: float
    lam: float
    lam2: float

    @classmethod
    def fit(
        cls, xfs: np.ndarray, yf: np.ndarray, sigma: float, lam: float, lam2: float
    ) -> ContextKcfModel:
        return cls(xfs, train(xfs, yf, sigma, lam, lam2), sigma, lam, lam2)

    def respond(self, zf: np.ndarray) -> np.ndarray:
        return respond(self.alphafs, self.xfs, zf, self.sigma, self.lam2)

    def update(self, xfs: np.ndarray, yf: np.ndarray, eta: float) -> None:
        """``x_hat_a <- (1 - eta) x_hat_a + eta x_hat_a,new``, the same for ``alpha_hat_a``."""
        if eta <= 0.0:
            return
        alphafs = train(xfs, yf, self.sigma, self.lam, self.lam2)
        self.xfs = (1.0 - eta) * self.xfs + eta * xfs
        self.alphafs = (1.0 - eta) * self.alphafs + eta * alphafs
