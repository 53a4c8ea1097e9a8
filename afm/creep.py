"""Creep under a clamped force: indentation -> shear creep compliance (Lee-Radok) -> Prony.

Lee and Radok's solution for a rigid cone pressed into a linear viscoelastic half-space with a
constant Poisson ratio, under a force step F0 held constant from t = 0::

    delta(t)^2 = pi (1 - nu) F0 J(t) / (4 tan(alpha))

delta indentation [um], F0 clamped force [nN], J(t) shear creep compliance [1/kPa], alpha half
opening angle [deg], nu Poisson ratio. For an elastic solid J = 1/G, E = 2 (1 + nu) G and this is
Sneddon's cone. Assumptions: the load is a step (a ramp much shorter than the shortest time
scale fitted), the contact area never shrinks, nu does not change with time.

Any axisymmetric tip of :mod:`afm.models` (elastic law F = E shape(delta)) follows the same
way: under a force step the contact radius grows monotonically and Lee and Radok's
correspondence gives::

    shape(delta(t)) = F0 J(t) / (2 (1 + nu))        i.e.  J(t) = 2 (1 + nu) shape(delta(t)) / F0

(the cone's line above; for a paraboloid of radius R, delta^(3/2) = 3 (1 - nu) F0 J / (8 sqrt R)).
:func:`fit_creep_tip` takes the tip by model key and geometry, :func:`fit_creep` the cone.

J(t) is fitted by a creep Prony series with non-negative terms (:func:`fit_creep_prony`):
non-negative least squares (:func:`scipy.optimize.nnls`) over a fixed grid of retardation
times, ``per_decade`` per decade between the sampling step and the record length; adjacent
non-zero grid terms are merged (weighted in log time) and the merged series is refined by
bounded least squares (:func:`scipy.optimize.least_squares`) with free retardation times.
The relaxation series follows exactly (:func:`afm.prony_series.relaxation_from_creep`).

Reference: E. H. Lee and J. R. M. Radok, J. Appl. Mech. 27 (1960) 438-444.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares, nnls

from afm.creep_data import CreepData
from afm.creep_data import check_creeping as shrinking
from afm.curve_io import read_creep
from afm.material_file import MaterialFile
from afm.models import POISSON_RATIO, get_model
from afm.models.sneddon_cone import HALF_ANGLE
from afm.prony_series import MAX_TIME_S, CreepProny, RelaxationProny, relaxation_from_creep
from oocyte_fe.checks import float_array, integer, positive
from oocyte_fe.errors import InputError, SolverError

MAX_RELATIVE_RMS = 0.1
"""Largest relative RMS residual of the J(t) fit accepted at all (above: refused)."""
GOOD_RELATIVE_RMS = 0.02
"""Largest relative RMS residual of the J(t) fit rated ``good``."""
BOUND_MARGIN = 2.0
"""Retardation times are bounded to [step e^-2, 3 T e^2] (log margin 2 around the NNLS grid)."""


def _cone_factor(half_angle_deg: float, nu: float) -> float:
    """pi (1 - nu) / (4 tan(alpha)), 1/um^0 (delta^2 = factor * F0 * J)."""
    alpha = HALF_ANGLE.check(half_angle_deg)
    return math.pi * (1.0 - POISSON_RATIO.check(nu)) / (4.0 * math.tan(math.radians(alpha)))


def compliance_from_indentation(
    indentation_um: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """J(t) = 4 tan(alpha) delta(t)^2 / (pi (1 - nu) F0), 1/kPa (Lee-Radok, cone)."""
    delta = float_array("<input>", "indentation_um", indentation_um)
    force = positive("<input>", "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        compliance = delta**2 / (_cone_factor(half_angle_deg, nu) * force)
    return _finite(compliance, "compliance_per_kPa")


def indentation_from_compliance(
    compliance_per_kPa: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """delta(t) = sqrt(pi (1 - nu) F0 J(t) / (4 tan(alpha))), um (Lee-Radok, cone)."""
    j = float_array("<input>", "compliance_per_kPa", compliance_per_kPa)
    force = positive("<input>", "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        delta = np.sqrt(_cone_factor(half_angle_deg, nu) * force * j)
    return _finite(delta, "indentation_um")


def tip_compliance(
    indentation_um: np.ndarray,
    force_nN: float,
    model: str,
    geometry: Mapping[str, float],
    nu: float = 0.5,
    where: str = "<input>",
) -> np.ndarray:
    """J(t) = 2 (1 + nu) shape(delta(t)) / F0, 1/kPa (Lee-Radok, any tip of :mod:`afm.models`)."""
    tip = get_model(model, where)
    geometry = tip.check_geometry(geometry, where)
    nu = POISSON_RATIO.check(nu, where)
    delta = float_array(where, "indentation_um", indentation_um)
    force = positive(where, "force_nN", force_nN, expected="a positive clamped force in nN")
    with np.errstate(all="ignore"):
        compliance = 2.0 * (1.0 + nu) * tip.shape(np.clip(delta, 0.0, None), geometry, nu) / force
    return _finite(compliance, "compliance_per_kPa")


@dataclass(frozen=True)
class CreepFit:
    """Creep fit: the data's J(t), the fitted creep series and its exact relaxation series.

    ``model`` and ``geometry`` are the tip the compliance was computed for.
    """

    time_s: np.ndarray
    compliance_per_kPa: np.ndarray
    creep: CreepProny
    relaxation: RelaxationProny
    nu: float
    model: str
    geometry: Mapping[str, float]
    clamp_force_nN: float
    relative_rms: float
    undetermined: tuple[str, ...] = ()

    @property
    def quality(self) -> str:
        """``good``, or ``poor: <reasons>`` (relative RMS above 2 %, undetermined terms)."""
        reasons = list(self.undetermined)
        if not self.relative_rms <= GOOD_RELATIVE_RMS:
            reasons.insert(0, f"relative RMS {self.relative_rms:.3g} > {GOOD_RELATIVE_RMS:g}")
        return "poor: " + "; ".join(reasons) if reasons else "good"

    @property
    def E0_kPa(self) -> float:
        """Instantaneous Young's modulus 2 (1 + nu) G0, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G0_kPa

    @property
    def E_inf_kPa(self) -> float:
        """Long-time Young's modulus 2 (1 + nu) G_inf, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G_inf_kPa

    def material(self, name: str, source: str) -> MaterialFile:
        """The material-file record (instantaneous E, nu, normalised Prony terms).

        The fit's rating is appended to ``source``, so a series with terms the record does
        not determine carries that flag into the TOML, ANSYS and FEBio files.
        """
        return MaterialFile(
            name=name,
            source=f"{source}; creep fit {self.quality}",
            E_kPa=self.E0_kPa,
            nu=self.nu,
            g=self.relaxation.g,
            tau_s=self.relaxation.tau_s,
        )


def _basis(t: np.ndarray, lambdas: np.ndarray) -> np.ndarray:
    return np.column_stack([np.ones_like(t), 1.0 - np.exp(-t[:, None] / lambdas[None, :])])


def _merge(weights: np.ndarray, lambdas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge runs of adjacent non-zero grid terms into one term each (log-weighted time)."""
    merged_w, merged_l, run = [], [], []
    for i, w in enumerate(weights):
        if w > 0:
            run.append(i)
        if run and (w <= 0 or i == weights.size - 1):
            idx = np.array(run)
            total = float(weights[idx].sum())
            merged_w.append(total)
            merged_l.append(float(np.exp(np.dot(weights[idx], np.log(lambdas[idx])) / total)))
            run = []
    return np.array(merged_w), np.array(merged_l)


