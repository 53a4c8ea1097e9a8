"""LAPACK band storage back to a dense matrix, for tests of the compiled tangents."""

from __future__ import annotations

import numpy as np


def band_to_dense(ab: np.ndarray, band: int) -> np.ndarray:
    """Dense (n, n) matrix of a ``gbtrf`` band array ``ab[2 b + i - j, j] = K[i, j]``."""
    n = ab.shape[1]
    dense = np.zeros((n, n))
    for j in range(n):
        for i in range(max(0, j - band), min(n, j + band + 1)):
            dense[i, j] = ab[2 * band + i - j, j]
    return dense
