"""Sparse LU of the Newton tangent (oocyte_fe.fe.linear) against a direct reference solve."""

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from oocyte_fe.fe import linear
from oocyte_fe.fe.linear import SparseLU, nested_dissection


def saddle_point(n_u: int = 300, n_p: int = 60, seed: int = 0, skew: float = 0.2) -> sp.csc_matrix:
    """[[K, B^T], [B, 0]]: K a 2-D Laplacian-like unsymmetric block, B sparse, zero p-block
    (the incompressible mixed form: every pressure pivot must come from elsewhere)."""
    rng = np.random.default_rng(seed)
    m = int(np.sqrt(n_u))
    lap = sp.kronsum(
        sp.diags_array([-1.0, 2.0, -1.0], offsets=[-1, 0, 1], shape=(m, m)),
        sp.diags_array([-1.0, 2.0, -1.0], offsets=[-1, 0, 1], shape=(m, m)),
    )
    K = lap + skew * sp.random(m * m, m * m, density=2 / (m * m), random_state=rng)
    B = sp.random(n_p, m * m, density=4 / (m * m), random_state=rng) + sp.eye(n_p, m * m)
    return sp.bmat([[K, B.T], [B, None]]).tocsc()


def test_solution_matches_a_direct_solve_on_an_indefinite_unsymmetric_system():
    A = saddle_point()
    b = np.random.default_rng(1).standard_normal(A.shape[0])
    x = SparseLU().factorize(A).solve(b)
    np.testing.assert_allclose(x, spsolve(A, b), rtol=1e-9, atol=1e-10)
    assert np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b)


def test_ordering_is_a_permutation_and_is_reused_while_the_pattern_repeats(monkeypatch):
    A = saddle_point()
    assert sorted(nested_dissection(A).tolist()) == list(range(A.shape[0]))
    calls = []

    def counted(M):
        calls.append(M.shape)
        return nested_dissection(M)

    monkeypatch.setattr(linear, "nested_dissection", counted)
    lu = SparseLU()
    b = np.ones(A.shape[0])
    for scale in (1.0, 2.0, 0.5):  # same pattern, new values: one ordering
        B = A.copy()
        B.data *= scale
        np.testing.assert_allclose(lu.factorize(B).solve(b), spsolve(B, b), rtol=1e-9)
    assert len(calls) == 1
    C = saddle_point(seed=5)  # another pattern: a new ordering, still the right answer
    np.testing.assert_allclose(lu.factorize(C).solve(b), spsolve(C, b), rtol=1e-9)
    assert len(calls) == 2


def test_singular_matrix_raises_runtime_error():
    A = saddle_point()
    A = A.tolil()
    A[:, 3] = 0.0
    with pytest.raises(RuntimeError):
        SparseLU().factorize(A.tocsc())