def fit_window(time_s: np.ndarray, where: str = "<input>") -> tuple[float, float]:
    """The retardation-time grid of a record, [max(step, 1e-6 s), 3 T] (T its last time).

    The fitted times may leave it by e^2 either side (:data:`BOUND_MARGIN`), so it must lie
    within the Prony series' [MIN_TIME_S, MAX_TIME_S] by that margin and hold a decade:
    refused (:class:`InputError` naming ``time_s``) otherwise, before a fit that could not
    hold its own result (a record of 6e-9 s gave an empty interval, one of 3e9 s a time of
    1.07e9 s).
    """
    t = np.asarray(time_s, dtype=float)
    lo = max(float(np.min(np.diff(t))), 1e-6)
    longest = MAX_TIME_S / (3.0 * math.exp(BOUND_MARGIN)) * (1 - 1e-9)  # exp/log round-off
    shortest = 10.0 * lo / 3.0
    if not shortest <= float(t[-1]) <= longest:
        raise InputError(
            where,
            "time_s",
            f"a record ending between {shortest:.3g} s (10 x max(sampling step, 1e-6 s) / 3) "
            f"and {longest:.3g} s (fitted times within {MAX_TIME_S:g} s)",
            got=f"{float(t[-1]):.6g} s",
        )
    return lo, 3.0 * float(t[-1])


