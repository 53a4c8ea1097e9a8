"""nanite's default analysis of a force curve, re-derived: for results comparable with nanite.

nanite (and PyJibe, built on it) is the field's open reference for AFM indentation. Its
default preprocessing and fit, written out here from its documented steps (units um, nN, kPa):

1. tip position ``x = piezo - F/k`` with the force as recorded;
2. force offset: the record is clipped at its largest force (index ``n_max``: the turn, or
   just after it in the retract); the contact index ``i_c`` is the first point where
   ``F - mean(F_b) > 2 max|F_b - mean(F_b)|``, ``F_b`` the first 10 % of the clipped points,
   and ``n_max // 2`` when no point is; ``F <- F - mean(F[:i_c])``;
3. tip offset: ``x <- x - x[i_c]``;
4. least squares of ``F = E shape(x - x0) + b`` over the whole approach, E, x0 and a baseline
   ``b`` free, started from E = 3 kPa, x0 = 0, b = 0, each residual weighted by
   ``min(|x - x0| / w_cp, 1)`` (``w_cp = 1 um``: points near contact count less).

The objective has local minima on some curves (a contact point far into the baseline or the
contact part), so nanite's path to its minimum is followed too: MINPACK's Levenberg-Marquardt
with forward-difference Jacobian (:func:`scipy.optimize.leastsq`, ``epsfcn = 1e-10``,
``ftol = xtol = 1.5e-8``), in SI units (m, N, Pa), with E >= 0 through the bound transform
``E = sqrt(u^2 + 1) - 1`` (F. James, MINUIT manual) that lmfit applies.

:func:`afm.fit.fit_indentation` differs in steps 2-4 (a baseline line, not an offset; no
weights; no free baseline in the fit), so the two agree only as far as the curve allows; use
this route to compare with nanite or to reproduce a nanite/PyJibe analysis.

Reference: P. Müller et al., BMC Bioinformatics 20 (2019) 465 (nanite).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.optimize import leastsq

from afm.baseline import Baseline
from afm.curve import ForceCurve
from afm.fit import IndentationFit
from afm.models import POISSON_RATIO, get_model
from oocyte_fe.errors import InputError

NANITE_WEIGHT_CP_UM = 1.0
"""nanite's default contact-point weight width (``weight_cp = 1e-6`` m)."""
NANITE_E_START_KPA = 3.0
"""nanite's start value for E (3000 Pa)."""


def contact_index_deviation(force_nN: np.ndarray, n_max: int | None = None) -> int:
    """Contact index of step 2 (module docstring); ``n_max`` defaults to the index of the
    largest force of ``force_nN``."""
    force = np.asarray(force_nN, dtype=float)
    n = int(np.argmax(force)) if n_max is None else int(n_max)
    clipped = force[:n]  # the approach's points when the largest force is in the retract
    window = clipped[: int(n * 0.1)]
    if window.size:
        mean = float(window.mean())
        above = np.flatnonzero(clipped - mean > 2.0 * float(np.max(np.abs(window - mean))))
        if above.size:
            return int(above[0])
    return min(n // 2, force.size - 1)


def fit_nanite_default(
    curve: ForceCurve,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    weight_cp_um: float = NANITE_WEIGHT_CP_UM,
    n_max: int | None = None,
) -> IndentationFit:
    """Fit ``curve`` the way nanite does by default (module docstring).

    ``n_max`` is the index of the largest force of the whole record (approach and retract);
    by default the largest force of the approach (the same unless the force still rises
    after the turn).

    In the result, the tip position is ``piezo - (F - offset)/k`` (this package's convention),
    ``contact_point_um`` is on that axis and ``offset_nN`` is the fitted baseline ``b``.
    """
    src = curve.source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    if not (np.isfinite(weight_cp_um) and weight_cp_um > 0):
        raise InputError(src, "weight_cp_um", "a positive width in um", weight_cp_um)
    k = curve.spring_constant_nN_per_um
    raw = curve.force_nN
    contact = contact_index_deviation(raw, n_max)
    offset = float(raw[:contact].mean()) if contact else float(raw[0])
    force = raw - offset
    x_raw = curve.piezo_um - raw / k
    shift = float(x_raw[contact])
    x = x_raw - shift

    # nanite's axis: tip position in m, decreasing towards the sample (afmformats' sign); the
    # forward-difference steps, and so the path of the fit, depend on that sign
    height_m, force_N, w_m = -x * 1e-6, force * 1e-9, weight_cp_um * 1e-6

    def modulus_Pa(u: float) -> float:
        return float(np.sqrt(u * u + 1.0) - 1.0)

    def residual(p: np.ndarray) -> np.ndarray:
        delta_m = p[1] - height_m  # indentation, m (p[1]: contact on nanite's axis)
        shape_um = tip.shape(np.clip(delta_m, 0.0, None) * 1e6, geometry, nu)
        model_N = modulus_Pa(p[0]) * 1e-12 * shape_um + p[2]
        return (force_N - model_N) * np.minimum(np.abs(delta_m) / w_m, 1.0)

    e_start_Pa = NANITE_E_START_KPA * 1e3
    start = np.array([np.sqrt((e_start_Pa + 1.0) ** 2 - 1.0), 0.0, 0.0])
    solution, _, info, message, status = leastsq(
        residual,
        start,
        full_output=True,
        ftol=1.5e-8,
        xtol=1.5e-8,
        gtol=0.0,
        maxfev=2000 * (start.size + 1),
        epsfcn=1e-10,
        factor=100,
    )
    E = modulus_Pa(solution[0]) * 1e-3
    x0, b = -float(solution[1]) * 1e6, float(solution[2]) * 1e9
    converged = status in (1, 2, 3, 4)
    # back to this package's tip position: piezo - (F - offset)/k = x_raw + offset/k
    to_ours = shift + offset / k
    x_ours = x + to_ours
    fitted = E * tip.shape(np.clip(x - x0, 0.0, None), geometry, nu) + b
    in_contact = x > x0
    residual_all = force - fitted
    f = force[in_contact]
    ss_tot = float(np.sum((f - f.mean()) ** 2)) if f.size else 0.0
    r2 = 1.0 - float(np.sum(residual_all[in_contact] ** 2)) / ss_tot if ss_tot > 0 else np.nan
    return IndentationFit(
        model=model,
        E_kPa=E,
        contact_point_um=x0 + to_ours,
        contact_method="nanite default",
        nu=nu,
        geometry=geometry,
        residual_rms_nN=float(np.sqrt(np.mean(residual_all**2))),
        r_squared=float(r2),
        n_contact_points=int(np.count_nonzero(in_contact)),
        success=bool(converged and E > 0),
        message=str(message),
        baseline=Baseline(offset, 0.0, float(np.std(raw[: max(contact, 2)])), max(contact, 1)),
        tip_position_um=x_ours,
        force_nN=force,
        offset_nN=b,
        height_channel=curve.height_channel,
    )
