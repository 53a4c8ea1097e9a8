"""How far a force curve determines each calibrated NMSD constant (from the Jacobian at the fit).

With the press's forward sensitivities (:mod:`nmsd.sensitivity`) at the calibrated constants,
the Jacobian of the model forces at the N fitted points with respect to the logarithms of the
P constants of the family is ``J_ik = p_k df_i/dp_k`` (nN). To first order the covariance of
``ln p`` is

    C = sigma^2 (J^T J)^+,    sigma^2 = max(SSR / (N - P), (FLOOR f_rms)^2)

with SSR the residual sum of squares of the fit (nN^2), ``f_rms`` the RMS measured force (nN)
and ``FLOOR`` = 0.01: the noise is taken as the residual's, but at least 1 % of the force (on
data fitted to round-off the residual alone would make every error vanish, however little the
force feels a constant). The relative standard error of ``p_k`` is ``sqrt(C_kk)``.

A constant is **not identified** when

- its relative standard error exceeds :data:`MAX_RELATIVE_SE` (1: its one-sigma range spans
  more than a factor e), i.e. it lies on a near-null singular direction of J;
- it loads (``|V_jk| > 1e-3``) on a singular direction of J below 1e-8 of the largest, which
  the pseudo-inverse drops (a constant at 0 has a zero column): infinite error;
- the calibration ended on one of its bounds (0, eq 8's ``k2 = 50 k1``, the bounds of
  ``dl_c`` and ``gap_um``): infinite error.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np

from nmsd.parameters import NmsdParameters
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement

FLOOR = 0.01
"""Least noise assumed, as a fraction of the RMS measured force."""
MAX_RELATIVE_SE = 1.0
"""Largest relative standard error of an identified constant."""
SINGULAR = 1e-8
"""Singular values of J below this fraction of the largest are dropped (pseudo-inverse)."""


@dataclass(frozen=True)
class Identifiability:
    """Relative standard error of each constant (``inf``: undetermined) and those not identified.

    ``why`` gives the reason for each constant not identified; ``sigma_nN`` the noise level
    used (nN); ``singular`` the singular values of J over the largest.
    """

    relative_se: dict[str, float]
    not_identified: tuple[str, ...]
    why: dict[str, str]
    sigma_nN: float
    singular: tuple[float, ...]

    def describe(self, name: str) -> str:
        """``± 12 %`` or ``not identified (reason)`` for one constant."""
        if name in self.why:
            return f"not identified ({self.why[name]})"
        return f"± {100 * self.relative_se[name]:.2g} %"


def identifiability(
    curves: Sequence[tuple[PressSetup, ForceDisplacement]],
    params: NmsdParameters,
    names: Sequence[str],
    gap_um: float = 0.0,
    pinned: Collection[str] = (),
) -> Identifiability:
    """Identifiability of the constants ``names`` (of :data:`nmsd.sensitivity.NAMES`) fitted
    to ``curves`` (each press with its gap already set) at ``params``; ``gap_um`` the gap's
    value when it is among ``names``; ``pinned`` the constants the fit left on a bound."""
    value = {"gap_um": gap_um, **{n: getattr(params, n) for n in names if n != "gap_um"}}
    blocks, residual, measured = [], [], []
    for setup, curve in curves:
        d = curve.displacement_um
        press = setup.run(params, record_um=d, sensitivities=True)
        sens = dict(zip(press.sensitivity_names, press.sensitivity_at(d).T, strict=True))
        blocks.append(np.stack([sens[n] * value[n] for n in names], axis=1))
        residual.append(press.force_at(d) - curve.force_nN)
        measured.append(curve.force_nN)
    jac, res, f = np.vstack(blocks), np.concatenate(residual), np.concatenate(measured)
    n, p = jac.shape
    ssr = float(res @ res)
    floor = FLOOR * float(np.sqrt(np.mean(f**2)))
    sigma = max(np.sqrt(ssr / (n - p)) if n > p else 0.0, floor)
    _, sv, vt = np.linalg.svd(jac, full_matrices=False)
    keep = sv > SINGULAR * sv[0] if sv[0] > 0 else np.zeros(len(sv), dtype=bool)
    cov = (vt[keep].T / sv[keep] ** 2) @ vt[keep] * sigma**2
    relative, why = {}, {}
    for k, name in enumerate(names):
        relative[name] = float(np.sqrt(cov[k, k]))
        if name in pinned:
            relative[name], why[name] = np.inf, "on a bound of the calibration"
        elif np.any(np.abs(vt[~keep, k]) > 1e-3):
            relative[name], why[name] = np.inf, "the force does not depend on it"
        elif relative[name] > MAX_RELATIVE_SE:
            why[name] = f"relative s.e. {relative[name]:.3g} > {MAX_RELATIVE_SE:g}"
    scale = sv[0] if sv[0] > 0 else 1.0
    return Identifiability(
        relative,
        tuple(n for n in names if n in why),
        why,
        float(sigma),
        tuple(float(s / scale) for s in sv),
    )
