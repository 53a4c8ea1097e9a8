"""Fitting a relaxation modulus to force ramps with Ting's method (:mod:`afm.viscoelastic.ting`).

The model of each ramp r (its own contact point x0_r [um]) is

    F_r(t) = Ting[E; shape(x_r(t) - x0_r)](t)                                   [nN]

with E(t) = sum_k A_k b_k(t; theta) one of the registered relaxation models
(:mod:`afm.viscoelastic.kernel`) shared by all ramps. Two stages:

1. the approaches alone, by variable projection: for given (x0_r, theta) the force is linear
   in the amplitudes A_k >= 0 (non-negative least squares); the outer least squares
   (:func:`scipy.optimize.least_squares`, trust region reflective) varies x0_r and theta
   (log tau for the exponential terms, beta for the power law);
2. with ``use_retract`` and a retract present, every parameter together over approach and
   retract, started from stage 1 (Ting's t1 depends on the amplitudes, so they are no longer
   separable).

Relaxation times are bounded to [h/2, 20 T] (h the sampling step, T the longest time in
contact); a time on a bound, shorter than 3 h or longer than T, or a term of zero modulus, is
listed in :attr:`RampFit.undetermined` (the ramp does not resolve it) and makes the fit poor.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, nnls

from afm.material_file import MaterialFile
from afm.models import POISSON_RATIO, IndentationModel, get_model
from afm.viscoelastic.kernel import RelaxationModel, get_relaxation_model
from afm.viscoelastic.power_law import MAX_BETA
from afm.viscoelastic.prony import MAX_TERMS
from afm.viscoelastic.ramp import RampCurve
from afm.viscoelastic.ting import causal_convolution, retract_force, retract_rows
from oocyte_fe.checks import integer, quantity
from oocyte_fe.errors import InputError

TAU_LOWER_STEPS = 0.5
TAU_UPPER_CONTACT = 20.0
GOOD_RELATIVE_RMS = 0.02
"""Largest RMS residual, as a fraction of the peak force, rated good."""
MIN_CONTACT_POINTS = 10
MIN_STEPS_PER_TAU = 3.0
"""A relaxation time resolved needs at least this many samples (shorter: flagged)."""
RETRACT_TOLERANCE = 1e-5
FD_STEP = 1.5e-8
"""Relative forward-difference step of the contact points and times in the retract stage."""
"""Relative change of cost and parameters that ends the approach-and-retract stage."""


@dataclass(frozen=True)
class RampFit:
    """Result of :func:`fit_ramp`: the relaxation modulus and the fit's figures.

    ``amplitudes_kPa`` and ``theta`` are the model's linear and non-linear parameters (see
    :attr:`parameters` for them by name with units); ``contact_points_um`` one per ramp;
    ``fitted_force_nN`` the model force on each ramp's grid (``ramps``).
    """

    relaxation: str
    model: str
    geometry: Mapping[str, float]
    nu: float
    amplitudes_kPa: tuple[float, ...]
    theta: tuple[float, ...]
    contact_points_um: tuple[float, ...]
    residual_rms_nN: float
    relative_rms: float
    r_squared: float
    used_retract: bool
    undetermined: tuple[str, ...]
    success: bool
    message: str
    ramps: tuple[RampCurve, ...]
    fitted_force_nN: tuple[np.ndarray, ...]

    @property
    def parameters(self) -> dict[str, float | tuple[float, ...]]:
        """The fitted parameters by name (units in the names)."""
        a, th = self.amplitudes_kPa, self.theta
        if self.relaxation == "power_law":
            return {"E0_kPa": a[0], "beta": th[0], "t0_s": th[1]}
        if self.relaxation == "standard_linear_solid":
            return {"E0_kPa": a[0] + a[1], "E_inf_kPa": a[0], "tau_s": th[0]}
        return {"E0_kPa": sum(a), "E_inf_kPa": a[0], "E_kPa": a[1:], "tau_s": th}

    @property
    def E0_kPa(self) -> float:
        """Instantaneous modulus E(0+) (Prony, SLS) or E(t0) (power law), kPa."""
        return float(self.parameters["E0_kPa"])

    def modulus(self, t_s: np.ndarray) -> np.ndarray:
        """The fitted relaxation modulus E(t), kPa."""
        rel = get_relaxation_model(self.relaxation)
        return rel.modulus(t_s, np.array(self.amplitudes_kPa), np.array(self.theta))

    @property
    def quality(self) -> str:
        """``good``, or ``poor: <reasons>`` (RMS above 2 % of the peak force, undetermined
        terms, no convergence)."""
        reasons = [] if self.success else [self.message]
        if not self.relative_rms <= GOOD_RELATIVE_RMS:
            reasons.append(f"relative RMS {self.relative_rms:.3g} > {GOOD_RELATIVE_RMS:g}")
        reasons.extend(self.undetermined)
        return "poor: " + "; ".join(reasons) if reasons else "good"

    def material(self, name: str, source: str) -> MaterialFile:
        """The material-file record (E0, nu, g_i = E_i / E0, tau_i) of a Prony or SLS fit;
        write it with :func:`afm.material_file.write_material`. The rating is appended to
        ``source``, so undetermined terms are flagged in the file."""
        if self.relaxation == "power_law":
            raise InputError(
                "<input>",
                "relaxation",
                "a Prony or standard-linear-solid fit for a material file (a power law has "
                "no Prony series; fit relaxation='prony')",
                self.relaxation,
            )
        e0 = self.E0_kPa
        g = tuple(a / e0 for a in self.amplitudes_kPa[1:])
        return MaterialFile(
            name=name,
            source=f"{source}; ramp fit ({self.relaxation}, Ting) {self.quality}",
            E_kPa=e0,
            nu=self.nu,
            g=g,
            tau_s=tuple(self.theta[: len(g)]),
        )


@dataclass(frozen=True)
class _Setup:
    tip: IndentationModel
    geometry: Mapping[str, float]
    nu: float
    rel: RelaxationModel
    n_theta: int
    t0: float


def _theta(setup: _Setup, q: np.ndarray) -> np.ndarray:
    """Model theta from the free non-linear parameters q (log tau, or beta)."""
    if setup.rel.key == "power_law":
        return np.array([q[0], setup.t0])
    return np.exp(q)


def _basis_force(
    setup: _Setup,
    ramp: RampCurve,
    x0: float,
    theta: np.ndarray,
    amplitudes: np.ndarray | None,
    sensitivity: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Force per unit amplitude of each basis function on ``ramp`` (N, n_basis); the retract
    (t1 from ``amplitudes``) only when ``amplitudes`` is given. With ``sensitivity`` also the
    change through t1 per amplitude (:func:`afm.viscoelastic.ting.retract_force`), so that
    dF/dA = force + sensitivity."""
    x = ramp.tip_position_um
    n, h = x.size, ramp.step_s
    delta = np.clip(x - x0, 0.0, None)
    shape = setup.tip.shape(delta, setup.geometry, setup.nu)
    w = np.diff(setup.rel.integrals(h * np.arange(n + 1), theta), axis=0) / h
    d_shape = np.diff(shape, prepend=0.0)
    force = causal_convolution(d_shape, w)
    turn = int(np.argmax(delta))
    sens = np.zeros_like(force)
    if amplitudes is not None and 0 < turn < n - 1:
        rows = retract_rows(turn, n)
        d_delta = np.diff(delta, prepend=0.0)
        out = retract_force(d_shape, d_delta, w @ amplitudes, turn, rows, w, sensitivity)
        values, by_t1 = out if sensitivity else (out, None)
        grid = np.arange(turn + 1, n)
        for k in range(w.shape[1]):
            force[turn + 1 :, k] = np.interp(grid, rows, values[:, k])
            if by_t1 is not None:
                sens[turn + 1 :, k] = np.interp(grid, rows, by_t1[:, k])
    return (force, sens) if sensitivity else force


