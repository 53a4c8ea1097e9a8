"""Creep under a held force: indentation -> shear creep compliance (Lee-Radok) -> Prony.

Lee and Radok's solution for a rigid cone pressed into a linear viscoelastic half-space with a
constant Poisson ratio, under a force step F0 held constant from t = 0::

    delta(t)^2 = pi (1 - nu) F0 J(t) / (4 tan(alpha))

delta indentation [um], F0 clamped force [nN], J(t) shear creep compliance [1/kPa], alpha half
opening angle [deg], nu Poisson ratio. For an elastic solid J = 1/G, E = 2 (1 + nu) G and this is
Sneddon's cone. Any axisymmetric tip of :mod:`afm.models` (elastic law F = E shape(delta))
follows the same way: ``shape(delta(t)) = F0 J(t) / (2 (1 + nu))`` (for a paraboloid of radius
R, delta^(3/2) = 3 (1 - nu) F0 J / (8 sqrt R)). :func:`fit_creep_tip` takes the tip by model
key and geometry, :func:`fit_creep` the cone.

A measured hold is not an exact step: the force drifts or overshoots and settles. While the
contact area does not shrink, Lee and Radok's correspondence holds for any load history
(Boltzmann superposition)::

    shape(delta(t)) = 1 / (2 (1 + nu)) * integral_{0-}^{t} J(t - s) dF(s)

with the force applied at t = 0 (F = 0 before; the step F(0) is part of the integral). The fit
uses the MEASURED force, piecewise linear between samples. With the reference force F_ref (the
mean force, ``clamp_force_nN``), f(t) = F(t) / F_ref and the apparent compliance
j(t) = 2 (1 + nu) shape(delta(t)) / F_ref (the step's J(t) when the force is clamped)::

    j(t) = J0 f(t) + sum_i J_i R_i(t)
    R_i(t) = integral_{0-}^{t} (1 - exp(-(t - s)/lambda_i)) df(s)

linear in the Prony weights for fixed retardation times. Over a sample interval of length h with
x = h / lambda, a = exp(-x) and the load rising by df, exactly::

    R(t_n) = a R(t_{n-1}) + (1 - a) f(t_{n-1}) + phi(x) df,     phi(x) = 1 - (1 - a) / x

with R(0) = 0 (:func:`compliance_response`). For a clamped force (f = 1) R_i = 1 - exp(-t/lambda_i),
the step fit. Assumptions: the contact area never shrinks (checked: :func:`check_creeping`), nu
does not change with time.

J(t) is fitted by a creep Prony series with non-negative terms (:func:`fit_creep_prony`):
non-negative least squares (:func:`scipy.optimize.nnls`) over a fixed grid of retardation
times, ``per_decade`` per decade between the sampling step and the record length; adjacent
non-zero grid terms are merged (weighted in log time) and the merged series is refined by
bounded least squares (:func:`scipy.optimize.least_squares`) with free retardation times.
The relaxation series follows exactly (:func:`afm.prony_series.relaxation_from_creep`).

References: E. H. Lee and J. R. M. Radok, J. Appl. Mech. 27 (1960) 438-444; T. C. T. Ting,
J. Appl. Mech. 33 (1966) 845-854 (the history integral while the contact grows).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit
from scipy.optimize import least_squares, nnls

from afm.creep_data import CreepData
from afm.creep_data import check_creeping as shrinking
from afm.curve_io import read_creep
from afm.material_file import MaterialFile
from afm.models import POISSON_RATIO, get_model
from afm.models.sneddon_cone import HALF_ANGLE
from afm.prony_series import MAX_TIME_S, CreepProny, RelaxationProny, relaxation_from_creep
from oocyte_fe.checks import float_array, increasing, integer, numbers_array, positive
from oocyte_fe.errors import InputError, SolverError

MAX_RELATIVE_RMS = 0.1
"""Largest relative RMS residual of the J(t) fit accepted at all (above: refused)."""
GOOD_RELATIVE_RMS = 0.02
"""Largest relative RMS residual of the J(t) fit rated ``good``."""
BOUND_MARGIN = 2.0
"""Retardation times are bounded to [step e^-2, 3 T e^2] (log margin 2 around the NNLS grid)."""


def _cone_factor(half_angle_deg: float, nu: float) -> float:
    """pi (1 - nu) / (4 tan(alpha)), 1/um^0 (delta^2 = factor * F0 * J)."""
    alpha = HALF_ANGLE.check(half_angle_deg)
    return math.pi * (1.0 - POISSON_RATIO.check(nu)) / (4.0 * math.tan(math.radians(alpha)))


def compliance_from_indentation(
    indentation_um: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """J(t) = 4 tan(alpha) delta(t)^2 / (pi (1 - nu) F0), 1/kPa (Lee-Radok, cone)."""
    delta = float_array("<input>", "indentation_um", indentation_um)
    force = positive("<input>", "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        compliance = delta**2 / (_cone_factor(half_angle_deg, nu) * force)
    return _finite(compliance, "compliance_per_kPa")


def indentation_from_compliance(
    compliance_per_kPa: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """delta(t) = sqrt(pi (1 - nu) F0 J(t) / (4 tan(alpha))), um (Lee-Radok, cone)."""
    j = float_array("<input>", "compliance_per_kPa", compliance_per_kPa)
    force = positive("<input>", "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        delta = np.sqrt(_cone_factor(half_angle_deg, nu) * force * j)
    return _finite(delta, "indentation_um")


def tip_compliance(
    indentation_um: np.ndarray,
    force_nN: float,
    model: str,
    geometry: Mapping[str, float],
    nu: float = 0.5,
    where: str = "<input>",
) -> np.ndarray:
    """J(t) = 2 (1 + nu) shape(delta(t)) / F0, 1/kPa (Lee-Radok, any tip of :mod:`afm.models`)."""
    tip = get_model(model, where)
    geometry = tip.check_geometry(geometry, where)
    nu = POISSON_RATIO.check(nu, where)
    delta = float_array(where, "indentation_um", indentation_um)
    force = positive(where, "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        compliance = 2.0 * (1.0 + nu) * tip.shape(np.clip(delta, 0.0, None), geometry, nu) / force
    return _finite(compliance, "compliance_per_kPa")


@dataclass(frozen=True)
class CreepFit:
    """Creep fit: the data's J(t), the fitted creep series and its exact relaxation series.

    ``compliance_per_kPa`` is the record's step compliance: the fitted J(t) times the measured
    over the fitted indentation response, shape(delta) / shape(delta_fit) (module docstring;
    under a clamped force, 2 (1 + nu) shape(delta(t)) / F0 itself). ``force_nN`` is the
    measured load history the fit used, ``clamp_force_nN`` its mean (the reference force).
    ``model`` and ``geometry`` are the tip the compliance was computed for.
    """

    time_s: np.ndarray
    compliance_per_kPa: np.ndarray
    creep: CreepProny
    relaxation: RelaxationProny
    nu: float
    model: str
    geometry: Mapping[str, float]
    clamp_force_nN: float
    relative_rms: float
    force_nN: np.ndarray
    undetermined: tuple[str, ...] = ()

    @property
    def quality(self) -> str:
        """``good``, or ``poor: <reasons>`` (relative RMS above 2 %, undetermined terms)."""
        reasons = list(self.undetermined)
        if not self.relative_rms <= GOOD_RELATIVE_RMS:
            reasons.insert(0, f"relative RMS {self.relative_rms:.3g} > {GOOD_RELATIVE_RMS:g}")
        return "poor: " + "; ".join(reasons) if reasons else "good"

    @property
    def E0_kPa(self) -> float:
        """Instantaneous Young's modulus 2 (1 + nu) G0, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G0_kPa

    @property
    def E_inf_kPa(self) -> float:
        """Long-time Young's modulus 2 (1 + nu) G_inf, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G_inf_kPa

    def material(self, name: str, source: str) -> MaterialFile:
        """The material-file record (instantaneous E, nu, normalised Prony terms).

        The fit's rating is appended to ``source``, so a series with terms the record does
        not determine carries that flag into the TOML, ANSYS and FEBio files.
        """
        return MaterialFile(
            name=name,
            source=f"{source}; creep fit {self.quality}",
            E_kPa=self.E0_kPa,
            nu=self.nu,
            g=self.relaxation.g,
            tau_s=self.relaxation.tau_s,
        )


SERIES_BELOW = 1e-3
"""Below this x = h / lambda, phi and psi of :func:`_responses` are summed from their series."""


@njit(cache=True)
def _responses(
    t: np.ndarray, load: np.ndarray, lambdas: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """R_i(t_n) and dR_i/d(ln lambda_i) for the piecewise-linear load f (module docstring).

    Per interval (x = h / lambda, a = exp(-x), q = 1 - a, df the load's rise)::

        R_n = R_{n-1} + q (f_{n-1} - R_{n-1}) + phi(x) df,     phi = 1 - q / x
        D_n = a D_{n-1} + a x (R_{n-1} - f_{n-1}) - psi(x) df,  psi = (q - x a) / x

    (D = dR/d ln lambda; dx/d ln lambda = -x). Below x = :data:`SERIES_BELOW` phi and psi are
    their Taylor series (phi = x/2 - x^2/6 + x^3/24 - x^4/120, psi = x/2 - x^2/3 + x^3/8
    - x^4/30 + x^5/144; truncation below 1e-14 relative), which the quotients lose to
    cancellation. For f = 1: R = 1 - exp(-t/lambda), D = -(t/lambda) exp(-t/lambda).
    """
    n, m = t.size, lambdas.size
    response = np.zeros((n, m))
    slope = np.zeros((n, m))
    for k in range(m):
        r, d = 0.0, 0.0
        for i in range(1, n):
            x = (t[i] - t[i - 1]) / lambdas[k]
            a = math.exp(-x)
            q = -math.expm1(-x)
            if x < SERIES_BELOW:
                phi = x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)))
                psi = x * (0.5 - x * (1.0 / 3.0 - x * (1.0 / 8.0 - x * (1.0 / 30.0 - x / 144.0))))
            else:
                phi = 1.0 - q / x
                psi = (q - x * a) / x
            rise = load[i] - load[i - 1]
            d = a * d + a * x * (r - load[i - 1]) - psi * rise
            r = r + q * (load[i - 1] - r) + phi * rise
            response[i, k] = r
            slope[i, k] = d
    return response, slope


FORCE_WINDOW = 0.1
"""Half width of the force smoothing window, relative to the time (t +- 10 % of t)."""
FORCE_WINDOW_SAMPLES = 200
"""Most samples either side of a time in the force smoothing window."""
FORCE_WINDOW_FEWEST = 20
"""Fewest samples either side of a time in the force smoothing window (where the record has
them): the first samples' noise is averaged too (with 2, 5 or 10 a 0.4 % force noise still
left a fitted term shorter than the sampling step)."""


@njit(cache=True)
def _local_linear(t: np.ndarray, y: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Local linear fit of y at each t_i over rows lo_i..hi_i - 1, triangular weights
    w = 1 - |t - t_i| / h_i (h_i the farther window edge; continuous in the data)::

        y_i = (S2 Sy - S1 Sty) / (S0 S2 - S1^2),  S_k = sum w (t - t_i)^k, Sy = sum w y,
        Sty = sum w (t - t_i) y

    (a window of one sample gives y_i; two give the line through them, y_i again).
    """
    n = t.size
    out = y.copy()
    for i in range(n):
        h = max(t[i] - t[lo[i]], t[hi[i] - 1] - t[i])
        if h <= 0.0:
            continue
        h = h * (1.0 + 1e-9)  # the farthest sample keeps a weight of ~1e-9: a line, not a point
        s0 = s1 = s2 = sy = sty = 0.0
        for k in range(lo[i], hi[i]):
            u = t[k] - t[i]
            w = 1.0 - abs(u) / h
            s0 += w
            s1 += w * u
            s2 += w * u * u
            sy += w * y[k]
            sty += w * u * y[k]
        den = s0 * s2 - s1 * s1
        if den > 1e-14 * s0 * s2:
            out[i] = (s2 * sy - s1 * sty) / den
    return out


