"""Small numerical helpers shared by the fits."""

from __future__ import annotations

import numpy as np

BLAS_SINGLE_THREAD_SIZE = 8192
"""Vectors up to this length are left to ``np.dot`` (OpenBLAS threads ddot above 10 000)."""


def dot(a: np.ndarray, b: np.ndarray) -> float:
    """Inner product sum(a_i b_i) of two 1-D arrays, without BLAS.

    ``np.dot`` hands vectors longer than 10 000 to OpenBLAS, which runs them on all its
    threads; on a shared machine those threads spin and one fit of a 16 644-point curve took
    up to 0.5 s of CPU. Shorter vectors go to ``np.dot`` (single-threaded there, and the
    fastest call); longer ones to ``einsum`` without ``optimize``, numpy's own loop.
    """
    if a.size <= BLAS_SINGLE_THREAD_SIZE:
        return float(np.dot(a, b))
    return float(np.einsum("i,i->", a, b))
