"""Ting's force on an axisymmetric tip pressed into a linear viscoelastic half-space.

For a tip whose elastic force is ``F = E shape(delta)`` (:mod:`afm.models`; shape includes
1/(1 - nu^2), nu constant in time) and a relaxation modulus E(t) [kPa], Ting's solution is,
while the contact grows (approach, t <= t_m, t_m the time of the deepest indentation)::

    F(t) = int_0^t E(t - s) d shape(delta(s))/ds ds                                 [nN]

and while it shrinks (retract, t > t_m)::

    F(t) = int_0^t1(t) E(t - s) d shape(delta(s))/ds ds,
    t1(t) <= t_m  defined by  int_t1(t)^t E(t - s) d delta(s)/ds ds = 0

(F = 0 once no t1 >= 0 solves it: the surface has come off the tip). For a paraboloid
shape = 4 sqrt(R) delta^(3/2) / (3 (1 - nu^2)), for a cone 2 tan(alpha) delta^2 /
(pi (1 - nu^2)); delta [um] is the indentation (tip position minus contact point, 0 before
contact), t [s]. Assumes a small indentation, no adhesion, frictionless contact, an
inertia-free quasi-static load.

Discretisation (exact for a shape(delta(t)) linear between samples on a uniform grid
t_n = n h): with Phi(t) = int_0^t E(u) du,

    F_n = sum_{j <= n} (S_j - S_{j-1}) W_{n-j},     W_m = (Phi((m+1) h) - Phi(m h)) / h,

a causal convolution done by FFT (O(N log N)); the t1 condition is the same sum over the
indentation increments, solved per retract point with the crossing interpolated inside its
step (at most ``MAX_RETRACT_ROWS`` retract points are solved, the others interpolated).

References: T. C. T. Ting, J. Appl. Mech. 33 (1966) 845-854; for cones and paraboloids with
a power-law modulus, Y. M. Efremov et al., Sci. Rep. 7 (2017) 1541.
"""

from __future__ import annotations

import numpy as np
from scipy.fft import irfft, next_fast_len, rfft

from oocyte_fe.checks import numbers_array, quantity
from oocyte_fe.errors import InputError

MAX_RETRACT_ROWS = 128
"""Retract points solved for t1 exactly; the force in between is interpolated linearly."""


def weights(integrals: np.ndarray, step_s: float) -> np.ndarray:
    """W_m = (Phi((m+1) h) - Phi(m h)) / h [kPa] from Phi at m h, m = 0..N (rows; columns:
    basis functions)."""
    return np.diff(integrals, axis=0) / step_s


def causal_convolution(increments: np.ndarray, w: np.ndarray) -> np.ndarray:
    """sum_{j <= n} increments_j w_{n-j} for every n (``w`` may have basis columns)."""
    n = increments.size
    size = next_fast_len(2 * n)
    spectrum = rfft(increments, size)
    if w.ndim == 1:
        return irfft(spectrum * rfft(w[:n], size), size)[:n]
    return irfft(spectrum[:, None] * rfft(w[:n], size, axis=0), size, axis=0)[:n]


