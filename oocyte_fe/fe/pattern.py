"""Sparse assembly on a fixed pattern: COO triplets to a canonical CSC matrix by one scatter.

A Newton iteration assembles the tangent from the same element and facet triplets every time
(the mesh, the regions and the loaded facets do not change; only the values do). Converting
the triplets with scipy sorts them and sums duplicates on every call. Here the first call
finds, once, the slot of every triplet in the canonical (column-major, sorted, duplicate-free)
pattern::

    key_n  = col_n * n_rows + row_n,      slots = unique(key)
    data_s = sum over n with slot(n) = s of value_n          (numpy bincount)

and later calls with the same ``(row, col)`` lists only scatter the values. The sums run in
triplet order, so a matrix equals scipy's conversion of the same triplets to rounding.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray


class SparsityPattern:
    """Assembles ``n_rows`` x ``n_cols`` matrices from triplets; rebuilt when they change."""

    def __init__(self, shape: tuple[int, int]) -> None:
        self.shape = shape
        self._rows: NDArray | None = None
        self._cols: NDArray | None = None
        self._slot: NDArray[np.intp] = np.empty(0, dtype=np.intp)
        self._indices: NDArray[np.int32] = np.empty(0, dtype=np.int32)
        self._indptr: NDArray[np.int32] = np.zeros(shape[1] + 1, dtype=np.int32)

    def _same(self, rows: NDArray, cols: NDArray) -> bool:
        return (
            self._rows is not None
            and self._cols is not None
            and rows.shape == self._rows.shape
            and np.array_equal(rows, self._rows)
            and np.array_equal(cols, self._cols)
        )

    def _build(self, rows: NDArray, cols: NDArray) -> None:
        n_rows, n_cols = self.shape
        key = cols.astype(np.int64) * n_rows + rows.astype(np.int64)
        unique, slot = np.unique(key, return_inverse=True)
        self._slot = slot.astype(np.intp)
        self._indices = (unique % n_rows).astype(np.int32)
        self._indptr = np.searchsorted(unique // n_rows, np.arange(n_cols + 1)).astype(np.int32)
        self._rows, self._cols = rows.copy(), cols.copy()

    def csc(self, rows: NDArray, cols: NDArray, values: NDArray) -> sp.csc_matrix:
        """The matrix with ``A[rows[n], cols[n]] += values[n]``, in canonical CSC form."""
        if not self._same(rows, cols):
            self._build(rows, cols)
        data = np.bincount(self._slot, weights=values, minlength=self._indices.size)
        # copies: a caller may prune or reorder the matrix in place, the pattern must stay
        A = sp.csc_matrix((data, self._indices.copy(), self._indptr.copy()), shape=self.shape)
        A.has_canonical_format = True
        return A
