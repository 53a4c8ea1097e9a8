"""Fitting a viscosity model to a flow curve by bounded least squares in log space.

Residuals are ``r_i = ln eta_model(gamma_i) - ln eta_i``: a measured flow curve spans decades
of viscosity with errors roughly proportional to the value, so log residuals weight every decade
alike (linear residuals would let the two lowest-rate points decide the fit). Positive
parameters (viscosities, time constants) are fitted as their logarithms, which turns their
orders-of-magnitude spread into one scale for the trust-region solver and keeps them positive;
exponents are fitted as they are. Bounds are the registry's.

Uncertainty: covariance ``C = s^2 (J^T J)^+`` of the fitted variables from the Jacobian at the
optimum, with ``s^2 = max(sum r^2 / (N - P), FLOOR^2)``: the noise is the residual's but at
least :data:`FLOOR` (1 %) in ln eta, as :mod:`nmsd.identifiability` takes it (on a curve fitted
to round-off the residual alone makes every error vanish: on a noiseless power law, 20 points
at 0.1-100 1/s, a Carreau fit gave eta0 and lambda to 6 and 12 % although only
eta0 lambda^(n-1) is in the data); a log-scale parameter's standard error is ``p sqrt(C_kk)``
(first order). A parameter the data do not determine (a singular value of J below ``1e-8`` of
the largest, one at a bound of its range, or one whose standard error in the fitted variable
exceeds :data:`MAX_SE`: its one-sigma range spans more than a factor e, or more than its own
size for an exponent) is reported with an infinite error and listed in ``unidentified``.
The trust-region solver keeps its iterates strictly inside the
bounds, so a parameter the data drive to a bound (a Cross time constant on power-law data,
lambda -> infinity) stops short of it, by 2e-6 to 4e-3 in ln lambda depending on the points.
A parameter is therefore *at a bound* when the bound lies within one standard error (or
:data:`AT_BOUND`) of it in the fitted variable (``ln p`` for a log-scale parameter, ``p``
otherwise) and the fit with the parameter held on that bound (the others refitted: its profile)
is no worse, ``cost_bound <= cost (1 + 1e-6) + 1e-15``: the data prefer the bound, or cannot
tell it from the optimum.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.viscosity import Rheology, ViscosityModel, get_model

FLOOR = 0.01
"""Least noise assumed in ln eta (1 % of the viscosity), as nmsd.identifiability's FLOOR."""
MAX_SE = 1.0
"""Largest standard error of an identified parameter: in ln p for a log-scale one, relative
(over |p|) for an exponent."""
AT_BOUND = 1e-3
"""Distance to a bound, in the fitted variable, within which a parameter may be at the bound
(also when its standard error is smaller): its profile decides."""


@dataclass(frozen=True)
class ViscosityFit:
    """Result of :func:`fit_viscosity`: parameters (internal units) and goodness of fit.

    ``r2`` is the coefficient of determination of the viscosity itself,
    ``1 - sum (eta_i - eta_fit_i)^2 / sum (eta_i - mean eta)^2``; ``r2_log`` is the same on
    ln eta (the fitted quantity). ``rmse`` is in kPa s, ``rmse_log`` is dimensionless.
    ``unidentified`` lists the free parameters with an infinite error, ``at_bound`` those of
    them at a bound of their range.
    """

    rheology: Rheology
    stderr: Mapping[str, float]
    fixed: tuple[str, ...]
    unidentified: tuple[str, ...]
    at_bound: tuple[str, ...]
    rmse: float
    rmse_log: float
    r2: float
    r2_log: float
    n_points: int
    success: bool
    message: str

    @property
    def model(self) -> ViscosityModel:
        return self.rheology.model

    @property
    def params(self) -> Mapping[str, float]:
        return self.rheology.params


def _r2(y: np.ndarray, y_fit: np.ndarray) -> float:
    return float(1.0 - np.sum((y - y_fit) ** 2) / np.sum((y - np.mean(y)) ** 2))


def _initial_guess(model: ViscosityModel, gamma: np.ndarray, eta: np.ndarray) -> dict[str, float]:
    """A data-based start: plateau from the highest viscosity, onset near the lowest rate."""
    slope = np.polyfit(np.log(gamma), np.log(eta), 1)[0]
    n = float(np.clip(1.0 + slope, 0.05, 1.0))
    guess = {
        "mu": float(np.exp(np.mean(np.log(eta)))),
        "eta0": float(2.0 * eta.max()),
        "eta_inf": float(1e-3 * eta.min()),
        "time_constant": float(1.0 / gamma.min()),
        "n": n,
        "a": 2.0,
        "m": float(np.clip(1.0 - n, 0.05, 1.5)),
        "consistency": float(np.exp(np.mean(np.log(eta) - (n - 1.0) * np.log(gamma)))),
    }
    return {p.key: float(np.clip(guess[p.key], p.lower, p.upper)) for p in model.parameters}