def fit_creep_prony(
    time_s: np.ndarray, compliance_per_kPa: np.ndarray, per_decade: int = 4
) -> tuple[CreepProny, float]:
    """Fit J(t) = J0 + sum J_i (1 - exp(-t/lambda_i)) with J0, J_i >= 0 (module docstring).

    Residuals are relative (divided by J), so short and long times weigh alike. Returns the
    series and the relative RMS residual. The record's times must allow a fit window
    (:func:`fit_window`).
    """
    t = np.asarray(time_s, dtype=float)
    j = np.asarray(compliance_per_kPa, dtype=float)
    lo, hi = fit_window(t)
    n_grid = max(int(round(per_decade * math.log10(hi / lo))) + 1, 2)
    grid = np.logspace(math.log10(lo), math.log10(hi), n_grid)
    weight = 1.0 / j
    coeffs, _ = nnls(_basis(t, grid) * weight[:, None], j * weight)
    terms, lambdas = _merge(coeffs[1:], grid)
    j0 = max(float(coeffs[0]), 1e-12 * float(j.max()))
    n = terms.size

    def residual(p: np.ndarray) -> np.ndarray:
        return (_basis(t, np.exp(p[1 + n :])) @ p[: 1 + n] - j) * weight

    def jacobian(p: np.ndarray) -> np.ndarray:
        lam = np.exp(p[1 + n :])
        decay = np.exp(-t[:, None] / lam[None, :])
        d_log_lambda = -p[1 : 1 + n] * decay * t[:, None] / lam[None, :]
        return np.column_stack([_basis(t, lam), d_log_lambda]) * weight[:, None]

    start = np.concatenate([[j0], terms, np.log(lambdas)])
    lower = np.concatenate([np.zeros(1 + n), np.full(n, math.log(lo) - BOUND_MARGIN)])
    upper = np.concatenate([np.full(1 + n, np.inf), np.full(n, math.log(hi) + BOUND_MARGIN)])
    result = least_squares(residual, start, jac=jacobian, bounds=(lower, upper), method="trf")
    p = result.x
    rms = float(np.sqrt(np.mean(result.fun**2)))
    terms, lambdas = _tidy(p[1 : 1 + n], np.exp(p[1 + n :]), float(np.sum(p[: 1 + n])))
    return CreepProny(float(p[0]), tuple(terms), tuple(lambdas)), rms


def _tidy(terms: np.ndarray, lambdas: np.ndarray, total: float) -> tuple[np.ndarray, np.ndarray]:
    """Drop terms below 1e-9 of J_inf and merge terms whose times differ by < 0.1 %.

    Dropping changes J(t) by less than 1e-9 relative, merging by less than 0.1 % of the merged
    terms; both keep the relaxation conversion well posed (a near-zero term next to another
    pole has its zero within round-off of that pole).
    """
    keep = terms > 1e-9 * total
    order = np.argsort(lambdas[keep])
    terms, lambdas = terms[keep][order], lambdas[keep][order]
    merged_t: list[float] = []
    merged_l: list[float] = []
    for w, lam in zip(terms, lambdas, strict=True):
        if merged_l and lam < 1.001 * merged_l[-1]:
            total_w = merged_t[-1] + w
            merged_l[-1] = math.exp(
                (merged_t[-1] * math.log(merged_l[-1]) + w * math.log(lam)) / total_w
            )
            merged_t[-1] = total_w
        else:
            merged_t.append(float(w))
            merged_l.append(float(lam))
    return np.array(merged_t), np.array(merged_l)


def _finite(values: np.ndarray, field: str) -> np.ndarray:
    if not np.all(np.isfinite(values)):
        raise InputError(
            "<input>",
            field,
            "a result within floating point range (inputs "
            "too large or too small, or negative compliance)",
        )
    return values


def check_creeping(data: CreepData) -> None:
    """Refuse a hold whose indentation shrinks (:func:`afm.creep_data.check_creeping`)."""
    shrinking(data.indentation_um, data.source)


def undetermined_terms(creep: CreepProny, time_s: np.ndarray) -> tuple[str, ...]:
    """Retardation terms the record cannot determine, one line each.

    A term is undetermined when its time is pinned at a bound of the fit (step e^-2 or
    3 T e^2, T the record length), shorter than the sampling step, or longer than the record.
    """
    t = np.asarray(time_s, dtype=float)
    step = max(float(np.min(np.diff(t))), 1e-6)
    record = float(t[-1] - t[0])
    low = math.log(step) - BOUND_MARGIN
    high = math.log(3.0 * record) + BOUND_MARGIN
    flags = []
    for i, lam in enumerate(creep.lambda_s, start=1):
        log_lam = math.log(lam)
        name = f"lambda_{i} = {lam:.3g} s"
        if abs(log_lam - low) < 1e-6 or abs(log_lam - high) < 1e-6:
            bound = "step e^-2" if abs(log_lam - low) < 1e-6 else "3 T e^2"
            flags.append(f"{name} pinned at its bound ({bound}): not determined by the record")
        elif lam < step:
            flags.append(f"{name} shorter than the sampling step {step:.3g} s: not determined")
        elif lam > record:
            flags.append(f"{name} longer than the record {record:.3g} s: not determined")
    return tuple(flags)


