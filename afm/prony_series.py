"""Prony series of shear relaxation G(t) and creep compliance J(t), and their exact interconversion.

Relaxation (units kPa, s)::

    G(t) = G_inf + sum_k G_k exp(-t/tau_k) = G0 [1 - sum_k g_k (1 - exp(-t/tau_k))]

with G0 = G_inf + sum G_k the instantaneous modulus and g_k = G_k/G0 the normalised terms
(the form of the material file, ANSYS ``TB,PRONY`` and FEBio ``viscoelastic``).

Creep (units 1/kPa, s)::

    J(t) = J0 + sum_i J_i (1 - exp(-t/lambda_i))

Interconversion. For linear viscoelasticity the Laplace transforms satisfy
``G_bar(s) J_bar(s) = 1/s^2``, i.e. ``s G_bar(s) = 1 / (s J_bar(s))``, where

    s J_bar(s) = J0 + sum_i J_i r_i / (s + r_i),         r_i = 1/lambda_i
    s G_bar(s) = G_inf + sum_k G_k s / (s + b_k),        b_k = 1/tau_k

Both sides are rational of equal degree N, so N creep terms give exactly N relaxation terms:

* the relaxation rates -b_k are the zeros of s J_bar(s). With all J_i > 0, s J_bar decreases
  between its poles -r_i, so there is one zero in each gap (-r_{i+1}, -r_i) and one below
  -r_N: relaxation times are real, positive and shorter than the retardation times;
* the residue of 1/(s J_bar) at a zero s_k equals G_k s_k, so G_k = 1 / (s_k (s J_bar)'(s_k))
  (positive, since both factors are negative);
* G0 = 1/J0 (s -> inf) and G_inf = 1/(J0 + sum J_i) (s -> 0).

The converse (relaxation -> creep) is the same construction on s G_bar(s), whose zeros lie in
(-b_1, 0) and in each gap (-b_{k+1}, -b_k), with J_i = 1/(r_i (s G_bar)'(-r_i)) and
J0 = 1/G0. Each zero is bracketed exactly, so :func:`scipy.optimize.brentq` finds it to machine
precision (no polynomial roots, which are ill-conditioned for spread time scales).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from oocyte_fe.checks import number, positive
from oocyte_fe.errors import InputError

MIN_TIME_S, MAX_TIME_S = 1e-9, 1e9
"""Admissible relaxation / retardation times, s (outside: refused, their rates overflow)."""
NEGLIGIBLE = 1e-12
"""Terms below this fraction of the total are dropped by the conversions (no effect on G, J)."""


def _items(values: object, what: str) -> list:
    if isinstance(values, (str, bytes)) or values is None:
        raise InputError("<input>", what, "a sequence of numbers", values)
    try:
        return list(np.atleast_1d(np.asarray(values, dtype=object)))
    except (TypeError, ValueError):
        raise InputError("<input>", what, "a sequence of numbers", values) from None


def _as_terms(
    values: tuple[float, ...] | np.ndarray, times: tuple[float, ...] | np.ndarray, what: str
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    v = tuple(
        number("<input>", what, a, expected="non-negative terms") for a in _items(values, what)
    )
    t = tuple(
        number("<input>", what, a, expected="positive time constants") for a in _items(times, what)
    )
    if len(v) != len(t):
        raise InputError("<input>", what, "as many terms as time constants", (len(v), len(t)))
    if any(a < 0 for a in v):
        raise InputError("<input>", what, "non-negative terms", v)
    if any(not MIN_TIME_S <= a <= MAX_TIME_S for a in t):
        raise InputError(
            "<input>", what, f"time constants in [{MIN_TIME_S:g}, {MAX_TIME_S:g}] s", t
        )
    order = np.argsort(t)
    return tuple(v[i] for i in order), tuple(t[i] for i in order)


@dataclass(frozen=True)
class RelaxationProny:
    """G(t) = G0 [1 - sum g_k (1 - exp(-t/tau_k))]: G0 [kPa], g_k [1], tau_k [s] ascending."""

    G0_kPa: float
    g: tuple[float, ...]
    tau_s: tuple[float, ...]

    def __post_init__(self) -> None:
        g, tau = _as_terms(self.g, self.tau_s, "g")
        g0 = positive("<input>", "G0_kPa", self.G0_kPa, expected="a positive modulus in kPa")
        object.__setattr__(self, "G0_kPa", g0)
        if sum(g) >= 1:
            raise InputError("<input>", "g", "sum of g below 1 (a solid)", sum(g))
        object.__setattr__(self, "g", g)
        object.__setattr__(self, "tau_s", tau)

    @property
    def G_inf_kPa(self) -> float:
        """Long-time (equilibrium) shear modulus G0 (1 - sum g), kPa."""
        return self.G0_kPa * (1.0 - sum(self.g))

    @property
    def moduli_kPa(self) -> np.ndarray:
        """G_k = G0 g_k, kPa."""
        return self.G0_kPa * np.asarray(self.g)

    def __call__(self, t_s: np.ndarray) -> np.ndarray:
        """G(t) in kPa."""
        t = np.asarray(t_s, dtype=float)[..., None]
        return self.G_inf_kPa + np.sum(self.moduli_kPa * np.exp(-t / np.asarray(self.tau_s)), -1)


@dataclass(frozen=True)
class CreepProny:
    """J(t) = J0 + sum J_i (1 - exp(-t/lambda_i)): J0, J_i [1/kPa], lambda_i [s] ascending."""

    J0_per_kPa: float
    J_per_kPa: tuple[float, ...]
    lambda_s: tuple[float, ...]

    def __post_init__(self) -> None:
        j, lam = _as_terms(self.J_per_kPa, self.lambda_s, "J_per_kPa")
        j0 = positive(
            "<input>", "J0_per_kPa", self.J0_per_kPa, expected="a positive compliance in 1/kPa"
        )
        object.__setattr__(self, "J0_per_kPa", j0)
        object.__setattr__(self, "J_per_kPa", j)
        object.__setattr__(self, "lambda_s", lam)

    @property
    def J_inf_per_kPa(self) -> float:
        """Long-time compliance J0 + sum J_i, 1/kPa."""
        return self.J0_per_kPa + sum(self.J_per_kPa)

    def __call__(self, t_s: np.ndarray) -> np.ndarray:
        """J(t) in 1/kPa."""
        t = np.asarray(t_s, dtype=float)[..., None]
        terms = np.asarray(self.J_per_kPa) * (1.0 - np.exp(-t / np.asarray(self.lambda_s)))
        return self.J0_per_kPa + np.sum(terms, -1)


def _zeros(
    func: Callable[[float], float], poles: np.ndarray, last: tuple[float, float]
) -> np.ndarray:
    """One zero of ``func`` in each gap between the sorted negative ``poles``, one in ``last``."""
    zeros = []
    gaps = [(poles[i], poles[i + 1]) for i in range(poles.size - 1)]
    for i, (a, b) in enumerate([*gaps, last]):
        if i < len(gaps):  # just inside the gap: the closer, the larger |func| near a pole
            for eps in (1e-12, 1e-14, 4e-16):
                lo, hi = a * (1 - eps), b * (1 + eps)
                if func(lo) * func(hi) < 0:
                    break
        else:
            lo, hi = a, b
        if not func(lo) * func(hi) < 0:
            raise InputError(
                "<input>", "lambda_s", "time constants the conversion can separate", (a, b)
            )
        zeros.append(brentq(func, lo, hi, xtol=1e-300, rtol=1e-15, maxiter=500))
    return np.array(zeros)


def _relaxation_from_creep(creep: CreepProny) -> RelaxationProny:
    j0 = creep.J0_per_kPa
    j = np.asarray(creep.J_per_kPa)
    r = 1.0 / np.asarray(creep.lambda_s)
    keep = j > NEGLIGIBLE * (j0 + float(np.sum(j)))
    j, r = j[keep], r[keep]
    if j.size == 0:
        return RelaxationProny(1.0 / j0, (), ())
    order = np.argsort(-r)  # poles -r ascending: most negative first
    j, r = j[order], r[order]
    poles = -r

    def s_j(s: float) -> float:
        return j0 + float(np.sum(j * r / (s + r)))

    lowest = poles[0] - 2.0 * float(np.sum(j * r)) / j0
    s_k = _zeros(s_j, poles, (lowest, poles[0] * (1 + 1e-12)))
    slope = -np.array([np.sum(j * r / (s + r) ** 2) for s in s_k])
    moduli = 1.0 / (s_k * slope)
    g0 = 1.0 / j0
    return RelaxationProny(g0, tuple(moduli / g0), tuple(-1.0 / s_k))


def _creep_from_relaxation(relaxation: RelaxationProny) -> CreepProny:
    g_inf = relaxation.G_inf_kPa
    gk = relaxation.moduli_kPa
    b = 1.0 / np.asarray(relaxation.tau_s)
    keep = gk > NEGLIGIBLE * relaxation.G0_kPa
    gk, b = gk[keep], b[keep]
    if gk.size == 0:
        return CreepProny(1.0 / relaxation.G0_kPa, (), ())
    order = np.argsort(-b)
    gk, b = gk[order], b[order]
    poles = -b

    def s_g(s: float) -> float:
        return g_inf + float(np.sum(gk * s / (s + b)))

    zeros = _zeros(s_g, poles, (poles[-1] * (1 - 1e-12), 0.0))
    rates = -zeros
    slope = np.array([np.sum(gk * b / (z + b) ** 2) for z in zeros])
    compliances = 1.0 / (rates * slope)
    return CreepProny(1.0 / relaxation.G0_kPa, tuple(compliances), tuple(1.0 / rates))


def _converted(convert: Callable, series: object, what: str) -> object:
    """Run a conversion; a series whose terms span more than floats can hold is refused."""
    try:
        with np.errstate(all="ignore"):
            return convert(series)
    except InputError as exc:
        raise InputError(exc.file, what, exc.expected, exc.got) from None
    except (ValueError, ZeroDivisionError, OverflowError, FloatingPointError):
        raise InputError(
            "<input>", what, "terms and times whose ratios stay within floating point range"
        ) from None


def relaxation_from_creep(creep: CreepProny) -> RelaxationProny:
    """Exact relaxation Prony series of a creep Prony series (module docstring)."""
    if not isinstance(creep, CreepProny):
        raise InputError("<input>", "creep", "a CreepProny series", type(creep).__name__)
    return _converted(_relaxation_from_creep, creep, "J_per_kPa")


def creep_from_relaxation(relaxation: RelaxationProny) -> CreepProny:
    """Exact creep Prony series of a relaxation Prony series (module docstring)."""
    if not isinstance(relaxation, RelaxationProny):
        raise InputError("<input>", "relaxation", "a RelaxationProny series", relaxation)
    return _converted(_creep_from_relaxation, relaxation, "g")
