"""The relaxation-modulus registry: one dict, filled by the :func:`relaxation_model` decorator.

Every model is linear in its amplitudes ``A_k`` (kPa) with basis functions that depend on the
non-linear parameters ``theta`` (times in s, exponents)::

    E(t) = sum_k A_k b_k(t; theta)                          [E] = kPa, [t] = s

and registers the basis integrals ``Phi_k(t) = int_0^t b_k(u) du`` (s), which is all Ting's
convolution needs (:mod:`afm.viscoelastic.ting`): with the indentation history piecewise
linear between samples, the convolution weights are exact differences of ``Phi``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from oocyte_fe.errors import InputError

BasisIntegrals = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""``(t [s], theta) -> Phi`` of shape ``(t.size, n_amplitudes)``."""


@dataclass(frozen=True)
class RelaxationModel:
    """A registered relaxation modulus.

    ``amplitudes`` names the linear parameters (kPa), ``nonlinear`` the others with their
    units; ``integrals(t, theta)`` gives Phi_k(t); ``modulus(t, amplitudes, theta)`` E(t).
    ``terms`` is the number of exponential terms (Prony) or 0.
    """

    key: str
    name: str
    equation: str
    amplitudes: tuple[str, ...]
    nonlinear: tuple[tuple[str, str], ...]
    integrals: BasisIntegrals
    basis: BasisIntegrals
    reference: str

    def modulus(self, t_s: np.ndarray, amplitudes: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """E(t) in kPa."""
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        return self.basis(t, np.asarray(theta, dtype=float)) @ np.asarray(amplitudes, float)


RELAXATION_MODELS: dict[str, RelaxationModel] = {}


def relaxation_model(
    key: str,
    *,
    name: str,
    equation: str,
    amplitudes: tuple[str, ...],
    nonlinear: tuple[tuple[str, str], ...],
    basis: BasisIntegrals,
    reference: str,
) -> Callable[[BasisIntegrals], BasisIntegrals]:
    """Register ``integrals`` (the decorated function) as the relaxation model ``key``."""

    def register(integrals: BasisIntegrals) -> BasisIntegrals:
        if key in RELAXATION_MODELS:
            raise ValueError(f"relaxation model {key!r} is registered twice")
        RELAXATION_MODELS[key] = RelaxationModel(
            key, name, equation, amplitudes, nonlinear, integrals, basis, reference
        )
        return integrals

    return register


def get_relaxation_model(key: str, where: str = "<input>") -> RelaxationModel:
    """Look a relaxation model up by key; an unknown key names the known ones."""
    if not isinstance(key, str) or key not in RELAXATION_MODELS:
        raise InputError(where, "relaxation", f"one of {', '.join(sorted(RELAXATION_MODELS))}", key)
    return RELAXATION_MODELS[key]