def _relaxation_of_fit(creep: CreepProny, src: str) -> RelaxationProny:
    """The exact relaxation series of a *fitted* creep series; a conversion that fails (the
    fit's times too close or its terms beyond floating point range: brentq cannot bracket a
    zero) is the fit's failure, so a :class:`SolverError` naming the record, not an argument."""
    try:
        return relaxation_from_creep(creep)
    except InputError as exc:
        times = ", ".join(f"{lam:.6g}" for lam in creep.lambda_s)
        raise SolverError(
            f"{src}: the creep Prony series fitted to this record ({len(creep.lambda_s)} terms, "
            f"retardation times {times} s) does not convert to a relaxation series "
            f"({exc.expected}); try a smaller per_decade or a longer, less noisy hold"
        ) from None


def fit_creep(
    data: CreepData, half_angle_deg: float = 10.0, nu: float = 0.5, per_decade: int = 4
) -> CreepFit:
    """:func:`fit_creep_tip` for a cone of half angle ``half_angle_deg`` (deg)."""
    where = data.source if isinstance(data, CreepData) else "<input>"
    half_angle_deg = HALF_ANGLE.check(half_angle_deg, where)
    return fit_creep_tip(data, "sneddon_cone", {"half_angle_deg": half_angle_deg}, nu, per_decade)


def fit_creep_tip(
    data: CreepData,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    per_decade: int = 4,
) -> CreepFit:
    """Lee-Radok compliance of a force-clamp hold for the tip ``model`` (with ``geometry``;
    left-out parameters take the model's default), its creep Prony fit and relaxation series.

    Refused (:class:`InputError`): an indentation shrinking during the hold
    (:func:`check_creeping`), a fit with relative RMS above ``MAX_RELATIVE_RMS``, a geometry
    outside the model's bounds, nu outside (-1, 0.5], ``per_decade`` not an integer in
    [1, 50]. Terms the record cannot determine are listed in ``CreepFit.undetermined`` and
    make the ``quality`` poor. A fitted series that does not convert to relaxation raises
    :class:`SolverError` naming the record.
    """
    if not isinstance(data, CreepData):
        raise InputError("<input>", "data", "a CreepData record", type(data).__name__)
    src = data.source
    tip = get_model(model, src)
    geometry = tip.check_geometry(geometry or {}, src)
    nu = POISSON_RATIO.check(nu, src)
    per_decade = integer(src, "per_decade", per_decade, 1, 50)
    check_creeping(data)
    force = data.clamp_force_nN
    compliance = tip_compliance(data.indentation_um, force, model, geometry, nu, src)
    j_min, j_max = float(np.min(compliance)), float(np.max(compliance))
    if not (j_min > 1e-100 and j_max < 1e100):
        raise InputError(
            src, "indentation_um", "an indentation whose compliance J(t) is within 1e-100..1e100"
        )
    fit_window(data.time_s, src)
    creep, rms = fit_creep_prony(data.time_s, compliance, per_decade)
    if not rms <= MAX_RELATIVE_RMS:
        raise InputError(
            src,
            "indentation_um",
            f"a hold a creep Prony series fits (relative RMS <= {MAX_RELATIVE_RMS:g})",
            f"relative RMS {rms:.3g}",
        )
    return CreepFit(
        time_s=data.time_s,
        compliance_per_kPa=compliance,
        creep=creep,
        relaxation=_relaxation_of_fit(creep, src),
        nu=nu,
        model=tip.key,
        geometry=geometry,
        clamp_force_nN=force,
        relative_rms=rms,
        undetermined=undetermined_terms(creep, data.time_s),
    )


def material_from_creep_csv(
    path: str | Path,
    name: str,
    half_angle_deg: float = 10.0,
    nu: float = 0.5,
    per_decade: int = 4,
) -> MaterialFile:
    """Read a creep CSV (:func:`afm.curve_io.read_creep`), fit it, return the material record.

    Write it with :func:`afm.material_file.write_material`.
    """
    data = read_creep(path)
    fit = fit_creep(data, half_angle_deg, nu, per_decade)
    source = (
        f"AFM creep {Path(path).name}: Lee-Radok cone (alpha {half_angle_deg:g} deg, "
        f"F0 {fit.clamp_force_nN:.3g} nN), creep Prony fit, exact conversion to relaxation"
    )
    return fit.material(name, source)
