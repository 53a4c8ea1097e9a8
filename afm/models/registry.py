"""The indentation-model registry: one dict, filled by the :func:`indentation_model` decorator.

Every model is a power of the indentation (or, generally, ``E`` times a shape function)::

    F(delta) = E * shape(delta; geometry, nu)        [F] = nN, [E] = kPa, [delta] = um

so the fit treats ``E`` linearly and needs only ``shape`` and its derivative ``dshape``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from oocyte_fe.checks import number
from oocyte_fe.errors import InputError

ShapeFunction = Callable[[np.ndarray, Mapping[str, float], float], np.ndarray]


@dataclass(frozen=True)
class Parameter:
    """One model parameter: its key, unit (internal system) and admissible interval.

    The interval is open, ``(lower, upper)``, or ``(lower, upper]`` with ``upper_inclusive``.
    ``default`` (if any) is used when a geometry leaves the parameter out.
    """

    key: str
    unit: str
    lower: float
    upper: float
    description: str
    upper_inclusive: bool = False
    default: float | None = None

    def check(self, value: float, where: str = "<input>") -> float:
        """Return ``value`` as float, or raise :class:`afm.errors.InputError`."""
        close = "]" if self.upper_inclusive else ")"
        expected = f"a value in ({self.lower:g}, {self.upper:g}{close} {self.unit}"
        value = number(where, self.key, value, expected=expected)
        below = value <= self.upper if self.upper_inclusive else value < self.upper
        if not (math.isfinite(value) and self.lower < value and below):
            raise InputError(where, self.key, expected, value)
        return value


@dataclass(frozen=True)
class IndentationModel:
    """A registered tip model.

    ``shape(delta, geometry, nu)`` is ``F/E`` in nN/kPa = um^2 for ``delta >= 0``;
    ``dshape`` its derivative in ``delta``. ``geometry`` holds the tip parameters named in
    ``geometry_parameters``. ``exponent`` is the power of delta for power-law models.
    """

    key: str
    name: str
    equation: str
    geometry_parameters: tuple[Parameter, ...]
    shape: ShapeFunction
    dshape: ShapeFunction
    exponent: float
    reference: str

    def check_geometry(self, geometry: Mapping[str, float], where: str = "<input>") -> dict:
        """Validated geometry: every parameter present and inside its bounds, no extra keys."""
        known = {p.key for p in self.geometry_parameters}
        if not isinstance(geometry, Mapping):
            raise InputError(where, "geometry", f"a table of {sorted(known)}", geometry)
        extra = sorted(set(geometry) - known)
        if extra:
            raise InputError(where, extra[0], f"a geometry key of {self.key}: {sorted(known)}")
        out = {}
        for p in self.geometry_parameters:
            value = geometry.get(p.key, p.default)
            if value is None:
                raise InputError(where, p.key, f"this geometry key for model {self.key}")
            out[p.key] = p.check(value, where)
        return out

    def force(
        self, delta_um: np.ndarray, E_kPa: float, geometry: Mapping[str, float], nu: float
    ) -> np.ndarray:
        """Force in nN at indentation ``delta_um`` (zero where ``delta <= 0``)."""
        delta = np.clip(np.asarray(delta_um, dtype=float), 0.0, None)
        return E_kPa * self.shape(delta, geometry, nu)


# Parameters shared by all models; a style test checks that keys keep one unit everywhere.
YOUNGS_MODULUS = Parameter("E", "kPa", 0.0, math.inf, "Young's modulus")
CONTACT_POINT = Parameter("contact_point", "um", -math.inf, math.inf, "tip position at contact")
POISSON_RATIO = Parameter("nu", "1", -1.0, 0.5, "Poisson ratio", upper_inclusive=True)
FIT_PARAMETERS = (YOUNGS_MODULUS, CONTACT_POINT)

MODELS: dict[str, IndentationModel] = {}


def indentation_model(
    key: str,
    *,
    name: str,
    equation: str,
    geometry: tuple[Parameter, ...],
    dshape: ShapeFunction,
    exponent: float,
    reference: str,
) -> Callable[[ShapeFunction], ShapeFunction]:
    """Register ``shape`` (the decorated function) as the model ``key``."""

    def register(shape: ShapeFunction) -> ShapeFunction:
        if key in MODELS:
            raise ValueError(f"indentation model {key!r} is registered twice")
        MODELS[key] = IndentationModel(
            key, name, equation, geometry, shape, dshape, exponent, reference
        )
        return shape

    return register


def get_model(key: str, where: str = "<input>") -> IndentationModel:
    """Look a model up by key; an unknown key names the known ones."""
    if not isinstance(key, str) or key not in MODELS:
        raise InputError(where, "model", f"one of {', '.join(sorted(MODELS))}", key)
    return MODELS[key]
