"""Pierce-through curves (seed 001, Fig. 3 right): the probe pierces the ZP, enters the cytoplasm.

The approach force rises (ZP), drops when the probe pierces the ZP, and rises again (cytoplasm).
The drop is the first force peak whose prominence (:func:`scipy.signal.find_peaks`) exceeds
``min_drop_fraction`` of the force range. Then:

* ZP: the points up to the peak are fitted like any approach curve (baseline, contact point,
  model), see :func:`afm.fit.fit_indentation`;
* cytoplasm: from the force minimum after the drop to the end, with its own contact reference
  x1 and force level F1::

      F(x) = F1 + E_cyt * shape(x - x1)                              [nN]

  fitted by least squares for (E_cyt, x1, F1), started from the minimum, with x1 bounded to
  [x0 - D/2, end of the segment] (x0 the ZP contact point, D = x_after - x0 the depth at the
  drop, x_after the tip position at the force minimum).

The one model covers both readings of the second segment:

A. the cytoplasm indented from where the tip stood after the drop, F1 the residual force
   carried by the pierced layer: ``F = F_res + E_cyt shape(x - x_after)``, so x1 = x_after;
B. a force increment with the cone keeping its depth (the cytoplasm is indented by the whole
   cone, counted from the original surface): ``F = F_res + E_cyt [shape(x - x0) -
   shape(x_after - x0)]``, so x1 = x0 and F1 = F_res - E_cyt shape(D).

The fitted x1 tells which reading the data follow (near x_after: A; near x0: B). A bound too
close to x_after (the earlier ``x_after - segment length``) clipped reading B when the second
segment was shorter than D and biased E_cyt by up to +25 %. A parameter that ends on a bound
(E_cyt = 0, x1 on either bound) is listed in ``IndentationFit.at_bound`` and makes the rating
poor. The seed paper instead fits both rising segments and subtracts the ZP slope from the
second; that subtraction is not defined precisely enough in the paper to reproduce.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import find_peaks

from afm.baseline import remove_baseline
from afm.curve import ForceCurve
from afm.fit import FitRange, IndentationFit, fit_indentation
from afm.models import MODELS, POISSON_RATIO, IndentationModel, get_model
from oocyte_fe.checks import fraction
from oocyte_fe.errors import InputError

MIN_SEGMENT_POINTS = 10


@dataclass(frozen=True)
class PierceEvent:
    """Where the probe pierced: index of the force peak and of the minimum after it."""

    peak_index: int
    trough_index: int
    peak_force_nN: float
    drop_nN: float


@dataclass(frozen=True)
class PierceFit:
    """Both layers of a pierce-through curve."""

    event: PierceEvent
    zp: IndentationFit
    cytoplasm: IndentationFit


def pierce_model(model: str, where: str = "<input>") -> IndentationModel:
    """The tip ``model`` if a pierce-through fit is defined for it, else :class:`InputError`.

    The cytoplasm segment is fitted as ``F = F1 + E_cyt shape(x - x1)``; for a tip whose
    force is linear in depth (``exponent`` 1: ``flat_punch``) this is ``(F1 - E_cyt s x1) +
    E_cyt s x``, so F1 and x1 are one parameter and the fit is not defined.
    """
    tip = get_model(model, where)
    if tip.exponent <= 1.0:
        usable = ", ".join(k for k, m in sorted(MODELS.items()) if m.exponent > 1.0)
        raise InputError(
            where,
            "model",
            f"a tip for pierce-through curves, one of {usable} (under a force linear in depth "
            "the cytoplasm's contact reference and force level are one parameter)",
            model,
        )
    return tip


def detect_pierce(curve: ForceCurve, min_drop_fraction: float = 0.1) -> PierceEvent:
    """The first force drop larger than ``min_drop_fraction`` of the force range."""
    force = curve.force_nN
    span = float(np.ptp(force))
    peaks, props = find_peaks(force, prominence=min_drop_fraction * span)
    if peaks.size == 0:
        drop = f": largest drop {_largest_drop(force) / span:.2g} of it" if span > 0 else ""
        raise InputError(
            curve.source,
            "force_nN",
            f"a pierce event: a force drop of more than {min_drop_fraction:g} of the force range "
            "(the ZP giving way)",
            f"no pierce detected{drop}",
        )
    peak = int(peaks[0])
    after = force[peak:]
    regained = np.flatnonzero(after > force[peak])
    end = peak + (int(regained[0]) if regained.size else after.size)
    trough = peak + int(np.argmin(force[peak:end]))
    return PierceEvent(peak, trough, float(force[peak]), float(force[peak] - force[trough]))


def _largest_drop(force: np.ndarray) -> float:
    """Largest fall of the force below an earlier maximum, nN."""
    return float(np.max(np.maximum.accumulate(force) - force))


def fit_offset_segment(
    x: np.ndarray,
    force: np.ndarray,
    model: str,
    geometry: Mapping[str, float],
    nu: float,
    source: str = "<input>",
    x1_lower: float | None = None,
) -> tuple[float, float, float, bool, str, tuple[str, ...]]:
    """Fit F = F1 + E shape(x - x1) on a segment starting at its minimum.

    Returns (E, x1, F1, ok, message, parameters at a bound). x1 lies in [``x1_lower``, x_end]
    (``x1_lower`` defaults to x_start - segment length).
    """
    tip = get_model(model, source)
    if x.size < MIN_SEGMENT_POINTS:
        raise InputError(source, "force_nN", f"{MIN_SEGMENT_POINTS} points after the pierce")
    x1_start, f1_start = float(x[0]), float(force[0])
    s0 = tip.shape(np.clip(x - x1_start, 0, None), geometry, nu)
    e_start = max(float(np.dot(force - f1_start, s0) / np.dot(s0, s0)), 1e-9)

    def residual(p: np.ndarray) -> np.ndarray:
        return p[2] + p[0] * tip.shape(np.clip(x - p[1], 0, None), geometry, nu) - force

    def jacobian(p: np.ndarray) -> np.ndarray:
        delta = np.clip(x - p[1], 0, None)
        return np.column_stack(
            [
                tip.shape(delta, geometry, nu),
                -p[0] * tip.dshape(delta, geometry, nu),
                np.ones_like(x),
            ]
        )

    span = float(np.ptp(x))
    scale_f = max(float(np.ptp(force)), 1e-12)
    low = x1_start - span if x1_lower is None else min(float(x1_lower), x1_start)
    high = float(x[-1])
    result = least_squares(
        residual,
        np.array([e_start, x1_start, f1_start]),
        jac=jacobian,
        bounds=([0.0, low, -np.inf], [np.inf, high, np.inf]),
        x_scale=np.array([e_start, 0.01 * span, 0.01 * scale_f]),
        method="trf",
    )
    e, x1, f1 = (float(v) for v in result.x)
    tol = 1e-6 * max(high - low, 1e-12)
    at_bound = tuple(
        name
        for name, hit in (
            ("E_cytoplasm = 0", e <= 1e-9 * e_start),
            ("x1 (lower)", x1 - low <= tol),
            ("x1 (upper)", high - x1 <= tol),
        )
        if hit
    )
    return e, x1, f1, bool(result.success), str(result.message), at_bound


def fit_pierce(
    curve: ForceCurve,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    zp_range: FitRange | None = None,
    min_drop_fraction: float = 0.1,
    contact_method: str = "fit",
) -> PierceFit:
    """Detect the pierce, fit the ZP on the first rising segment and the cytoplasm on the second.

    Refused (:class:`InputError` naming ``curve.source``): a tip for which the cytoplasm fit
    is not defined (:func:`pierce_model`), a curve without a force drop of more than
    ``min_drop_fraction`` of its force range ("no pierce detected"), too few points before
    the drop or after it.
    """
    if not isinstance(curve, ForceCurve):
        raise InputError("<input>", "curve", "a ForceCurve", type(curve).__name__)
    src = curve.source
    tip = pierce_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    min_drop_fraction = fraction(src, "min_drop_fraction", min_drop_fraction)
    event = detect_pierce(curve, min_drop_fraction)
    if event.peak_index < MIN_SEGMENT_POINTS:
        raise InputError(src, "force_nN", "a rising ZP segment before the pierce")
    zp = fit_indentation(
        curve.slice(0, event.peak_index + 1), model, geometry, nu, zp_range, contact_method
    )
    corrected = remove_baseline(curve, zp.baseline)
    second = corrected.slice(event.trough_index, len(curve.piezo_um))
    x, force = second.tip_position_um, second.force_nN
    depth = float(x[0]) - zp.contact_point_um
    try:
        with np.errstate(all="ignore"):
            e, x1, f1, ok, msg, at_bound = fit_offset_segment(
                x, force, model, geometry, nu, src, zp.contact_point_um - 0.5 * max(depth, 0.0)
            )
    except (ZeroDivisionError, FloatingPointError, OverflowError, np.linalg.LinAlgError):
        e = math.nan
    except ValueError as exc:  # scipy: residuals not finite at the start
        if isinstance(exc, InputError):
            raise
        e = math.nan
    if not math.isfinite(e):
        raise InputError(src, "force_nN", "a second segment the fit resolves to finite numbers")
    fitted = f1 + e * tip.shape(np.clip(x - x1, 0, None), geometry, nu)
    residual = force - fitted
    ss_tot = float(np.sum((force - force.mean()) ** 2))
    cytoplasm = IndentationFit(
        model=model,
        E_kPa=e,
        contact_point_um=x1,
        contact_method="fit (offset segment)",
        nu=nu,
        geometry=geometry,
        residual_rms_nN=float(np.sqrt(np.mean(residual**2))),
        r_squared=1.0 - float(np.sum(residual**2)) / ss_tot if ss_tot > 0 else float("nan"),
        n_contact_points=int(np.count_nonzero(x > x1)),
        success=ok,
        message=msg,
        baseline=zp.baseline,
        tip_position_um=x,
        force_nN=force,
        offset_nN=f1,
        at_bound=at_bound,
    )
    return PierceFit(event, zp, cytoplasm)