def smoothed_force(time_s: np.ndarray, force_nN: np.ndarray) -> np.ndarray:
    """The force history the creep fit uses, nN: a local linear fit (:func:`_local_linear`)
    over t +- :data:`FORCE_WINDOW` t, with :data:`FORCE_WINDOW_FEWEST` to
    :data:`FORCE_WINDOW_SAMPLES` rows either side (fewer at the record's ends).

    Sensor noise in the force would enter the instantaneous term J0 F(t) of the fit (a 0.4 %
    force noise on a clamped record gave a spurious 3 ms term and E0 +1.7 %); the window grows
    with t, as the fit's resolution in log time, so a settling force is followed while the
    noise is averaged. A constant or linear force is returned unchanged (to round-off).
    """
    t, force = _history(time_s, force_nN)
    n = t.size
    rows = np.arange(n)
    lo = np.searchsorted(t, t * (1.0 - FORCE_WINDOW), side="left")
    hi = np.searchsorted(t, t * (1.0 + FORCE_WINDOW), side="right")
    lo = np.clip(lo, rows - FORCE_WINDOW_SAMPLES, rows - FORCE_WINDOW_FEWEST).clip(0)
    hi = np.clip(hi, rows + FORCE_WINDOW_FEWEST + 1, rows + FORCE_WINDOW_SAMPLES + 1).clip(None, n)
    return _local_linear(t, force, lo, hi)


