"""Prony series relaxation modulus (the form the FE and the material file use).

.. math::

    E(t) = E_\\infty + \\sum_i E_i e^{-t/\\tau_i}, \\qquad
    \\Phi(t) = E_\\infty t + \\sum_i E_i \\tau_i (1 - e^{-t/\\tau_i})

E_inf long-time modulus [kPa], E_i relaxing moduli [kPa], tau_i relaxation times [s].
Instantaneous modulus E0 = E_inf + sum E_i; the material file's normalised terms are
g_i = E_i / E0 (with constant nu, the same for the shear modulus G(t) = E(t) / (2 (1 + nu))).
The standard linear solid is the one-term series (:mod:`afm.viscoelastic.standard_linear_solid`).

Reference: the generalised Maxwell model, e.g. N. W. Tschoegl, The Phenomenological Theory of
Linear Viscoelastic Behavior (Springer 1989), ch. 3.
"""

from __future__ import annotations

import numpy as np

from afm.viscoelastic.kernel import relaxation_model

MAX_TERMS = 4


def basis(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """[1, exp(-t/tau_1), ...], theta = tau_i [s]."""
    t = np.asarray(t, dtype=float)[:, None]
    return np.column_stack([np.ones(t.shape[0]), np.exp(-t / np.asarray(theta, float)[None, :])])


@relaxation_model(
    "prony",
    name="Prony series",
    equation="E(t) = E_inf + sum_i E_i exp(-t/tau_i)",
    amplitudes=("E_inf_kPa", "E_i_kPa"),
    nonlinear=(("tau_s", "s"),),
    basis=basis,
    reference="Tschoegl 1989, ch. 3",
)
def integrals(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """[t, tau_i (1 - exp(-t/tau_i))], s."""
    t = np.clip(np.asarray(t, dtype=float), 0.0, None)[:, None]
    tau = np.asarray(theta, float)[None, :]
    return np.column_stack([t[:, 0], -tau * np.expm1(-t / tau)])