def check_fit_data(
    model_key: str,
    shear_rate: np.ndarray,
    viscosity: np.ndarray,
    *,
    fixed: Mapping[str, float] | None = None,
    source: str = "flow curve",
) -> tuple[ViscosityModel, np.ndarray, np.ndarray, dict[str, float], list]:
    """The checks :func:`fit_viscosity` makes before fitting (``validate`` makes them too):
    (model, shear rates, viscosities, fixed parameters, free parameters), or
    :class:`InputError` naming ``source`` for non-positive or non-finite data, mismatched
    lengths, fewer distinct shear rates than free parameters, or viscosities that do not vary.
    """
    model = get_model(model_key, source)
    gamma = np.asarray(shear_rate, dtype=float)
    eta = np.asarray(viscosity, dtype=float)
    fixed = dict(fixed or {})
    if gamma.shape != eta.shape or gamma.ndim != 1:
        raise InputError(source, "shear_rate, viscosity", "two 1-D columns of equal length")
    for name, values, kind in (
        ("shear_rate", gamma, "shear_rate_per_s"),
        ("viscosity", eta, "viscosity_kPa_s"),
    ):
        low, high, _ = checks.QUANTITIES[kind]
        checks.numbers_array(source, name, values, ge=low, le=high)
    unknown = set(fixed) - set(model.keys)
    if unknown:
        raise InputError(source, f"fixed.{sorted(unknown)[0]}", f"one of {model.keys}")
    free = [p for p in model.parameters if p.key not in fixed]
    distinct = np.unique(gamma).size
    if distinct < len(free):
        raise InputError(
            source,
            "shear_rate",
            f"at least {len(free)} distinct shear rates to fit the {len(free)} free parameters "
            f"of {model.key}",
            got=distinct,
        )
    if np.ptp(np.log(eta)) == 0:
        raise InputError(
            source,
            "viscosity",
            "viscosities that vary (equal ones determine no shear thinning; R^2 is undefined)",
            got=float(eta[0]),
        )
    return model, gamma, eta, fixed, free


def fit_viscosity(
    model_key: str,
    shear_rate: np.ndarray,
    viscosity: np.ndarray,
    *,
    fixed: Mapping[str, float] | None = None,
    source: str = "flow curve",
) -> ViscosityFit:
    """Fit ``model_key`` to ``viscosity`` (kPa s) at ``shear_rate`` (1/s).

    ``fixed`` holds parameters kept at given values (internal units). Raises
    :class:`InputError` naming ``source`` for non-positive or non-finite data, mismatched
    lengths, or fewer points than free parameters (:func:`check_fit_data`).
    """
    model, gamma, eta, fixed, free = check_fit_data(
        model_key, shear_rate, viscosity, fixed=fixed, source=source
    )

    def to_params(x: np.ndarray) -> dict[str, float]:
        values = {
            p.key: float(np.exp(v) if p.log_scale else v) for p, v in zip(free, x, strict=True)
        }
        return {**values, **fixed}

    def residuals(x: np.ndarray) -> np.ndarray:
        return np.log(model(gamma, to_params(x))) - np.log(eta)

    def scale(p, v):
        return np.log(v) if p.log_scale else v

    start = _initial_guess(model, gamma, eta)
    x0 = np.array([scale(p, start[p.key]) for p in free])
    lower = np.array([scale(p, p.lower) for p in free])
    upper = np.array([scale(p, p.upper) for p in free])
    sol = least_squares(residuals, x0, bounds=(lower, upper), x_scale="jac", method="trf")
    params = to_params(sol.x)
    rheology = Rheology(model, params, source)

    dof = max(gamma.size - len(free), 1)
    s2 = max(2.0 * sol.cost / dof, FLOOR**2)
    u, sv, vt = np.linalg.svd(sol.jac, full_matrices=False)
    keep = sv > 1e-8 * sv[0]
    cov = (vt[keep].T / sv[keep] ** 2) @ vt[keep] * s2
    weak = ~keep
    spread = np.sqrt(np.clip(np.diag(cov), 0.0, None))  # standard errors, fitted variables

    def pinned(k: int) -> bool:
        """The profile of free parameter ``k`` is lowest at the bound near it."""
        gaps = (sol.x[k] - lower[k], upper[k] - sol.x[k])
        if min(gaps) > max(AT_BOUND, spread[k]):
            return False
        x = sol.x.copy()
        x[k] = lower[k] if gaps[0] <= gaps[1] else upper[k]
        rest = np.arange(len(free)) != k
        cost = 0.5 * float(np.sum(residuals(x) ** 2))
        if np.any(rest):

            def pinned_residuals(y: np.ndarray) -> np.ndarray:
                x[rest] = y
                return residuals(x)

            cost = float(
                least_squares(
                    pinned_residuals,
                    sol.x[rest],
                    bounds=(lower[rest], upper[rest]),
                    x_scale="jac",
                    method="trf",
                ).cost
            )
        return cost <= sol.cost * (1.0 + 1e-6) + 1e-15

    at_bound = [pinned(k) for k in range(len(free))]
    stderr: dict[str, float] = {key: 0.0 for key in fixed}
    unidentified = []
    for k, p in enumerate(free):
        # a direction the data do not see: the parameter loads on a dropped singular vector
        undetermined = bool(np.any(np.abs(vt[weak, k]) > 1e-3)) or bool(at_bound[k])
        se = float(np.sqrt(cov[k, k]))
        undetermined |= se > MAX_SE * (1.0 if p.log_scale else abs(params[p.key]))
        if undetermined:
            stderr[p.key] = float("inf")
            unidentified.append(p.key)
            continue
        stderr[p.key] = params[p.key] * se if p.log_scale else se

    eta_fit = model(gamma, params)
    return ViscosityFit(
        rheology=rheology,
        stderr=stderr,
        fixed=tuple(fixed),
        unidentified=tuple(unidentified),
        at_bound=tuple(p.key for p, hit in zip(free, at_bound, strict=True) if hit),
        rmse=float(np.sqrt(np.mean((eta_fit - eta) ** 2))),
        rmse_log=float(np.sqrt(np.mean(sol.fun**2))),
        r2=_r2(eta, eta_fit),
        r2_log=_r2(np.log(eta), np.log(eta_fit)),
        n_points=int(gamma.size),
        success=bool(sol.success),
        message=str(sol.message),
    )
