"""Aggregating a metric over the samples: moments, percentiles, global sensitivity indices.

Summary over the ``n`` finite values ``y_i`` of the finished samples: mean, sample standard
deviation ``sqrt(sum (y_i - mean)^2 / (n - 1))`` and the 5/50/95 % percentiles (linear
interpolation, ``numpy.percentile``). Sensitivity indices come from SALib on the unit-cube
coordinates of the design (both methods are invariant under the monotone maps to values):

- ``rbd_fast``: first-order index ``S1_j = Var(E[y | x_j]) / Var(y)`` by random-balance
  designs FAST (Tarantola et al. 2006, bias-corrected; Plischke 2010), with a bootstrap 95 %
  interval, from ``M = clip(n // 16, 2, 10)`` harmonics (SALib's default 10 from 160
  samples on; fewer harmonics for small sweeps, where 10 leave too few points per
  harmonic); at least 16 samples.
- ``pawn``: the moment-independent PAWN index (median Kolmogorov-Smirnov distance between the
  unconditional and conditional output distributions, Pianosi & Wagener 2015). SALib gives
  no interval for it: here the ``n`` samples are resampled with replacement ``B = 200`` times
  (seeded), the index recomputed on each, and the half-width is ``1.96 SD`` of those ``B``
  values, the normal-approximation interval SALib uses for ``S1_conf``.

Every interval is ``index +- conf`` (95 %); an index whose interval reaches zero
(``index - conf <= 0``) is not resolved from zero at this sample size and is flagged.
Below ``RECOMMENDED[method]`` finished samples the report warns that the indices are
indicative only: for RBD-FAST the rule of SALib's FAST sampler, ``N > 4 M^2`` with its default
``M = 4`` (``SALib.sample.fast_sampler``), i.e. 65; for PAWN SALib's default ``S = 10``
slides with at least 10 samples in each, i.e. 100 (SALib states no number for PAWN).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

MIN_SAMPLES = {"rbd_fast": 16, "pawn": 20}
RECOMMENDED = {"rbd_fast": 65, "pawn": 100}
BOOTSTRAP = 200
Z95 = 1.959963984540054  # standard normal 97.5 % quantile


def harmonics(n: int) -> int:
    """Harmonics ``M`` of the RBD-FAST estimate for ``n`` samples."""
    return int(np.clip(n // 16, 2, 10))


@dataclass(frozen=True)
class Summary:
    """Statistics of one metric over the finished samples (``n`` finite values)."""

    n: int
    mean: float
    sd: float
    p05: float
    p50: float
    p95: float

    def as_dict(self) -> dict[str, float]:
        return {"mean": self.mean, "sd": self.sd, "p05": self.p05, "p50": self.p50, "p95": self.p95}


def summarize(values: np.ndarray) -> Summary:
    """Mean, SD (ddof 1), 5/50/95 % percentiles of the finite values; NaN when none."""
    y = np.asarray(values, dtype=float)
    y = y[np.isfinite(y)]
    if len(y) == 0:
        return Summary(0, *(5 * [np.nan]))
    p05, p50, p95 = np.percentile(y, [5, 50, 95])
    sd = float(np.std(y, ddof=1)) if len(y) > 1 else np.nan
    return Summary(len(y), float(np.mean(y)), sd, float(p05), float(p50), float(p95))


@dataclass(frozen=True)
class Sensitivity:
    """Indices of one metric per parameter, with a 95 % interval half-width (NaN if none),
    on ``n`` finished samples."""

    method: str
    index: dict[str, float]
    conf: dict[str, float]
    n: int = 0

    def spans_zero(self, name: str) -> bool:
        """True when the 95 % interval of ``name``'s index reaches zero (or is unknown)."""
        conf = self.conf[name]
        return not math.isfinite(conf) or self.index[name] - conf <= 0.0

    @property
    def too_few(self) -> bool:
        """Fewer finished samples than ``RECOMMENDED`` for the method."""
        return self.n < RECOMMENDED[self.method]


def _pawn(problem: dict, x: np.ndarray, y: np.ndarray, seed: int) -> np.ndarray:
    from SALib.analyze import pawn

    return np.asarray(pawn.analyze(problem, x, y, S=min(10, len(y) // 10), seed=seed)["median"])


def bootstrap_conf(
    index: Callable[[np.ndarray, np.ndarray], np.ndarray],
    x: np.ndarray,
    y: np.ndarray,
    seed: int,
    resamples: int = BOOTSTRAP,
) -> np.ndarray:
    """95 % half-width ``1.96 SD`` of ``index(x*, y*)`` over ``resamples`` bootstrap
    resamples (rows drawn with replacement, ``numpy.random.default_rng(seed)``)."""
    rng = np.random.default_rng(seed)
    draws = []
    for _ in range(resamples):
        rows = rng.integers(0, len(y), len(y))
        if np.ptp(y[rows]) > 0:
            draws.append(index(x[rows], y[rows]))
    return Z95 * np.std(np.array(draws), axis=0, ddof=1)


def sensitivity(
    unit: np.ndarray, y: np.ndarray, names: list[str], method: str, seed: int = 0
) -> Sensitivity | None:
    """SALib indices of ``y`` over the unit-cube design ``unit`` (n, d), or ``None``.

    ``None`` when ``method`` is ``"none"``, when fewer than ``MIN_SAMPLES[method]`` finite
    values exist, or when ``y`` is constant (no variance to share out).
    """
    if method == "none":
        return None
    y = np.asarray(y, dtype=float)
    keep = np.isfinite(y)
    x, y = unit[keep], y[keep]
    if len(y) < MIN_SAMPLES[method] or np.ptp(y) == 0:
        return None
    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if method == "rbd_fast":
            from SALib.analyze import rbd_fast

            res = rbd_fast.analyze(problem, x, y, M=harmonics(len(y)), seed=seed)
            index, conf = res["S1"], res["S1_conf"]
        else:
            index = _pawn(problem, x, y, seed)
            conf = bootstrap_conf(lambda xs, ys: _pawn(problem, xs, ys, seed), x, y, seed)
    return Sensitivity(
        method,
        {n: float(v) for n, v in zip(names, index, strict=True)},
        {n: float(v) for n, v in zip(names, conf, strict=True)},
        len(y),
    )
