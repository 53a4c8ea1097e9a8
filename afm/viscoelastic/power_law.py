"""Power-law rheology: a relaxation modulus without a time scale.

.. math::

    E(t) = E_0 (t / t_0)^{-\\beta}, \\qquad
    \\Phi(t) = \\int_0^t E(u)\\,du = E_0 t_0 \\frac{(t/t_0)^{1-\\beta}}{1-\\beta}

E0 modulus at the reference time [kPa], t0 reference time [s] (fixed, 1 s unless given; E0
depends on it, beta does not), beta power-law exponent [1], 0 <= beta < 1 (0: elastic solid,
1: Newtonian liquid). Integrable at t = 0 for beta < 1, so the discrete convolution is exact
for an indentation history linear between samples.

Reference: B. Fabry et al., Phys. Rev. Lett. 87 (2001) 148102; Ting's method with it:
Y. M. Efremov et al., Sci. Rep. 7 (2017) 1541.
"""

from __future__ import annotations

import numpy as np

from afm.viscoelastic.kernel import relaxation_model

MAX_BETA = 0.95
"""Largest exponent fitted (at 1 the modulus is no longer integrable at t = 0)."""


def basis(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(t/t0)^-beta, theta = (beta, t0)."""
    beta, t0 = float(theta[0]), float(theta[1])
    with np.errstate(divide="ignore"):
        return (np.asarray(t, dtype=float) / t0)[:, None] ** -beta


@relaxation_model(
    "power_law",
    name="power-law rheology",
    equation="E(t) = E0 (t/t0)^-beta",
    amplitudes=("E0_kPa",),
    nonlinear=(("beta", "1"), ("t0_s", "s")),
    basis=basis,
    reference="Fabry et al. 2001, PRL 87:148102; Efremov et al. 2017, Sci. Rep. 7:1541",
)
def integrals(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Phi(t)/E0 = t0 (t/t0)^(1-beta) / (1-beta), s."""
    beta, t0 = float(theta[0]), float(theta[1])
    t = np.clip(np.asarray(t, dtype=float), 0.0, None)
    return (t0 * (t / t0) ** (1.0 - beta) / (1.0 - beta))[:, None]
