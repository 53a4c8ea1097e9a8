"""Cell-wise feature maps of an image patch: HOG and a grayscale-histogram channel.

Both maps have shape ``(rows // cell, cols // cell, channels)`` so that the correlation filters
of the two features answer on the same grid and their responses can be fused (seed 000,
Algorithm 1, line 5).

HOG (Dalal and Triggs 2005, cell-wise as in KCF, Henriques et al. 2015, Section 6.1): the
gradient ``g = (d I/dx, d I/dy)`` by central differences, magnitude ``|g|`` and unsigned
orientation ``theta = atan2(gy, gx) mod pi`` voted into ``n_orient`` bins with linear
interpolation between the two nearest bin centres; votes are summed over each
``cell x cell`` block; each cell histogram ``h`` is divided by the root of the gradient energy
of its 3 x 3 cell neighbourhood, ``h / sqrt(mean_{3x3} |h|^2 + eps)``, and truncated at 0.2.
Dividing by the local energy makes the map invariant to a global gain (illumination drift).

Grayscale histogram: the patch is taken relative to its own median, ``u = (I / median I - 1) /
s`` (median over every other pixel) with ``s`` = 4 % (invariant to a global gain of the
illumination, and the median is barely moved by a spindle or a droplet covering less than half
the window), and each pixel votes with triangular weights into ``n_bins`` intensity bins spread
evenly over ``u in [-u_max, u_max]`` (+-10 % of the median for the defaults); pixels outside
that band do not vote. The map is the fraction of each cell's pixels in each bin. The
birefringent spindle, a few % brighter than the cytoplasm, fills the upper bins; a dark lipid
droplet, the pipette's glass or the bright zona fall outside the band and leave their cells
empty, so they neither dominate the template (a first version clipped them into the end bins,
and the tracker then stayed with a static droplet beside a faint spindle) nor look like the
spindle, and an occluder empties the spindle's cells (the response falls).
"""

from __future__ import annotations

import functools

import numpy as np

from oocyte_fe.tracking.window_stats import median

HOG_CLIP = 0.2
"""Dalal-Triggs truncation of the normalised histogram."""


def _crop(patch: np.ndarray, cell: int) -> np.ndarray:
    h, w = patch.shape
    if h < cell or w < cell:
        raise ValueError(f"patch {patch.shape} is smaller than one {cell} x {cell} cell")
    return patch[: h - h % cell, : w - w % cell]


@functools.lru_cache(maxsize=64)
def _cell_index(shape: tuple[int, int], cell: int, n_bins: int) -> np.ndarray:
    """Per pixel, the flat index of its cell's first bin in a ``(H // cell, W // cell,
    n_bins)`` histogram (the image is cropped to whole cells); cached and read-only."""
    h, w = shape
    rows = np.arange(h)[:, None] // cell
    cols = np.arange(w)[None, :] // cell
    index = (rows * (w // cell) + cols) * n_bins
    index.flags.writeable = False
    return index


@functools.lru_cache(maxsize=64)
def _edge_padded(n: int) -> np.ndarray:
    """Indices ``0, 0, 1, ..., n - 1, n - 1``: an axis of n cells padded by its edge cells."""
    index = np.clip(np.arange(-1, n + 1), 0, n - 1)
    index.flags.writeable = False
    return index


def orientation_votes(img: np.ndarray, cell: int, n_orient: int) -> np.ndarray:
    """Orientation votes summed per cell (central differences, zero on the border; linear
    interpolation between the two nearest bins)."""
    h, w = img.shape
    gx = np.zeros_like(img)
    gy = np.zeros_like(img)
    gx[:, 1:-1] = 0.5 * (img[:, 2:] - img[:, :-2])
    gy[1:-1, :] = 0.5 * (img[2:, :] - img[:-2, :])
    mag = np.sqrt(gx * gx + gy * gy)  # hypot's overflow guard is 7x slower; |g| < 1e154 here
    theta = np.arctan2(gy, gx)
    theta += np.pi * (theta < 0.0)  # unsigned orientation in [0, pi]
    pos = theta * (n_orient / np.pi) - 0.5  # in [-0.5, n_orient - 0.5]
    lo = np.floor(pos)
    frac = pos - lo
    lo_bin = lo.astype(np.intp)  # -1 ... n_orient - 1: wrap the two ends
    hi_bin = lo_bin + 1
    lo_bin[lo_bin < 0] = n_orient - 1
    hi_bin[hi_bin >= n_orient] = 0
    base = _cell_index(img.shape, cell, n_orient)
    n = (h // cell) * (w // cell) * n_orient
    hist = np.bincount((base + lo_bin).ravel(), (mag * (1.0 - frac)).ravel(), n)
    hist += np.bincount((base + hi_bin).ravel(), (mag * frac).ravel(), n)
    return hist.reshape(h // cell, w // cell, n_orient)


def hog_cells(patch: np.ndarray, cell: int = 4, n_orient: int = 9) -> np.ndarray:
    """HOG map of a 2-D patch, shape ``(H // cell, W // cell, n_orient)`` (see module doc)."""
    img = _crop(np.asarray(patch, dtype=np.float64), cell)
    hist = orientation_votes(img, cell, n_orient)
    energy = np.sum(hist * hist, axis=2)
    hc, wc = energy.shape
    padded = energy[_edge_padded(hc)][:, _edge_padded(wc)]  # np.pad(energy, 1, mode="edge")
    nbhd = sum(padded[i : i + hc, j : j + wc] for i in range(3) for j in range(3))
    scale = np.sqrt(nbhd / 9.0 + 1e-12)
    return np.minimum(hist / scale[..., None], HOG_CLIP)


def _gray_votes(u: np.ndarray, cell: int, n_bins: int, u_max: float) -> np.ndarray:
    """Triangular votes of standardised intensities into n_bins, summed per cell; pixels
    outside ``[-u_max, u_max]`` do not vote."""
    h, w = u.shape
    keep = (u >= -u_max) & (u <= u_max)
    pos = (u[keep] + u_max) * ((n_bins - 1) / (2.0 * u_max))
    lo = np.minimum(np.floor(pos).astype(np.int64), n_bins - 2)
    frac = pos - lo
    base = _cell_index(u.shape, cell, n_bins)[keep] + lo
    n = (h // cell) * (w // cell) * n_bins
    hist = np.bincount(base, 1.0 - frac, n) + np.bincount(base + 1, frac, n)
    return hist.reshape(h // cell, w // cell, n_bins)


def gray_histogram_cells(
    patch: np.ndarray, cell: int = 4, n_bins: int = 8, spread: float = 0.04, u_max: float = 2.5
) -> np.ndarray:
    """Grayscale-histogram map, shape ``(H // cell, W // cell, n_bins)`` (see module doc)."""
    img = _crop(np.asarray(patch, dtype=np.float64), cell)
    level = median(img[::2, ::2])
    u = (img / (level if level > 0 else 1.0) - 1.0) / spread
    return _gray_votes(u, cell, n_bins, u_max) / (cell * cell)


FEATURES = {"hog": hog_cells, "gray": gray_histogram_cells}
"""Feature extractors by name: ``f(patch, cell) -> (H // cell, W // cell, C)``."""