def _basis(t: np.ndarray, load: np.ndarray, lambdas: np.ndarray) -> np.ndarray:
    """Columns f(t) (for J0) and R_i(t) (for J_i) of the apparent compliance j(t)."""
    return np.column_stack([load, _responses(t, load, lambdas)[0]])


def compliance_response(
    creep: CreepProny, time_s: np.ndarray, relative_force: np.ndarray | None = None
) -> np.ndarray:
    """Apparent compliance j(t) = J0 f(t) + sum J_i R_i(t) of ``creep`` under the load history
    F(t) = F_ref f(t), 1/kPa (module docstring): 2 (1 + nu) shape(delta(t)) / F_ref.

    ``relative_force`` is f at ``time_s`` (piecewise linear between them, applied at t = 0);
    left out it is 1 (a force step), and j(t) = J(t).
    """
    if not isinstance(creep, CreepProny):
        raise InputError("<input>", "creep", "a CreepProny series", type(creep).__name__)
    t, load = _history(time_s, relative_force)
    lambdas = np.asarray(creep.lambda_s, dtype=float)
    return _basis(t, load, lambdas) @ np.array([creep.J0_per_kPa, *creep.J_per_kPa])


def _history(
    time_s: np.ndarray, relative_force: np.ndarray | None, where: str = "<input>"
) -> tuple[np.ndarray, np.ndarray]:
    """(t - t[0], f) checked: times increasing from t[0], f finite and of the same length
    (ones when left out)."""
    t = increasing(where, "time_s", time_s)
    if t.size < 2:
        raise InputError(where, "time_s", "at least 2 times in s", t.size)
    if relative_force is None:
        return t - t[0], np.ones_like(t)
    load = numbers_array(where, "relative_force", relative_force, ge=-1e6, le=1e6)
    if load.shape != t.shape:
        raise InputError(where, "relative_force", f"{t.size} values (one per time)", load.size)
    return t - t[0], load


