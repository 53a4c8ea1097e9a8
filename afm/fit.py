"""Fitting an indentation model to a force curve: Young's modulus and contact point.

With the baseline removed and the tip-sample separation applied, the model is

    F(x) = E * shape(x - x0)   for x > x0,   0 otherwise          [nN]

x tip position [um] (``piezo - F/k``), x0 contact point [um], E Young's modulus [kPa], ``shape``
the registered tip model (:mod:`afm.models`). The fit is a two-parameter least squares
(Levenberg-Marquardt with the 2 x 2 normal equations in closed form and the analytic Jacobian
``dF/dE = shape``, ``dF/dx0 = -E dshape``; scipy's bounded trust region reflective if it fails
or leaves E > 0 or the data range; a fit ending on those bounds is rated poor) over all points
of the fit window: the non-contact points pin the contact point, the contact points the
modulus. The baseline is refitted on the points before the fitted contact and the model
refitted while the baseline line reached past it (at most ``MAX_BASELINE_PASSES`` fits).
With ``contact_method = "deviation"`` x0 is fixed at the deviation estimate and E is the
linear least-squares solution.

The fit window keeps every point before contact and, in contact, the points up to
``max_indentation_um`` past the contact estimate or up to ``max_force_fraction`` of the maximum
force (whichever ends first; all points when neither is given).

Every point of the window counts equally; nanite (and :mod:`afm.nanite_pipeline`) weights the
residuals near the contact point less and fits a constant baseline offset with the model,
which on real curves changes E by up to 9x where its weighted fit takes another contact point
(docs/afm.md, "The default analysis against nanite").
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.optimize import least_squares

from afm.baseline import Baseline, baseline_before, fit_baseline, remove_baseline
from afm.contact_point import check_method, deviation_index
from afm.curve import ForceCurve
from afm.models import POISSON_RATIO, IndentationModel, get_model
from afm.numerics import dot
from oocyte_fe.checks import number, positive
from oocyte_fe.errors import InputError

MIN_CONTACT_POINTS = 5
GOOD_R_SQUARED = 0.95
MAX_MODULUS_SPREAD = 0.3
"""Largest change of E(delta) with depth rated good: max / min - 1 of its medians over
``MODULUS_BINS`` depth bins (:attr:`IndentationFit.modulus_profile`)."""
MODULUS_BINS = 6
MAX_SYSTEMATIC_RESIDUAL = 0.1
"""Largest mean residual over any of ``RESIDUAL_BINS`` depth bins of the contact points rated
good, as a fraction of the largest fitted force (the model missing the curve's shape)."""
RESIDUAL_BINS = 8
MAX_SNAP_IN = 0.1
"""Largest dip below zero force just before contact rated good, as a fraction of the largest
fitted force (an attractive snap-in the contact models do not hold)."""
SNAP_IN_NOISE_SDS = 5.0
"""A dip counts as snap-in only when it is also deeper than this many baseline noise SDs."""
MAX_BASELINE_PASSES = 4
"""Fits at most: the first, then refits while the baseline reaches past the contact found."""
BASELINE_MARGIN = 0.1
LM_MAX_ITERATIONS = 200
MAX_MAGNITUDE = 1e12
"""Largest |piezo| [um] and |force| [nN] accepted: beyond it the column's unit is wrong."""


@dataclass(frozen=True)
class FitRange:
    """Which contact points to fit: by indentation depth [um] and/or fraction of max force."""

    max_indentation_um: float | None = None
    max_force_fraction: float | None = None

    def __post_init__(self) -> None:
        d, f = self.max_indentation_um, self.max_force_fraction
        if d is not None:
            d = positive("<input>", "max_indentation_um", d, expected="a positive depth in um")
        if f is not None:
            f = number("<input>", "max_force_fraction", f, expected="a fraction in (0, 1]")
            if not 0 < f <= 1:
                raise InputError("<input>", "max_force_fraction", "a fraction in (0, 1]", f)
        object.__setattr__(self, "max_indentation_um", d)
        object.__setattr__(self, "max_force_fraction", f)


@dataclass(frozen=True)
class IndentationFit:
    """Result of :func:`fit_indentation` (arrays cover the fit window).

    The rating and the figures it uses are computed once, on first use (and travel with
    the fit when it is pickled).
    """

    model: str
    E_kPa: float
    contact_point_um: float
    contact_method: str
    nu: float
    geometry: Mapping[str, float]
    residual_rms_nN: float
    r_squared: float
    n_contact_points: int
    success: bool
    message: str
    baseline: Baseline
    tip_position_um: np.ndarray
    force_nN: np.ndarray
    offset_nN: float = 0.0
    height_channel: str = ""
    """Recorded column the tip position came from (:attr:`afm.curve.ForceCurve.height_channel`)."""
    at_bound: tuple[str, ...] = ()
    """Fit parameters that ended on a bound of the fit (each lowers the quality rating)."""

    @property
    def indentation_um(self) -> np.ndarray:
        """delta = x - x0 over the fit window, um (negative before contact)."""
        return self.tip_position_um - self.contact_point_um

    @property
    def fitted_force_nN(self) -> np.ndarray:
        """Model force over the fit window, nN."""
        model = get_model(self.model)
        return self.offset_nN + model.force(self.indentation_um, self.E_kPa, self.geometry, self.nu)

    @cached_property
    def peak_force_nN(self) -> float:
        """Largest fitted force over the window, baseline offset removed, nN."""
        return float(np.max(self.fitted_force_nN - self.offset_nN))

    @cached_property
    def max_indentation_um(self) -> float:
        """Largest indentation delta of the fit window, um (0 without contact)."""
        return max(float(self.indentation_um.max()), 0.0)

    @cached_property
    def modulus_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """E(delta) by depth: (bin centres [um], medians of E(delta) [kPa]) over
        ``MODULUS_BINS`` equal bins from 10 % to 100 % of the largest indentation (NaN for a
        bin of fewer than 3 points). Flat where the model holds."""
        depth = self.max_indentation_um
        delta, modulus = self.pointwise_modulus(0.1 * depth)
        edges = np.linspace(0.1 * depth, depth, MODULUS_BINS + 1)
        which = np.clip(np.searchsorted(edges, delta, side="left") - 1, 0, MODULUS_BINS - 1)
        medians = np.array(
            [
                float(np.median(modulus[which == b]))
                if np.count_nonzero(which == b) >= 3
                else math.nan
                for b in range(MODULUS_BINS)
            ]
        )
        return 0.5 * (edges[1:] + edges[:-1]), medians

    @cached_property
    def modulus_spread(self) -> float:
        """max / min - 1 of :attr:`modulus_profile` (how much E(delta) changes with depth);
        NaN unless every bin has a positive median."""
        medians = self.modulus_profile[1]
        if not np.all(medians > 0):
            return math.nan
        return float(medians.max() / medians.min() - 1.0)

    @cached_property
    def systematic_residual(self) -> float:
        """max_b |mean(F - F_fit) over bin b| / max(F_fit): the contact points cut by depth
        into ``RESIDUAL_BINS`` bins of equal count (noise averages out, a wrong shape does
        not); NaN with fewer points than bins."""
        delta = self.indentation_um
        contact = delta > 0
        peak = self.peak_force_nN
        if np.count_nonzero(contact) < RESIDUAL_BINS or not peak > 0:
            return math.nan
        residual = (self.force_nN - self.fitted_force_nN)[contact][np.argsort(delta[contact])]
        means = [float(b.mean()) for b in np.array_split(residual, RESIDUAL_BINS)]
        return max(abs(m) for m in means) / peak

    @cached_property
    def snap_in_nN(self) -> float:
        """Lowest force (baseline removed) over the approach within 10 % of the largest
        indentation before contact, nN (0 when it stays above zero)."""
        delta = self.indentation_um
        before = (delta <= 0) & (delta > -0.1 * self.max_indentation_um)
        if not before.any():
            return 0.0
        return min(float(np.min(self.force_nN[before] - self.offset_nN)), 0.0)

    @cached_property
    def poor_reasons(self) -> tuple[str, ...]:
        """Why the fit is rated poor, one phrase per criterion failed (empty: good).

        Criteria: the fit converged and no parameter ended on a bound; at least 20 points in
        contact; R^2 >= ``GOOD_R_SQUARED``; no systematic residual above
        ``MAX_SYSTEMATIC_RESIDUAL``; no snap-in deeper than ``MAX_SNAP_IN`` of the largest
        force (and ``SNAP_IN_NOISE_SDS`` noise SDs); E(delta) changing with depth by at most
        ``MAX_MODULUS_SPREAD``.
        """
        reasons = []
        if not self.success:
            reasons.append(self.message)
        if self.at_bound:
            reasons.append(f"{', '.join(self.at_bound)} at a bound of the fit")
        if self.n_contact_points < 4 * MIN_CONTACT_POINTS:
            reasons.append(f"only {self.n_contact_points} points in contact")
        if not self.r_squared >= GOOD_R_SQUARED:
            reasons.append(f"R^2 = {self.r_squared:.3f} < {GOOD_R_SQUARED}")
        systematic = self.systematic_residual
        if systematic > MAX_SYSTEMATIC_RESIDUAL:
            reasons.append(
                f"systematic residual {100 * systematic:.0f} % of the peak force "
                f"(> {100 * MAX_SYSTEMATIC_RESIDUAL:g} %: the model misses the curve's shape)"
            )
        peak = self.peak_force_nN
        snap = self.snap_in_nN
        noise = SNAP_IN_NOISE_SDS * self.baseline.noise_nN
        if peak > 0 and -snap > MAX_SNAP_IN * peak and -snap > noise:
            reasons.append(f"snap-in of {snap:.3g} nN at contact ({100 * snap / peak:.0f} %)")
        spread = self.modulus_spread
        if spread > MAX_MODULUS_SPREAD:
            centres, medians = self.modulus_profile
            low, high = int(np.argmin(medians)), int(np.argmax(medians))
            reasons.append(
                f"E(delta) changes with depth: {medians[low]:.4g} kPa at {centres[low]:.3g} um, "
                f"{medians[high]:.4g} kPa at {centres[high]:.3g} um (+{100 * spread:.0f} %)"
            )
        return tuple(reasons)

    @cached_property
    def quality(self) -> str:
        """``good``, or ``poor: <reasons>`` (:attr:`poor_reasons`)."""
        reasons = self.poor_reasons
        return "poor: " + "; ".join(reasons) if reasons else "good"

    @cached_property
    def rating(self) -> str:
        """Every figure the rating used: R^2, points in contact, systematic residual, snap-in
        and E(delta) spread, with the reasons of a poor rating first."""
        spread = self.modulus_spread
        trend = f"{100 * spread:.0f} %" if math.isfinite(spread) else "n/a"
        peak = self.peak_force_nN
        snap = round(100 * self.snap_in_nN / peak, 1) + 0.0 if peak > 0 else math.nan  # no -0.0
        figures = (
            f"R^2 {self.r_squared:.3f}, {self.n_contact_points} points in contact, "
            f"systematic residual {100 * self.systematic_residual:.1f} %, "
            f"snap-in {snap:.1f} %, E(delta) spread {trend}"
        )
        return f"{self.quality} ({figures})"

    def pointwise_modulus(self, min_indentation_um: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """E(delta) = (F - offset) / shape(delta) at each contact point: (delta [um], E [kPa]).

        Constant where the model holds; a trend with depth shows where it does not (substrate,
        tip shape, non-linearity). Points with delta <= ``min_indentation_um`` are left out.
        """
        model = get_model(self.model)
        delta = self.indentation_um
        keep = delta > max(min_indentation_um, 0.0)
        shape = model.shape(delta[keep], self.geometry, self.nu)
        return delta[keep], (self.force_nN[keep] - self.offset_nN) / shape


def _contact_stats(
    force: np.ndarray, fitted: np.ndarray, in_contact: np.ndarray
) -> tuple[float, float]:
    residual = force - fitted
    rms = float(np.sqrt(np.mean(residual**2)))
    f = force[in_contact]
    ss_tot = float(np.sum((f - f.mean()) ** 2))
    ss_res = float(np.sum(residual[in_contact] ** 2))
    r2 = 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan")
    return rms, r2


def fit_window(
    x: np.ndarray, force: np.ndarray, contact_index: int, fit_range: FitRange, source: str
) -> np.ndarray:
    """Boolean mask of the fit window (module docstring); raises when it is outside the data."""
    keep = np.ones(x.size, dtype=bool)
    x0 = x[contact_index]
    if fit_range.max_indentation_um is not None:
        depth = fit_range.max_indentation_um
        available = float(x[contact_index:].max() - x0)
        if depth > available:
            raise InputError(
                source,
                "max_indentation_um",
                f"a depth within the data (at most {available:.3g} um past contact)",
                depth,
            )
        keep &= x <= x0 + depth
    if fit_range.max_force_fraction is not None:
        above = np.flatnonzero(force > fit_range.max_force_fraction * force.max())
        if above.size:
            keep[above[0] :] = False
    keep[: contact_index + 1] = True
    in_contact = int(np.count_nonzero(keep[contact_index + 1 :]))
    if in_contact < MIN_CONTACT_POINTS:
        if x.size - contact_index - 1 < MIN_CONTACT_POINTS:  # the curve itself, not the range
            raise InputError(
                source,
                "force_nN",
                f"a curve that reaches contact at least {MIN_CONTACT_POINTS} points before the "
                "end of the approach (too few points to fit E)",
                f"{x.size - contact_index - 1} points past the contact estimate",
            )
        raise InputError(
            source,
            "fit range",
            f"at least {MIN_CONTACT_POINTS} points in contact inside it",
            f"{in_contact} points",
        )
    return keep


def fit_contact_power(
    x: np.ndarray,
    force: np.ndarray,
    model: IndentationModel,
    geometry: Mapping[str, float],
    nu: float,
    x0_guess: float,
    free_contact: bool = True,
) -> tuple[float, float, bool, str]:
    """Least squares of ``F = E shape(x - x0)``: returns (E, x0, success, message)."""
    delta0 = np.clip(x - x0_guess, 0.0, None)
    s0 = model.shape(delta0, geometry, nu)
    e_guess = float(dot(force, s0) / dot(s0, s0))
    if not free_contact:
        return e_guess, x0_guess, bool(e_guess > 0), "linear least squares"

    def residual(p: np.ndarray) -> np.ndarray:
        return p[0] * model.shape(np.clip(x - p[1], 0.0, None), geometry, nu) - force

    def jacobian(p: np.ndarray) -> np.ndarray:
        delta = np.clip(x - p[1], 0.0, None)
        jac = np.empty((x.size, 2))
        jac[:, 0] = model.shape(delta, geometry, nu)
        jac[:, 1] = -p[0] * model.dshape(delta, geometry, nu)
        return jac

    span = float(np.ptp(x))
    lower, upper = np.array([0.0, x.min() - span]), np.array([np.inf, x.max()])
    e_start = max(e_guess, 1e-12)
    fitted = _levenberg_marquardt(x, force, model, geometry, nu, e_start, x0_guess, span)
    if fitted is not None and lower[0] < fitted[0] and lower[1] < fitted[1] < upper[1]:
        return fitted[0], fitted[1], True, fitted[2]
    # bounded trust region reflective (scipy) if the fast path fails or leaves the box
    result = least_squares(
        residual,
        np.array([e_start, x0_guess]),
        jac=jacobian,
        bounds=(lower, upper),
        x_scale=np.array([e_start, 0.01 * span]),
        method="trf",
    )
    return float(result.x[0]), float(result.x[1]), bool(result.success), result.message


def _levenberg_marquardt(
    x: np.ndarray,
    force: np.ndarray,
    model: IndentationModel,
    geometry: Mapping[str, float],
    nu: float,
    e_start: float,
    x0_start: float,
    span: float,
) -> tuple[float, float, str] | None:
    """Levenberg-Marquardt for (E, x0) with the 2 x 2 normal equations solved in closed form.

    Jacobian columns ``shape(delta)`` and ``-E dshape(delta)``; Marquardt damping
    ``(A + lambda diag A) step = -J^T r``. Converged when a step changes E by < 1e-10
    relative and x0 by < 1e-10 of the x span, or the cost by < 1e-14 relative. Returns
    (E, x0, message), or None when it does not converge (the caller falls back to scipy).
    """

    # sorted by x: the points before x0 contribute their force squared (a prefix sum), only
    # the contact points (a tail slice) need the model
    order = np.argsort(x, kind="stable")
    xs, fs = x[order], force[order]
    prefix = np.concatenate(([0.0], np.cumsum(fs * fs)))

    def evaluate(e: float, x0: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        first = int(np.searchsorted(xs, x0, side="right"))
        delta = xs[first:] - x0
        shape = model.shape(delta, geometry, nu)
        res = e * shape - fs[first:]
        return delta, shape, res, float(prefix[first]) + dot(res, res)

    e, x0 = e_start, x0_start
    delta, shape, res, cost = evaluate(e, x0)
    damping = 1e-3
    for iteration in range(1, LM_MAX_ITERATIONS + 1):
        j1 = -e * model.dshape(delta, geometry, nu)
        a11, a12, a22 = float(dot(shape, shape)), float(dot(shape, j1)), float(dot(j1, j1))
        g1, g2 = float(dot(shape, res)), float(dot(j1, res))
        while True:
            m11, m22 = a11 * (1.0 + damping), a22 * (1.0 + damping)
            det = m11 * m22 - a12 * a12
            if not (np.isfinite(det) and det > 0):
                damping *= 10.0
                if damping > 1e16:
                    return None
                continue
            d_e = -(m22 * g1 - a12 * g2) / det
            d_x = -(m11 * g2 - a12 * g1) / det
            trial = evaluate(e + d_e, x0 + d_x)
            if trial[3] <= cost:
                break
            damping *= 10.0
            if damping > 1e16:
                return e, x0, f"converged (no further decrease) after {iteration} iterations"
        old_cost = cost
        e, x0 = e + d_e, x0 + d_x
        delta, shape, res, cost = trial
        damping = max(damping * 0.1, 1e-12)
        small_step = abs(d_e) <= 1e-10 * abs(e) and abs(d_x) <= 1e-10 * span
        if small_step or old_cost - cost <= 1e-14 * old_cost:
            return e, x0, f"Levenberg-Marquardt converged in {iteration} iterations"
    return None


def _refined_baseline(curve: ForceCurve, baseline: Baseline, x0: float) -> Baseline | None:
    """A baseline ending before contact ``x0`` if the current one reaches past it, else None."""
    piezo = curve.piezo_um
    end = piezo[0] + (1.0 - BASELINE_MARGIN) * (x0 - piezo[0])
    last = piezo[min(baseline.n_points, piezo.size) - 1]
    # refit only when the line reaches past the margin by more than 2 % of the free travel
    if last <= end + 0.02 * (x0 - piezo[0]) or np.count_nonzero(piezo <= end) < 3:
        return None
    return baseline_before(curve, x0, BASELINE_MARGIN)


def fit_indentation(
    curve: ForceCurve,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    fit_range: FitRange | None = None,
    contact_method: str = "fit",
    n_sigma: float = 5.0,
) -> IndentationFit:
    """Fit ``model`` to an approach curve: remove the baseline, find contact, fit E (and x0).

    ``geometry`` holds the tip parameters of the model; left-out ones take the parameter's
    default (the seed's 10 deg half angle for ``sneddon_cone``). Returns an
    :class:`IndentationFit`; bad input raises :class:`afm.errors.InputError` naming
    ``curve.source``.
    """
    if not isinstance(curve, ForceCurve):
        raise InputError("<input>", "curve", "a ForceCurve", type(curve).__name__)
    src = curve.source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    check_method(contact_method, src)
    fit_range = FitRange() if fit_range is None else fit_range
    if not isinstance(fit_range, FitRange):
        raise InputError(src, "fit_range", "a FitRange (or None)", fit_range)
    n_sigma = positive(src, "n_sigma", n_sigma, expected="a positive number of noise SDs")
    for name, values in (("piezo_um", curve.piezo_um), ("force_nN", curve.force_nN)):
        if not float(np.max(np.abs(values))) <= MAX_MAGNITUDE:
            raise InputError(
                src, name, f"values within +-{MAX_MAGNITUDE:g} (check the column's unit)"
            )
    try:
        with np.errstate(all="ignore"):
            fit = _fit_curve(curve, tip, geometry, nu, fit_range, contact_method, n_sigma)
    except (ZeroDivisionError, FloatingPointError, OverflowError, np.linalg.LinAlgError):
        fit = None
    except ValueError as exc:  # scipy's fallback: residuals not finite at the start
        if isinstance(exc, InputError):
            raise
        fit = None
    if fit is None or not all(
        math.isfinite(v) for v in (fit.E_kPa, fit.contact_point_um, fit.residual_rms_nN)
    ):
        raise InputError(
            src,
            "force_nN",
            "a curve the fit resolves to finite numbers (check the units and scale of the "
            "piezo and force columns)",
        )
    return fit


def _fit_curve(
    curve: ForceCurve,
    tip: IndentationModel,
    geometry: Mapping[str, float],
    nu: float,
    fit_range: FitRange,
    contact_method: str,
    n_sigma: float,
) -> IndentationFit:
    """The steps of :func:`fit_indentation` once its arguments are checked."""
    src = curve.source
    model = tip.key
    baseline = fit_baseline(curve)
    x0 = None
    for _ in range(MAX_BASELINE_PASSES):
        corrected = remove_baseline(curve, baseline)
        force = corrected.force_nN
        x = corrected.tip_position_um
        contact = deviation_index(force, baseline.noise_nN, n_sigma, src)
        window = fit_window(x, force, contact, fit_range, src)
        xw, fw = x[window], force[window]
        start = float(x[contact]) if x0 is None or contact_method != "fit" else x0
        E, x0, ok, msg = fit_contact_power(
            xw, fw, tip, geometry, nu, start, free_contact=contact_method == "fit"
        )
        # the baseline must end before the contact found (piezo at contact ~ x0, F = 0 there)
        refined = _refined_baseline(curve, baseline, x0)
        if refined is None:
            break
        baseline = refined
    fitted = E * tip.shape(np.clip(xw - x0, 0.0, None), geometry, nu)
    in_contact = xw > x0
    rms, r2 = _contact_stats(fw, fitted, in_contact)
    span = float(np.ptp(xw))
    tol = 1e-6 * max(span, 1e-300)
    at_bound = tuple(
        name
        for name, hit in (
            ("E = 0", not E > 0),
            ("x0 (lower)", contact_method == "fit" and x0 - (float(xw.min()) - span) <= tol),
            ("x0 (upper)", contact_method == "fit" and float(xw.max()) - x0 <= tol),
        )
        if hit
    )
    return IndentationFit(
        model=model,
        E_kPa=E,
        contact_point_um=x0,
        contact_method=contact_method,
        nu=nu,
        geometry=geometry,
        residual_rms_nN=rms,
        r_squared=r2,
        n_contact_points=int(np.count_nonzero(in_contact)),
        success=ok,
        message=str(msg),
        baseline=baseline,
        tip_position_um=xw,
        force_nN=fw,
        height_channel=curve.height_channel,
        at_bound=at_bound,
    )
