"""Resampling a measured force curve within a stated relative scatter.

Each measured force is multiplied by an independent normal factor,

    F*_i = max(0, F_i (1 + s z_i)),   z_i ~ N(0, 1) drawn from ``numpy.random.default_rng(seed)``

with ``s`` the stated relative standard deviation (dimensionless); the displacements are
kept. ``seed`` names the realisation, so a sweep over seeds is a set of resampled curves
and every one of them can be rebuilt from its seed alone.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np


def resample_relative(force: np.ndarray, noise_rel: float, seed: int) -> np.ndarray:
    """``force`` with multiplicative normal noise of relative SD ``noise_rel``, floored at 0."""
    if noise_rel < 0:
        raise ValueError(f"noise_rel must be >= 0, got {noise_rel}")
    z = np.random.default_rng(seed).standard_normal(len(force))
    return np.maximum(0.0, np.asarray(force, dtype=float) * (1.0 + noise_rel * z))


def relative_scatter(measured: np.ndarray, model: np.ndarray, floor: float) -> float:
    """RMS of ``(measured - model) / model`` over the points where ``model >= floor``."""
    keep = np.asarray(model) >= floor
    r = (np.asarray(measured)[keep] - np.asarray(model)[keep]) / np.asarray(model)[keep]
    return float(np.sqrt(np.mean(r**2)))


def write_force_csv(
    path: Path, displacement_um: np.ndarray, columns: dict[str, np.ndarray]
) -> Path:
    """A force-displacement CSV: ``displacement_um`` then each named column (units in names)."""
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["displacement_um", *columns])
        for i, d in enumerate(displacement_um):
            writer.writerow([repr(float(d)), *(repr(float(c[i])) for c in columns.values())])
    return path