def _merge(weights: np.ndarray, lambdas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge runs of adjacent non-zero grid terms into one term each (log-weighted time)."""
    merged_w, merged_l, run = [], [], []
    for i, w in enumerate(weights):
        if w > 0:
            run.append(i)
        if run and (w <= 0 or i == weights.size - 1):
            idx = np.array(run)
            total = float(weights[idx].sum())
            merged_w.append(total)
            merged_l.append(float(np.exp(np.dot(weights[idx], np.log(lambdas[idx])) / total)))
            run = []
    return np.array(merged_w), np.array(merged_l)


def fit_window(time_s: np.ndarray, where: str = "<input>") -> tuple[float, float]:
    """The retardation-time grid of a record, [max(step, 1e-6 s), 3 T] (T its last time).

    The fitted times may leave it by e^2 either side (:data:`BOUND_MARGIN`), so it must lie
    within the Prony series' [MIN_TIME_S, MAX_TIME_S] by that margin and hold a decade:
    refused (:class:`InputError` naming ``time_s``) otherwise, before a fit that could not
    hold its own result (a record of 6e-9 s gave an empty interval, one of 3e9 s a time of
    1.07e9 s).
    """
    t = np.asarray(time_s, dtype=float)
    lo = max(float(np.min(np.diff(t))), 1e-6)
    longest = MAX_TIME_S / (3.0 * math.exp(BOUND_MARGIN)) * (1 - 1e-9)  # exp/log round-off
    shortest = 10.0 * lo / 3.0
    if not shortest <= float(t[-1]) <= longest:
        raise InputError(
            where,
            "time_s",
            f"a record ending between {shortest:.3g} s (10 x max(sampling step, 1e-6 s) / 3) "
            f"and {longest:.3g} s (fitted times within {MAX_TIME_S:g} s)",
            got=f"{float(t[-1]):.6g} s",
        )
    return lo, 3.0 * float(t[-1])


def fit_creep_prony(
    time_s: np.ndarray,
    compliance_per_kPa: np.ndarray,
    per_decade: int = 4,
    relative_force: np.ndarray | None = None,
) -> tuple[CreepProny, float]:
    """Fit J(t) = J0 + sum J_i (1 - exp(-t/lambda_i)) with J0, J_i >= 0 (module docstring).

    ``compliance_per_kPa`` is the apparent compliance j(t) = 2 (1 + nu) shape(delta(t)) / F_ref
    and ``relative_force`` the load history f(t) = F(t) / F_ref at the same times (left out: a
    force step, f = 1, and j = J); the series is fitted to j(t) = J0 f(t) + sum J_i R_i(t) by
    Boltzmann superposition. Residuals are relative (divided by j), so short and long times
    weigh alike. Returns the series and the relative RMS residual. The record's times must
    allow a fit window (:func:`fit_window`).
    """
    t, load = _history(time_s, relative_force)
    j = np.asarray(compliance_per_kPa, dtype=float)
    lo, hi = fit_window(t)
    n_grid = max(int(round(per_decade * math.log10(hi / lo))) + 1, 2)
    grid = np.logspace(math.log10(lo), math.log10(hi), n_grid)
    weight = 1.0 / j
    coeffs, _ = nnls(_basis(t, load, grid) * weight[:, None], j * weight)
    terms, lambdas = _merge(coeffs[1:], grid)
    j0 = max(float(coeffs[0]), 1e-12 * float(j.max()))
    n = terms.size

    def residual(p: np.ndarray) -> np.ndarray:
        return (_basis(t, load, np.exp(p[1 + n :])) @ p[: 1 + n] - j) * weight

    def jacobian(p: np.ndarray) -> np.ndarray:
        response, slope = _responses(t, load, np.exp(p[1 + n :]))
        d_log_lambda = p[1 : 1 + n] * slope
        return np.column_stack([load, response, d_log_lambda]) * weight[:, None]

    start = np.concatenate([[j0], terms, np.log(lambdas)])
    lower = np.concatenate([np.zeros(1 + n), np.full(n, math.log(lo) - BOUND_MARGIN)])
    upper = np.concatenate([np.full(1 + n, np.inf), np.full(n, math.log(hi) + BOUND_MARGIN)])
    result = least_squares(residual, start, jac=jacobian, bounds=(lower, upper), method="trf")
    p = result.x
    rms = float(np.sqrt(np.mean(result.fun**2)))
    terms, lambdas = _tidy(p[1 : 1 + n], np.exp(p[1 + n :]), float(np.sum(p[: 1 + n])))
    return CreepProny(float(p[0]), tuple(terms), tuple(lambdas)), rms


def _tidy(terms: np.ndarray, lambdas: np.ndarray, total: float) -> tuple[np.ndarray, np.ndarray]:
    """Drop terms below 1e-9 of J_inf and merge terms whose times differ by < 0.1 %.

    Dropping changes J(t) by less than 1e-9 relative, merging by less than 0.1 % of the merged
    terms; both keep the relaxation conversion well posed (a near-zero term next to another
    pole has its zero within round-off of that pole).
    """
    keep = terms > 1e-9 * total
    order = np.argsort(lambdas[keep])
    terms, lambdas = terms[keep][order], lambdas[keep][order]
    merged_t: list[float] = []
    merged_l: list[float] = []
    for w, lam in zip(terms, lambdas, strict=True):
        if merged_l and lam < 1.001 * merged_l[-1]:
            total_w = merged_t[-1] + w
            merged_l[-1] = math.exp(
                (merged_t[-1] * math.log(merged_l[-1]) + w * math.log(lam)) / total_w
            )
            merged_t[-1] = total_w
        else:
            merged_t.append(float(w))
            merged_l.append(float(lam))
    return np.array(merged_t), np.array(merged_l)


def _finite(values: np.ndarray, field: str) -> np.ndarray:
    if not np.all(np.isfinite(values)):
        raise InputError(
            "<input>",
            field,
            "a result within floating point range (inputs "
            "too large or too small, or negative compliance)",
        )
    return values


def check_creeping(data: CreepData) -> None:
    """Refuse a hold whose indentation shrinks (:func:`afm.creep_data.check_creeping`)."""
    shrinking(data.indentation_um, data.source)


def undetermined_terms(creep: CreepProny, time_s: np.ndarray) -> tuple[str, ...]:
    """Retardation terms the record cannot determine, one line each.

    A term is undetermined when its time is pinned at a bound of the fit (step e^-2 or
    3 T e^2, T the record length), shorter than the sampling step, or longer than the record.
    """
    t = np.asarray(time_s, dtype=float)
    step = max(float(np.min(np.diff(t))), 1e-6)
    record = float(t[-1] - t[0])
    low = math.log(step) - BOUND_MARGIN
    high = math.log(3.0 * record) + BOUND_MARGIN
    flags = []
    for i, lam in enumerate(creep.lambda_s, start=1):
        log_lam = math.log(lam)
        name = f"lambda_{i} = {lam:.3g} s"
        if abs(log_lam - low) < 1e-6 or abs(log_lam - high) < 1e-6:
            bound = "step e^-2" if abs(log_lam - low) < 1e-6 else "3 T e^2"
            flags.append(f"{name} pinned at its bound ({bound}): not determined by the record")
        elif lam < step:
            flags.append(f"{name} shorter than the sampling step {step:.3g} s: not determined")
        elif lam > record:
            flags.append(f"{name} longer than the record {record:.3g} s: not determined")
    return tuple(flags)


def _relaxation_of_fit(creep: CreepProny, src: str) -> RelaxationProny:
    """The exact relaxation series of a *fitted* creep series; a conversion that fails (the
    fit's times too close or its terms beyond floating point range: brentq cannot bracket a
    zero) is the fit's failure, so a :class:`SolverError` naming the record, not an argument."""
    try:
        return relaxation_from_creep(creep)
    except InputError as exc:
        times = ", ".join(f"{lam:.6g}" for lam in creep.lambda_s)
        raise SolverError(
            f"{src}: the creep Prony series fitted to this record ({len(creep.lambda_s)} terms, "
            f"retardation times {times} s) does not convert to a relaxation series "
            f"({exc.expected}); try a smaller per_decade or a longer, less noisy hold"
        ) from None


def fit_creep(
    data: CreepData, half_angle_deg: float = 10.0, nu: float = 0.5, per_decade: int = 4
) -> CreepFit:
    """:func:`fit_creep_tip` for a cone of half angle ``half_angle_deg`` (deg)."""
    where = data.source if isinstance(data, CreepData) else "<input>"
    half_angle_deg = HALF_ANGLE.check(half_angle_deg, where)
    return fit_creep_tip(data, "sneddon_cone", {"half_angle_deg": half_angle_deg}, nu, per_decade)


def fit_creep_tip(
    data: CreepData,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    per_decade: int = 4,
) -> CreepFit:
    """Lee-Radok compliance of a force-clamp hold for the tip ``model`` (with ``geometry``;
    left-out parameters take the model's default), its creep Prony fit and relaxation series.

    The fit uses the record's measured force history by Boltzmann superposition (module
    docstring): a drifting or overshooting force is fitted as it was applied, a clamped force
    gives the step fit.

    Refused (:class:`InputError`): an indentation shrinking during the hold
    (:func:`check_creeping`), a fit with relative RMS above ``MAX_RELATIVE_RMS``, a geometry
    outside the model's bounds, nu outside (-1, 0.5], ``per_decade`` not an integer in
    [1, 50]. Terms the record cannot determine are listed in ``CreepFit.undetermined`` and
    make the ``quality`` poor. A fitted series that does not convert to relaxation raises
    :class:`SolverError` naming the record.
    """
    if not isinstance(data, CreepData):
        raise InputError("<input>", "data", "a CreepData record", type(data).__name__)
    src = data.source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    per_decade = integer(src, "per_decade", per_decade, 1, 50)
    check_creeping(data)
    force = data.clamp_force_nN
    compliance = tip_compliance(data.indentation_um, force, model, geometry, nu, src)
    j_min, j_max = float(np.min(compliance)), float(np.max(compliance))
    if not (j_min > 1e-100 and j_max < 1e100):
        raise InputError(
            src, "indentation_um", "an indentation whose compliance J(t) is within 1e-100..1e100"
        )
    fit_window(data.time_s, src)
    load = smoothed_force(data.time_s, data.force_nN) / force
    creep, rms = fit_creep_prony(data.time_s, compliance, per_decade, load)
    if not rms <= MAX_RELATIVE_RMS:
        raise InputError(
            src,
            "indentation_um",
            f"a hold a creep Prony series fits (relative RMS <= {MAX_RELATIVE_RMS:g})",
            f"relative RMS {rms:.3g}",
        )
    fitted = compliance_response(creep, data.time_s, load)
    return CreepFit(
        time_s=data.time_s,
        compliance_per_kPa=creep(data.time_s) * compliance / fitted,
        creep=creep,
        relaxation=_relaxation_of_fit(creep, src),
        nu=nu,
        model=tip.key,
        geometry=geometry,
        clamp_force_nN=force,
        relative_rms=rms,
        force_nN=data.force_nN,
        undetermined=undetermined_terms(creep, data.time_s),
    )


def material_from_creep_csv(
    path: str | Path,
    name: str,
    half_angle_deg: float = 10.0,
    nu: float = 0.5,
    per_decade: int = 4,
) -> MaterialFile:
    """Read a creep CSV (:func:`afm.curve_io.read_creep`), fit it, return the material record.

    Write it with :func:`afm.material_file.write_material`.
    """
    data = read_creep(path)
    fit = fit_creep(data, half_angle_deg, nu, per_decade)
    source = (
        f"AFM creep {Path(path).name}: Lee-Radok cone (alpha {half_angle_deg:g} deg, "
        f"F0 {fit.clamp_force_nN:.3g} nN), creep Prony fit, exact conversion to relaxation"
    )
    return fit.material(name, source)
