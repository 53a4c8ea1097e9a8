"""Generalized-Newtonian viscosity models: one registry, filled by :func:`viscosity_model`.

Each entry is a frozen :class:`ViscosityModel` holding the equation, one :class:`Parameter`
record per parameter (unit, bounds, whether it is fitted in log space) and the function
``eta(gamma, **params)``. Units are the package's: viscosity in kPa s (1 Pa s = 1e-3 kPa s),
shear rate in 1/s, time constants in s. Model functions use only operations that accept
complex numbers, so :meth:`Rheology.viscosity_slope` can take a complex-step derivative.

A :class:`Rheology` is a model bound to validated parameter values; it gives the viscosity,
the shear stress ``tau = eta(gamma) gamma`` and its inverse ``gamma(tau)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from scipy.optimize import brentq

from oocyte_fe.errors import InputError

ArrayLike = float | np.ndarray


@dataclass(frozen=True)
class Parameter:
    """One model parameter: key, unit (internal system), bounds and fitting scale."""

    key: str
    unit: str
    lower: float
    upper: float
    log_scale: bool
    description: str

    def __post_init__(self) -> None:
        if not self.lower < self.upper:
            raise ValueError(f"parameter {self.key}: lower bound must be below upper bound")
        if self.log_scale and self.lower <= 0:
            raise ValueError(f"parameter {self.key}: a log-scale parameter needs lower > 0")


@dataclass(frozen=True)
class ViscosityModel:
    """A registered viscosity model ``eta(gamma; params)`` (kPa s, gamma in 1/s)."""

    key: str
    name: str
    equation: str
    parameters: tuple[Parameter, ...]
    function: Callable[..., ArrayLike]
    finite_zero_shear: bool
    reference: str

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(p.key for p in self.parameters)

    def parameter(self, key: str) -> Parameter:
        return next(p for p in self.parameters if p.key == key)

    def __call__(self, gamma: ArrayLike, params: Mapping[str, float]) -> ArrayLike:
        return self.function(gamma, **{k: params[k] for k in self.keys})


_MODELS: dict[str, ViscosityModel] = {}


def viscosity_model(
    key: str,
    *,
    name: str,
    equation: str,
    parameters: tuple[Parameter, ...],
    finite_zero_shear: bool,
    reference: str,
) -> Callable[[Callable[..., ArrayLike]], Callable[..., ArrayLike]]:
    """Register ``function(gamma, **params)`` as the viscosity model ``key``."""

    def register(function: Callable[..., ArrayLike]) -> Callable[..., ArrayLike]:
        if key in _MODELS:
            raise ValueError(f"viscosity model {key!r} is already registered")
        _MODELS[key] = ViscosityModel(
            key, name, equation, parameters, function, finite_zero_shear, reference
        )
        return function

    return register


def viscosity_models() -> Mapping[str, ViscosityModel]:
    """All registered models, read-only."""
    return MappingProxyType(_MODELS)


def get_model(key: str, source: str = "viscosity model") -> ViscosityModel:
    """The model ``key``; an unknown key raises :class:`InputError` listing the known ones."""
    if key not in _MODELS:
        raise InputError(source, "model", f"one of {', '.join(sorted(_MODELS))}", got=key)
    return _MODELS[key]


# Parameter records shared by several models (same key, same unit everywhere).
ETA0 = Parameter("eta0", "kPa s", 1e-12, 1e6, True, "zero-shear viscosity")
ETA_INF = Parameter("eta_inf", "kPa s", 1e-15, 1e6, True, "infinite-shear viscosity")
TIME = Parameter("time_constant", "s", 1e-9, 1e9, True, "relaxation time; 1/time is the onset rate")
N_INDEX = Parameter("n", "1", 1e-3, 1.5, False, "power-law index (n < 1: shear-thinning)")


@viscosity_model(
    "newtonian",
    name="Newtonian",
    equation="eta = mu",
    parameters=(Parameter("mu", "kPa s", 1e-15, 1e6, True, "dynamic viscosity"),),
    finite_zero_shear=True,
    reference="",
)
def newtonian(gamma: ArrayLike, mu: float) -> ArrayLike:
    """``eta = mu`` (kPa s), independent of the shear rate."""
    return mu + 0.0 * gamma


@viscosity_model(
    "power_law",
    name="Power law (Ostwald-de Waele)",
    equation="eta = K gamma^(n-1)",
    parameters=(
        Parameter("consistency", "kPa s^n", 1e-15, 1e6, True, "consistency K"),
        N_INDEX,
    ),
    finite_zero_shear=False,
    reference="Bird, Armstrong, Hassager, Dynamics of Polymeric Liquids, vol. 1 (1987)",
)
def power_law(gamma: ArrayLike, consistency: float, n: float) -> ArrayLike:
    """``eta = K gamma^(n-1)``; K in kPa s^n, gamma in 1/s. Unbounded as gamma -> 0."""
    return consistency * gamma ** (n - 1.0)


@viscosity_model(
    "carreau",
    name="Carreau",
    equation="eta = eta_inf + (eta0 - eta_inf) [1 + (lambda gamma)^2]^((n-1)/2)",
    parameters=(ETA0, ETA_INF, TIME, N_INDEX),
    finite_zero_shear=True,
    reference="Carreau, Trans. Soc. Rheol. 16 (1972) 99",
)
def carreau(
    gamma: ArrayLike, eta0: float, eta_inf: float, time_constant: float, n: float
) -> ArrayLike:
    """``eta = eta_inf + (eta0 - eta_inf) [1 + (lambda gamma)^2]^((n-1)/2)`` (kPa s)."""
    return eta_inf + (eta0 - eta_inf) * (1.0 + (time_constant * gamma) ** 2) ** ((n - 1.0) / 2.0)


@viscosity_model(
    "carreau_yasuda",
    name="Carreau-Yasuda",
    equation="eta = eta_inf + (eta0 - eta_inf) [1 + (lambda gamma)^a]^((n-1)/a)",
    parameters=(
        ETA0,
        ETA_INF,
        TIME,
        N_INDEX,
        Parameter("a", "1", 0.1, 10.0, True, "Yasuda transition exponent (a = 2: Carreau)"),
    ),
    finite_zero_shear=True,
    reference="Yasuda, Armstrong, Cohen, Rheol. Acta 20 (1981) 163",
)
def carreau_yasuda(
    gamma: ArrayLike, eta0: float, eta_inf: float, time_constant: float, n: float, a: float
) -> ArrayLike:
    """``eta = eta_inf + (eta0 - eta_inf) [1 + (lambda gamma)^a]^((n-1)/a)`` (kPa s)."""
    return eta_inf + (eta0 - eta_inf) * (1.0 + (time_constant * gamma) ** a) ** ((n - 1.0) / a)


@viscosity_model(
    "cross",
    name="Cross",
    equation="eta = eta_inf + (eta0 - eta_inf) / [1 + (lambda gamma)^m]",
    parameters=(
        ETA0,
        ETA_INF,
        TIME,
        Parameter("m", "1", 1e-3, 2.0, False, "Cross rate exponent (m ~ 1 - n)"),
    ),
    finite_zero_shear=True,
    reference="Cross, J. Colloid Sci. 20 (1965) 417",
)
def cross(
    gamma: ArrayLike, eta0: float, eta_inf: float, time_constant: float, m: float
) -> ArrayLike:
    """``eta = eta_inf + (eta0 - eta_inf) / [1 + (lambda gamma)^m]`` (kPa s)."""
    return eta_inf + (eta0 - eta_inf) / (1.0 + (time_constant * gamma) ** m)


@dataclass(frozen=True)
class Rheology:
    """A viscosity model bound to parameter values (internal units), checked on creation.

    ``source`` names where the values came from (a file, a fit) for error messages.
    """

    model: ViscosityModel
    params: Mapping[str, float]
    source: str = field(default="rheology", compare=False)

    def __post_init__(self) -> None:
        missing = set(self.model.keys) - set(self.params)
        extra = set(self.params) - set(self.model.keys)
        if missing or extra:
            bad = sorted(missing or extra)[0]
            raise InputError(
                self.source,
                f"{self.model.key}.{bad}",
                f"exactly the parameters {', '.join(self.model.keys)}",
            )
        for p in self.model.parameters:
            value = self.params[p.key]
            if not (math.isfinite(value) and p.lower <= value <= p.upper):
                raise InputError(
                    self.source,
                    f"{self.model.key}.{p.key}",
                    f"a value in [{p.lower:g}, {p.upper:g}] {p.unit}",
                    got=value,
                )
        object.__setattr__(self, "params", MappingProxyType(dict(self.params)))

    @classmethod
    def of(cls, key: str, source: str = "rheology", **params: float) -> Rheology:
        """``Rheology.of("carreau", eta0=..., ...)``."""
        return cls(get_model(key, source), params, source)

    def viscosity(self, gamma: ArrayLike) -> ArrayLike:
        """eta(gamma) in kPa s; gamma in 1/s."""
        return self.model(gamma, self.params)

    def stress(self, gamma: ArrayLike) -> ArrayLike:
        """Shear stress ``tau = eta(gamma) gamma`` in kPa."""
        return self.viscosity(gamma) * gamma

    def viscosity_slope(self, gamma: np.ndarray, floor: float = 1e-12) -> np.ndarray:
        """``(d eta / d gamma) / gamma`` in kPa s^3 by a complex-step derivative.

        gamma is floored at ``floor`` 1/s, where the ratio has its finite limit for models with
        a finite zero-shear viscosity. Used by Newton's method on the duct-flow problem.
        """
        g = np.maximum(np.asarray(gamma, dtype=float), floor)
        step = 1e-30 * g
        return np.imag(self.model(g + 1j * step, self.params)) / step / g

    def shear_rate(self, tau: float) -> float:
        """Shear rate (1/s) at shear stress ``tau`` (kPa): the root of ``eta(g) g = tau``.

        Solved by Brent's method on ``ln g`` over shear rates ``e^-100 .. e^100`` 1/s; ``tau
        eta`` must be increasing in g, true for every registered model with n > 0 or
        eta_inf > 0. Below that range the flow is linear (``g = tau / eta(e^-100)``); a stress
        above it is an :class:`InputError` naming the largest stress solved.
        """
        if tau == 0.0:
            return 0.0
        log_tau = math.log(tau)

        def gap(s: float) -> float:
            return math.log(float(self.stress(math.exp(s)))) - log_tau

        if gap(-100.0) > 0:
            return tau / (float(self.stress(math.exp(-100.0))) / math.exp(-100.0))
        if gap(100.0) < 0:
            raise InputError(
                self.source,
                "shear stress",
                f"at most {float(self.stress(math.exp(100.0))):.3g} kPa (a shear rate of "
                "e^100 1/s)",
                got=tau,
            )
        return math.exp(brentq(gap, -100.0, 100.0, xtol=1e-14, rtol=1e-14))
