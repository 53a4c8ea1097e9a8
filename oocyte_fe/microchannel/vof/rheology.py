"""The project's viscosity models as OpenFOAM's kinematic ``transportModel`` coefficients.

OpenFOAM (v1912, ``viscosityModels``) works with the kinematic viscosity ``nu = eta / rho``
(m^2/s) and the strain rate ``gamma = sqrt(2) |symm(grad U)|`` (1/s; ``du/dy`` in simple
shear, the project's shear rate)::

    BirdCarreau:    nu = nuInf + (nu0 - nuInf) [1 + (k gamma)^a]^((n - 1)/a)    (a = 2: Carreau)
    CrossPowerLaw:  nu = nuInf + (nu0 - nuInf) / [1 + (m gamma)^n]

so the registry's ``carreau`` (eta0, eta_inf, lambda, n) maps to BirdCarreau (eta0/rho,
eta_inf/rho, k = lambda, n, a = 2), ``carreau_yasuda`` adds ``a``, and ``cross`` (eta0, eta_inf,
lambda, m) maps to CrossPowerLaw (nu0, nuInf, m = lambda, n = m). Densities come in
nN s^2/um^4 and viscosities in kPa s (internal units); the coefficients go out in SI.

**Capping the zero-shear viscosity.** :func:`cap_zero_shear` lowers eta0 to a cap ``c`` while
keeping the high-rate branch ``(eta0 - eta_inf) (lambda gamma)^(n-1)`` of a Carreau(-Yasuda)
curve: ``lambda' = lambda ((eta0 - eta_inf) / (c - eta_inf))^(1/(n-1))``. The capped curve
equals the original to within 1 % wherever the original is below about ``c / 2``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.units import DENSITY, VISCOSITY
from oocyte_fe.microchannel.viscosity import Rheology

# internal (kPa s) / (nN s^2/um^4) -> SI (Pa s) / (kg/m^3) = m^2/s
_KPA_S = 1.0 / VISCOSITY["Pa_s"]
_RHO = 1.0 / DENSITY["kg_m3"]


@dataclass(frozen=True)
class FoamViscosity:
    """One phase's OpenFOAM ``transportModel`` and its coefficients (SI, kinematic)."""

    model: str  # "Newtonian", "BirdCarreau" or "CrossPowerLaw"
    coeffs: dict[str, float]

    def nu(self, gamma: np.ndarray) -> np.ndarray:
        """Kinematic viscosity (m^2/s) at strain rate ``gamma`` (1/s), OpenFOAM's formula."""
        g = np.asarray(gamma, dtype=float)
        c = self.coeffs
        if self.model == "Newtonian":
            return c["nu"] + 0.0 * g
        if self.model == "BirdCarreau":
            a = c.get("a", 2.0)
            return c["nuInf"] + (c["nu0"] - c["nuInf"]) * (1.0 + (c["k"] * g) ** a) ** (
                (c["n"] - 1.0) / a
            )
        return c["nuInf"] + (c["nu0"] - c["nuInf"]) / (1.0 + (c["m"] * g) ** c["n"])


def foam_viscosity(rheology: Rheology, density: float) -> FoamViscosity:
    """OpenFOAM coefficients of ``rheology`` (internal units) for a phase of ``density``
    (nN s^2/um^4). Models OpenFOAM has no counterpart for raise :class:`InputError`."""
    p = rheology.params
    to_nu = _KPA_S / (density * _RHO)
    key = rheology.model.key
    if key == "newtonian":
        return FoamViscosity("Newtonian", {"nu": p["mu"] * to_nu})
    if key in ("carreau", "carreau_yasuda"):
        coeffs = {
            "nu0": p["eta0"] * to_nu,
            "nuInf": p["eta_inf"] * to_nu,
            "k": p["time_constant"],
            "n": p["n"],
            "a": p.get("a", 2.0),
        }
        return FoamViscosity("BirdCarreau", coeffs)
    if key == "cross":
        coeffs = {
            "nu0": p["eta0"] * to_nu,
            "nuInf": p["eta_inf"] * to_nu,
            "m": p["time_constant"],
            "n": p["m"],
        }
        return FoamViscosity("CrossPowerLaw", coeffs)
    raise InputError(
        rheology.source, "model", "newtonian, carreau, carreau_yasuda or cross for OpenFOAM", key
    )


def cap_zero_shear(rheology: Rheology, cap: float) -> Rheology:
    """The Carreau(-Yasuda) ``rheology`` with eta0 lowered to ``cap`` (kPa s), the high-rate
    power-law branch kept (module docstring). Returned unchanged when eta0 <= cap."""
    p = dict(rheology.params)
    if rheology.model.key not in ("carreau", "carreau_yasuda"):
        raise InputError(rheology.source, "model", "a Carreau model to cap", rheology.model.key)
    if p["eta0"] <= cap:
        return rheology
    if cap <= p["eta_inf"]:
        raise InputError(rheology.source, "zero_shear_cap", "a cap above eta_inf", cap)
    ratio = (p["eta0"] - p["eta_inf"]) / (cap - p["eta_inf"])
    p["time_constant"] = p["time_constant"] * ratio ** (1.0 / (p["n"] - 1.0))
    p["eta0"] = cap
    return Rheology(rheology.model, p, rheology.source)
