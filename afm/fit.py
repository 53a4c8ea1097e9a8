"""Fitting an indentation model to a force curve: Young's modulus and contact point.

With the baseline removed and the tip-sample separation applied, the model is

    F(x) = E * shape(x - x0)   for x > x0,   0 otherwise          [nN]

x tip position [um] (``piezo - F/k``), x0 contact point [um], E Young's modulus [kPa], ``shape``
the registered tip model (:mod:`afm.models`). The fit is a two-parameter least squares
(:func:`scipy.optimize.least_squares`, Levenberg-Marquardt, falling back to bounded trust
region reflective if it leaves E > 0 or the data range; analytic Jacobian ``dF/dE = shape``,
``dF/dx0 = -E dshape``) over all points of the fit window: the non-contact
points pin the contact point, the contact points the modulus. With ``contact_method =
"deviation"`` x0 is fixed at the deviation estimate and E is the linear least-squares solution.

The fit window keeps every point before contact and, in contact, the points up to
``max_indentation_um`` past the contact estimate or up to ``max_force_fraction`` of the maximum
force (whichever ends first; all points when neither is given).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from afm.baseline import Baseline, fit_baseline, remove_baseline
from afm.contact_point import check_method, deviation_index
from afm.curve import ForceCurve
from afm.errors import AfmInputError
from afm.models import POISSON_RATIO, IndentationModel, get_model

MIN_CONTACT_POINTS = 5
GOOD_R_SQUARED = 0.95


@dataclass(frozen=True)
class FitRange:
    """Which contact points to fit: by indentation depth [um] and/or fraction of max force."""

    max_indentation_um: float | None = None
    max_force_fraction: float | None = None

    def __post_init__(self) -> None:
        d, f = self.max_indentation_um, self.max_force_fraction
        if d is not None and not (np.isfinite(d) and d > 0):
            raise AfmInputError("<input>", "max_indentation_um", "a positive depth in um", d)
        if f is not None and not (np.isfinite(f) and 0 < f <= 1):
            raise AfmInputError("<input>", "max_force_fraction", "a fraction in (0, 1]", f)


@dataclass(frozen=True)
class IndentationFit:
    """Result of :func:`fit_indentation` (arrays cover the fit window)."""

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

    @property
    def indentation_um(self) -> np.ndarray:
        """delta = x - x0 over the fit window, um (negative before contact)."""
        return self.tip_position_um - self.contact_point_um

    @property
    def fitted_force_nN(self) -> np.ndarray:
        """Model force over the fit window, nN."""
        model = get_model(self.model)
        return self.offset_nN + model.force(self.indentation_um, self.E_kPa, self.geometry, self.nu)

    @property
    def quality(self) -> str:
        """``good``, or ``poor: <reason>`` (fit failed, R^2 < 0.95, too few contact points)."""
        if not self.success:
            return f"poor: {self.message}"
        if self.n_contact_points < 4 * MIN_CONTACT_POINTS:
            return f"poor: only {self.n_contact_points} points in contact"
        if not self.r_squared >= GOOD_R_SQUARED:
            return f"poor: R^2 = {self.r_squared:.3f} < {GOOD_R_SQUARED}"
        return "good"

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
            raise AfmInputError(
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
    if np.count_nonzero(keep[contact_index + 1 :]) < MIN_CONTACT_POINTS:
        raise AfmInputError(
            source, "fit range", f"at least {MIN_CONTACT_POINTS} points in contact inside it"
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
    e_guess = float(np.dot(force, s0) / np.dot(s0, s0))
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
    start = np.array([max(e_guess, 1e-12), x0_guess])
    scale = np.array([max(e_guess, 1e-12), 0.01 * span])
    # Levenberg-Marquardt (MINPACK) is the fastest here; bounded TRF only if it leaves the box
    result = least_squares(residual, start, jac=jacobian, x_scale=scale, method="lm")
    lower, upper = np.array([0.0, x.min() - span]), np.array([np.inf, x.max()])
    if not (result.success and np.all(result.x > lower) and np.all(result.x < upper)):
        result = least_squares(
            residual, start, jac=jacobian, bounds=(lower, upper), x_scale=scale, method="trf"
        )
    return float(result.x[0]), float(result.x[1]), bool(result.success), result.message


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
    :class:`IndentationFit`; bad input raises :class:`afm.errors.AfmInputError` naming
    ``curve.source``.
    """
    src = curve.source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    check_method(contact_method, src)
    fit_range = fit_range or FitRange()
    baseline = fit_baseline(curve)
    corrected = remove_baseline(curve, baseline)
    force = corrected.force_nN
    x = corrected.tip_position_um
    contact = deviation_index(force, baseline.noise_nN, n_sigma, src)
    window = fit_window(x, force, contact, fit_range, src)
    xw, fw = x[window], force[window]
    E, x0, ok, msg = fit_contact_power(
        xw, fw, tip, geometry, nu, float(x[contact]), free_contact=contact_method == "fit"
    )
    fitted = E * tip.shape(np.clip(xw - x0, 0.0, None), geometry, nu)
    in_contact = xw > x0
    rms, r2 = _contact_stats(fw, fitted, in_contact)
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
    )