def _contact_guess(ramp: RampCurve, exponent: float) -> float:
    """x0 from F^(1/n) linear in x over the approach points between 10 % and 90 % of the peak."""
    a = ramp.approach()
    f, x = a.force_nN, a.tip_position_um
    peak = float(f.max())
    use = (f > 0.1 * peak) & (f < 0.9 * peak)
    if np.count_nonzero(use) < 3 or not peak > 0:
        return float(x[int(np.argmax(f > 0.1 * peak))]) if peak > 0 else float(x[0])
    slope, intercept = np.polyfit(x[use], f[use] ** (1.0 / exponent), 1)
    return float(-intercept / slope) if slope > 0 else float(x[use][0])


def _check_ramps(ramps: RampCurve | Sequence[RampCurve]) -> tuple[RampCurve, ...]:
    items = (ramps,) if isinstance(ramps, RampCurve) else tuple(ramps)
    if not items or not all(isinstance(r, RampCurve) for r in items):
        raise InputError("<input>", "ramps", "a RampCurve or a sequence of them", ramps)
    for r in items:
        a = r.approach()
        if int(np.count_nonzero(a.force_nN > 0.1 * float(a.force_nN.max()))) < MIN_CONTACT_POINTS:
            raise InputError(
                r.source,
                "force_nN",
                f"an approach with at least {MIN_CONTACT_POINTS} points in contact",
            )
    return items


