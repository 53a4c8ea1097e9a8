"""Standard linear solid (Zener): one spring in parallel with a Maxwell element.

.. math::

    E(t) = E_\\infty + (E_0 - E_\\infty) e^{-t/\\tau}, \\qquad
    \\Phi(t) = E_\\infty t + (E_0 - E_\\infty) \\tau (1 - e^{-t/\\tau})

E0 instantaneous modulus [kPa], E_inf long-time modulus [kPa] (0 < E_inf <= E0), tau
relaxation time at constant strain [s]. The one-term Prony series (:mod:`afm.viscoelastic.prony`)
with E_1 = E0 - E_inf; fitted amplitudes are (E_inf, E_1).

Reference: C. Zener, Elasticity and Anelasticity of Metals (Chicago 1948).
"""

from __future__ import annotations

import numpy as np

from afm.viscoelastic import prony
from afm.viscoelastic.kernel import relaxation_model


def basis(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """[1, exp(-t/tau)], theta = (tau,) [s]."""
    return prony.basis(t, np.asarray(theta, float)[:1])


@relaxation_model(
    "standard_linear_solid",
    name="standard linear solid",
    equation="E(t) = E_inf + (E0 - E_inf) exp(-t/tau)",
    amplitudes=("E_inf_kPa", "E_1_kPa"),
    nonlinear=(("tau_s", "s"),),
    basis=basis,
    reference="Zener 1948",
)
def integrals(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """[t, tau (1 - exp(-t/tau))], s."""
    return prony.integrals(t, np.asarray(theta, float)[:1])