def retract_force(
    d_shape: np.ndarray,
    d_delta: np.ndarray,
    w: np.ndarray,
    turn: int,
    rows: np.ndarray,
    w_basis: np.ndarray | None = None,
    sensitivity: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Ting's retract force at the grid points ``rows`` (all > ``turn``).

    ``d_shape`` and ``d_delta`` are the increments S_j - S_{j-1} and delta_j - delta_{j-1}
    (j: the step ending at t_j; S_{-1} = delta_{-1} = 0), ``w`` the weights of the model's
    E(t), ``turn`` the index of the deepest point. With R_c = sum_{j >= c} d_delta_j w_{n-j}
    (the t1 condition with t1 at the start of step c), t1 lies in the step c* with
    R_{c*+1} < 0 <= R_{c*}, a fraction theta = -R_{c*+1} / (d_delta_c* w_{n-c*}) of it after
    t1. Returns F (nN), or with ``w_basis`` (weights per basis function, columns) the force
    per unit amplitude of each basis function with the same t1, ``(rows.size, n_basis)``.

    With ``sensitivity`` (and ``w_basis``) also the change of F through t1 when the amplitude
    A_k of ``w = sum_k A_k w_basis_k`` changes: differentiating theta gives
    ``(d_shape_c* / d_delta_c*) (R_{c*+1,k} + theta d_delta_c* w_k,n-c*)``, R_k the t1 sum of
    basis k alone; dF/dA_k is the basis force plus this.
    """
    contact = np.flatnonzero(d_delta[: turn + 1] != 0.0)
    first = int(contact[0]) if contact.size else turn  # no terms before contact
    j = np.arange(first, turn + 1)
    lag = rows[:, None] - j[None, :]  # >= 1
    w_lag = w[lag]
    load = d_delta[first : turn + 1][None, :] * w_lag
    tail = np.cumsum(load[:, ::-1], axis=1)[:, ::-1]  # column c: sum_{c <= j <= turn}
    unload = causal_convolution(d_delta, w)[rows] - tail[:, 0]  # sum_{turn < j <= n}
    ok = (unload[:, None] + tail) >= 0.0
    found = ok.any(axis=1)
    c = np.where(found, (turn - first) - np.argmax(ok[:, ::-1], axis=1), 0)  # column of j
    ext = np.concatenate([tail, np.zeros((rows.size, 1))], axis=1)
    idx = np.arange(rows.size)
    r_hi = unload + ext[idx, c + 1]
    step_term = load[idx, c]
    with np.errstate(divide="ignore", invalid="ignore"):
        theta = np.clip(np.where(step_term > 0, -r_hi / step_term, 1.0), 0.0, 1.0)
    col = np.arange(j.size)[None, :]
    factor = (col < c[:, None]) + (col == c[:, None]) * (1.0 - theta)[:, None]
    factor = factor * found[:, None] * d_shape[first : turn + 1][None, :]
    if w_basis is None:
        return np.sum(factor * w_lag, axis=1)
    wb_lag = w_basis[lag]
    values = np.einsum("rj,rjk->rk", factor, wb_lag)
    if not sensitivity:
        return values
    load_k = d_delta[first : turn + 1][None, :, None] * wb_lag
    tail_k = np.cumsum(load_k[:, ::-1], axis=1)[:, ::-1]
    unload_k = causal_convolution(d_delta, w_basis)[rows] - tail_k[:, 0]
    ext_k = np.concatenate([tail_k, np.zeros((rows.size, 1, w_basis.shape[1]))], axis=1)
    r_hi_k = unload_k + ext_k[idx, c + 1]
    dd = d_delta[first + c]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(found & (dd != 0), d_shape[first + c] / dd, 0.0)
    sens = ratio[:, None] * (r_hi_k + theta[:, None] * load_k[idx, c])
    return values, sens


def retract_rows(turn: int, n: int) -> np.ndarray:
    """Retract grid points solved exactly: all, or about ``MAX_RETRACT_ROWS``: half spaced
    geometrically from the turn (where the force falls steeply), half evenly, with the last."""
    count = n - turn - 1
    if count <= MAX_RETRACT_ROWS:
        return np.arange(turn + 1, n)
    half = MAX_RETRACT_ROWS // 2
    offsets = np.concatenate(
        [np.geomspace(1, count, half), np.linspace(1, count, MAX_RETRACT_ROWS - half)]
    )
    return turn + np.unique(offsets.round().astype(int))


def ting_force(
    shape_values: np.ndarray, delta: np.ndarray, integrals: np.ndarray, step_s: float
) -> np.ndarray:
    """Ting's force [nN] on a uniform grid of step ``step_s`` [s].

    ``shape_values`` S_n = shape(delta_n) [um^2], ``delta`` the indentation [um] (clipped at 0:
    before contact it is 0), ``integrals`` Phi(n h) for n = 0..N [kPa s] of the model's E(t).
    Approach up to the deepest point, retract after it (module docstring).
    """
    where = "ting_force"
    s = numbers_array(where, "shape_values", shape_values, ge=0.0)
    delta = np.clip(numbers_array(where, "delta", delta), 0.0, None)
    phi = numbers_array(where, "integrals", integrals)
    step_s = quantity(where, "step_s", step_s, "time_s")
    if s.ndim != 1 or delta.shape != s.shape or phi.shape != (s.size + 1,):
        raise InputError(
            where, "integrals", "1-D shape values and indentations of one length N, N + 1 integrals"
        )
    w = weights(phi, step_s)
    d_shape = np.diff(s, prepend=0.0)
    d_delta = np.diff(delta, prepend=0.0)
    force = causal_convolution(d_shape, w)
    turn = int(np.argmax(delta))
    n = delta.size
    if turn < n - 1 and turn > 0:
        rows = retract_rows(turn, n)
        values = retract_force(d_shape, d_delta, w, turn, rows)
        force[turn + 1 :] = np.interp(np.arange(turn + 1, n), rows, values)
    return force
