"""Sparse assembly on a fixed pattern (oocyte_fe.fe.pattern) against scipy's conversion."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from oocyte_fe.fe.pattern import SparsityPattern


def _triplets(seed: int, n: int = 40, m: int = 900):
    rng = np.random.default_rng(seed)
    return rng.integers(0, n, m), rng.integers(0, n, m), rng.standard_normal(m)


def test_the_pattern_matrix_equals_scipys_and_is_canonical():
    rows, cols, vals = _triplets(0)  # many duplicates: 900 triplets in a 40 x 40 matrix
    pattern = SparsityPattern((40, 40))
    expected = sp.csc_matrix((vals, (rows, cols)), shape=(40, 40)).toarray()
    for scale in (1.0, -2.5):  # the second call reuses the pattern with new values
        A = pattern.csc(rows, cols, scale * vals)
        np.testing.assert_allclose(A.toarray(), scale * expected, rtol=0, atol=1e-13)
        assert A.has_canonical_format
        assert np.all(np.diff(A.indices[A.indptr[0] : A.indptr[1]]) > 0)


def test_new_triplets_rebuild_and_a_pruned_matrix_leaves_the_pattern_intact():
    pattern = SparsityPattern((40, 40))
    rows, cols, vals = _triplets(1)
    A = pattern.csc(rows, cols, vals)
    A.data[:] = 0.0
    A.eliminate_zeros()  # in place on the matrix's arrays, not the pattern's
    again = pattern.csc(rows, cols, vals)
    dense = sp.csc_matrix((vals, (rows, cols)), shape=(40, 40)).toarray()
    np.testing.assert_allclose(again.toarray(), dense, atol=1e-13)
    rows2, cols2, vals2 = _triplets(2)
    other = pattern.csc(rows2, cols2, vals2)
    dense2 = sp.csc_matrix((vals2, (rows2, cols2)), shape=(40, 40)).toarray()
    np.testing.assert_allclose(other.toarray(), dense2, atol=1e-13)
