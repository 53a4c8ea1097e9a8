"""Creep under a clamped force: indentation -> shear creep compliance (Lee-Radok) -> Prony.

Lee and Radok's solution for a rigid cone pressed into a linear viscoelastic half-space with a
constant Poisson ratio, under a force step F0 held constant from t = 0::

    delta(t)^2 = pi (1 - nu) F0 J(t) / (4 tan(alpha))

delta indentation [um], F0 clamped force [nN], J(t) shear creep compliance [1/kPa], alpha half
opening angle [deg], nu Poisson ratio. For an elastic solid J = 1/G, E = 2 (1 + nu) G and this is
Sneddon's cone. Assumptions: the load is a step (a ramp much shorter than the shortest time
scale fitted), the contact area never shrinks, nu does not change with time.

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
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares, nnls

from afm.creep_data import CreepData
from afm.curve_io import read_creep
from afm.material_file import MaterialFile
from afm.prony_series import CreepProny, RelaxationProny, relaxation_from_creep


def _cone_factor(half_angle_deg: float, nu: float) -> float:
    """pi (1 - nu) / (4 tan(alpha)), 1/um^0 (delta^2 = factor * F0 * J)."""
    return math.pi * (1.0 - nu) / (4.0 * math.tan(math.radians(half_angle_deg)))


def compliance_from_indentation(
    indentation_um: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """J(t) = 4 tan(alpha) delta(t)^2 / (pi (1 - nu) F0), 1/kPa (Lee-Radok, cone)."""
    delta = np.asarray(indentation_um, dtype=float)
    return delta**2 / (_cone_factor(half_angle_deg, nu) * force_nN)


def indentation_from_compliance(
    compliance_per_kPa: np.ndarray, force_nN: float, half_angle_deg: float = 10.0, nu: float = 0.5
) -> np.ndarray:
    """delta(t) = sqrt(pi (1 - nu) F0 J(t) / (4 tan(alpha))), um (Lee-Radok, cone)."""
    j = np.asarray(compliance_per_kPa, dtype=float)
    return np.sqrt(_cone_factor(half_angle_deg, nu) * force_nN * j)


@dataclass(frozen=True)
class CreepFit:
    """Creep fit: the data's J(t), the fitted creep series and its exact relaxation series."""

    time_s: np.ndarray
    compliance_per_kPa: np.ndarray
    creep: CreepProny
    relaxation: RelaxationProny
    nu: float
    half_angle_deg: float
    clamp_force_nN: float
    relative_rms: float

    @property
    def E0_kPa(self) -> float:
        """Instantaneous Young's modulus 2 (1 + nu) G0, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G0_kPa

    @property
    def E_inf_kPa(self) -> float:
        """Long-time Young's modulus 2 (1 + nu) G_inf, kPa."""
        return 2.0 * (1.0 + self.nu) * self.relaxation.G_inf_kPa

    def material(self, name: str, source: str) -> MaterialFile:
        """The material-file record (instantaneous E, nu, normalised Prony terms)."""
        return MaterialFile(
            name=name,
            source=source,
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


def fit_creep_prony(
    time_s: np.ndarray, compliance_per_kPa: np.ndarray, per_decade: int = 4
) -> tuple[CreepProny, float]:
    """Fit J(t) = J0 + sum J_i (1 - exp(-t/lambda_i)) with J0, J_i >= 0 (module docstring).

    Residuals are relative (divided by J), so short and long times weigh alike. Returns the
    series and the relative RMS residual.
    """
    t = np.asarray(time_s, dtype=float)
    j = np.asarray(compliance_per_kPa, dtype=float)
    step = float(np.min(np.diff(t)))
    lo, hi = max(step, 1e-6), 3.0 * float(t[-1])
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
    lower = np.concatenate([np.zeros(1 + n), np.full(n, math.log(lo) - 2.0)])
    upper = np.concatenate([np.full(1 + n, np.inf), np.full(n, math.log(hi) + 2.0)])
    result = least_squares(residual, start, jac=jacobian, bounds=(lower, upper), method="trf")
    p = result.x
    rms = float(np.sqrt(np.mean(result.fun**2)))
    return CreepProny(float(p[0]), tuple(p[1 : 1 + n]), tuple(np.exp(p[1 + n :]))), rms


def fit_creep(
    data: CreepData, half_angle_deg: float = 10.0, nu: float = 0.5, per_decade: int = 4
) -> CreepFit:
    """Lee-Radok compliance of a force-clamp hold, its creep Prony fit and relaxation series."""
    force = data.clamp_force_nN
    compliance = compliance_from_indentation(data.indentation_um, force, half_angle_deg, nu)
    creep, rms = fit_creep_prony(data.time_s, compliance, per_decade)
    return CreepFit(
        time_s=data.time_s,
        compliance_per_kPa=compliance,
        creep=creep,
        relaxation=relaxation_from_creep(creep),
        nu=nu,
        half_angle_deg=half_angle_deg,
        clamp_force_nN=force,
        relative_rms=rms,
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