def fit_ramp(
    ramps: RampCurve | Sequence[RampCurve],
    model: str = "hertz_paraboloid",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    relaxation: str = "prony",
    terms: int = 2,
    t0_s: float = 1.0,
    use_retract: bool = True,
    start_tau_s: Sequence[float] | None = None,
) -> RampFit:
    """Fit ``relaxation`` (``power_law``, ``standard_linear_solid`` or ``prony`` with
    ``terms`` exponential terms) to one or more ramps of the tip ``model`` (``sneddon_cone``,
    ``hertz_paraboloid``, ``hertz_sphere``, any of :mod:`afm.models`) with ``geometry``.

    Several ramps (for example speeds a decade apart) share the modulus, each has its own
    contact point. ``t0_s`` is the power law's reference time; ``start_tau_s`` optional
    starting relaxation times. Module docstring for the method; bad input raises
    :class:`oocyte_fe.errors.InputError`.
    """
    items = _check_ramps(ramps)
    src = items[0].source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    rel = get_relaxation_model(relaxation, src)
    t0 = quantity(src, "t0_s", t0_s, "time_s")
    if rel.key == "prony":
        n_theta = integer(src, "terms", terms, 1, MAX_TERMS)
    else:
        n_theta = 1
    if not isinstance(use_retract, bool):
        raise InputError(src, "use_retract", "true or false", use_retract)
    setup = _Setup(tip, geometry, nu, rel, n_theta, t0)
    step = min(r.step_s for r in items)
    x0_start = np.array([_contact_guess(r, tip.exponent) for r in items])
    contact_time = max(
        float(r.step_s * np.count_nonzero(r.approach().tip_position_um > x0))
        for r, x0 in zip(items, x0_start, strict=True)
    )
    contact_time = max(contact_time, 4 * step)
    lo_tau, hi_tau = TAU_LOWER_STEPS * step, TAU_UPPER_CONTACT * contact_time
    if rel.key == "power_law":
        q0, q_lo, q_hi = np.array([0.2]), np.array([0.0]), np.array([MAX_BETA])
    else:
        if start_tau_s is None:
            tau0 = (
                np.geomspace(3 * step, contact_time, n_theta + 1)[1:]
                if n_theta > 1
                else (np.array([contact_time / 3]))
            )
        else:
            if isinstance(start_tau_s, str | bytes) or not isinstance(start_tau_s, Sequence):
                raise InputError(src, "start_tau_s", "a list of times in s", start_tau_s)
            tau0 = np.array([quantity(src, "start_tau_s", v, "time_s") for v in start_tau_s])
            if tau0.size != n_theta:
                raise InputError(src, "start_tau_s", f"{n_theta} times", tau0.size)
        q0 = np.log(np.clip(tau0, lo_tau * 1.01, hi_tau / 1.01))
        q_lo, q_hi = np.full(n_theta, math.log(lo_tau)), np.full(n_theta, math.log(hi_tau))
    n_ramps = len(items)
    approaches = [r.approach() for r in items]
    spans = [float(np.ptp(r.tip_position_um)) for r in items]
    x_lo = np.array([float(r.tip_position_um.min()) - s for r, s in zip(items, spans, strict=True)])
    x_hi = np.array([float(r.tip_position_um.max()) for r in items])
    f_app = np.concatenate([a.force_nN for a in approaches])

    def projected(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        m = _design(setup, approaches, p, None)
        scale = np.maximum(np.linalg.norm(m, axis=0), 1e-300)
        amps, _ = nnls(m / scale, f_app)
        amps = amps / scale
        return m @ amps - f_app, amps

    p0 = np.concatenate([x0_start, q0])
    lower, upper = np.concatenate([x_lo, q_lo]), np.concatenate([x_hi, q_hi])
    p0 = np.clip(p0, lower + 1e-9 * np.abs(lower), upper - 1e-9 * np.abs(upper))
    x_scale = np.concatenate([np.full(n_ramps, max(min(spans), 1e-6) * 0.01), np.ones(q0.size)])
    with np.errstate(all="ignore"):
        first = least_squares(
            lambda p: projected(p)[0], p0, bounds=(lower, upper), x_scale=x_scale, method="trf"
        )
    p, amps = first.x, projected(first.x)[1]
    success, message = bool(first.success), str(first.message)
    with_retract = use_retract and any(r.turn < r.time_s.size - 1 for r in items)
    if with_retract:
        p, amps, success, message = _fit_with_retract(setup, items, p, amps, (lower, upper))
        curves: Sequence[RampCurve] = items
    else:
        curves = approaches
    theta = _theta(setup, p[n_ramps:])
    fitted = [
        _basis_force(setup, c, p[i], theta, amps if with_retract else None) @ amps
        for i, c in enumerate(curves)
    ]
    data = np.concatenate([c.force_nN for c in curves])
    model_f = np.concatenate(fitted)
    res = model_f - data
    rms = float(np.sqrt(np.mean(res**2)))
    contact = model_f > 0
    ss_tot = float(np.sum((data[contact] - data[contact].mean()) ** 2))
    r2 = 1.0 - float(np.sum(res[contact] ** 2)) / ss_tot if ss_tot > 0 else math.nan
    if rel.key != "power_law":
        order = np.argsort(theta)
        theta, amps = theta[order], np.concatenate([amps[:1], amps[1:][order]])
    flags = _undetermined(rel.key, amps, theta, step, contact_time, lo_tau, hi_tau)
    return RampFit(
        relaxation=rel.key,
        model=tip.key,
        geometry=geometry,
        nu=nu,
        amplitudes_kPa=tuple(float(a) for a in amps),
        theta=tuple(float(v) for v in theta),
        contact_points_um=tuple(float(v) for v in p[:n_ramps]),
        residual_rms_nN=rms,
        relative_rms=rms / max(float(np.max(np.abs(data))), 1e-300),
        r_squared=r2,
        used_retract=with_retract,
        undetermined=flags,
        success=success,
        message=message,
        ramps=tuple(curves),
        fitted_force_nN=tuple(fitted),
    )


def _undetermined(
    key: str,
    amps: np.ndarray,
    theta: np.ndarray,
    step: float,
    contact_time: float,
    lo_tau: float,
    hi_tau: float,
) -> tuple[str, ...]:
    """Parameters the ramps do not determine, one line each (module docstring)."""
    if key == "power_law":
        beta = float(theta[0])
        if beta <= 1e-6 or beta >= MAX_BETA - 1e-6:
            return (f"beta = {beta:.3g} at a bound of the fit [0, {MAX_BETA:g}]",)
        return ()
    flags = []
    for i, (tau, e) in enumerate(zip(theta, amps[1:], strict=True), start=1):
        name = f"tau_{i} = {tau:.3g} s"
        if not e > 0:
            flags.append(f"term {i} ({name}) has zero modulus: not resolved")
        elif abs(math.log(tau / lo_tau)) < 1e-3 or abs(math.log(tau / hi_tau)) < 1e-3:
            flags.append(f"{name} at a bound of the fit: not determined by the ramp")
        elif tau < MIN_STEPS_PER_TAU * step:
            flags.append(
                f"{name} shorter than {MIN_STEPS_PER_TAU:g} sampling steps ({step:.3g} s): "
                "not determined"
            )
        elif tau > contact_time:
            flags.append(
                f"{name} longer than the time in contact {contact_time:.3g} s: not separated "
                "from E_inf"
            )
    return tuple(flags)


def _design(
    setup: _Setup, curves: Sequence[RampCurve], p: np.ndarray, amps: np.ndarray | None
) -> np.ndarray:
    """Stacked basis forces of ``curves`` for p = (x0 per curve, free non-linear parameters)."""
    n = len(curves)
    theta = _theta(setup, p[n:])
    return np.concatenate([_basis_force(setup, c, p[i], theta, amps) for i, c in enumerate(curves)])


def _fit_with_retract(
    setup: _Setup,
    items: Sequence[RampCurve],
    p: np.ndarray,
    amps: np.ndarray,
    bounds: tuple[np.ndarray, np.ndarray],
) -> tuple[np.ndarray, np.ndarray, bool, str]:
    """Stage 2: every parameter over approach and retract, from stage 1's (p, amps).

    Jacobian: the amplitude columns analytic (force per amplitude plus its change through
    t1), the contact points and times by forward differences.
    """
    f_all = np.concatenate([r.force_nN for r in items])
    n_ramps, n_a, n_p = len(items), amps.size, p.size
    spans = [float(np.ptp(r.tip_position_um)) for r in items]
    typical = np.concatenate([np.full(n_ramps, max(spans)), np.ones(n_p - n_ramps)])
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def residual(z: np.ndarray) -> np.ndarray:
        return _design(setup, items, z[:n_p], z[n_p:]) @ z[n_p:] - f_all

    def evaluate(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = z.tobytes()
        if key not in cache:
            cache.clear()
            theta = _theta(setup, z[n_ramps:n_p])
            parts = [
                _basis_force(setup, c, z[i], theta, z[n_p:], sensitivity=True)
                for i, c in enumerate(items)
            ]
            m = np.concatenate([f for f, _ in parts])
            cache[key] = (m @ z[n_p:] - f_all, m + np.concatenate([s for _, s in parts]))
        return cache[key]

    def jacobian(z: np.ndarray) -> np.ndarray:
        base, d_amps = evaluate(z)
        cols = []
        for i in range(n_p):  # x0 and theta by forward differences (t1 moves with them)
            step = FD_STEP * max(abs(z[i]), typical[i])
            step = -step if z[i] + step > z_hi[i] else step
            shifted = z.copy()
            shifted[i] += step
            cols.append((residual(shifted) - base) / step)
        return np.column_stack([*cols, d_amps])

    amp_scale = np.maximum(amps, 1e-3 * max(float(amps.max()), 1e-12))
    z0 = np.concatenate([p, amp_scale if np.any(amps <= 0) else amps])
    z_lo = np.concatenate([bounds[0], np.zeros(n_a)])
    z_hi = np.concatenate([bounds[1], np.full(n_a, np.inf)])
    with np.errstate(all="ignore"):
        result = least_squares(
            lambda z: evaluate(z)[0],
            np.clip(z0, z_lo, z_hi),
            jac=jacobian,
            bounds=(z_lo, z_hi),
            x_scale="jac",
            method="trf",
            ftol=RETRACT_TOLERANCE,
            xtol=RETRACT_TOLERANCE,
        )
    return result.x[:n_p], result.x[n_p:], bool(result.success), str(result.message)
