"""Reduced model of the oocyte's deformation at the fluid junction: a Kelvin-Voigt capsule
loaded for a finite residence time.

The oocyte (diameter d_c, um) is carried at the channel's mean velocity U (um/s, from
:class:`~oocyte_fe.microchannel.channel.Channel`). At the junction it feels, over its length, the
viscous pressure difference of the Poiseuille flow, amplified by the confinement and the
merging streams::

    sigma = c_load 8 mu U d_c / R^2                              (kPa)

for a residence time ``t_res = L_j / U`` (s). The cell responds as a Kelvin-Voigt solid with the
AFM Young's modulus E (kPa) and the Carreau viscosity of its cytoplasm at the local strain
rate ``gamma_j = U / d_c`` (1/s), ``tau = eta(gamma_j) / E`` (s)::

    D = (sigma / E) (1 - exp(-t_res / tau))        Taylor deformation D = (a - b) / (a + b)
    ratio = b / a = (1 - D) / (1 + D)              (minor over major axis, Table 4)

Fitted (named) parameters: ``load_factor`` c_load (1) and ``junction_length`` L_j (um), by least
squares on the relative ratio error at the chosen pressures; E, d_c, the rheology and the
channel are inputs. Only ``c_load / E`` and ``L_j E / eta`` are identifiable from the ratios.
At high pressure ``D -> c_load 8 mu d_c L_j / (R^2 eta)``: the deformation saturates because the
load grows like U while the loading time shrinks like 1/U.

What it cannot capture, compared with a three-phase VOF: the cell's shape and its ZP/cytoplasm
layers, the real junction geometry and the two merging streams, inertia (Re ~ 70-320), the
cell's lag behind the fluid and its position off the centre line, surface forces, large
deformation and recovery after the junction; the ratio is a single scalar per pressure.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from oocyte_fe.checks import HUGE, QUANTITIES, TINY, number, numbers_array, positive
from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.viscosity import Rheology


@dataclass(frozen=True)
class JunctionCell:
    """The fixed (not fitted) description of the cell: diameter (um), modulus (kPa), rheology."""

    diameter: float
    modulus: float
    rheology: Rheology

    def __post_init__(self) -> None:
        object.__setattr__(self, "diameter", positive("JunctionCell", "diameter", self.diameter))
        object.__setattr__(self, "modulus", positive("JunctionCell", "modulus", self.modulus))
        if not isinstance(self.rheology, Rheology):
            raise InputError("JunctionCell", "rheology", "a Rheology", got=type(self.rheology))


@dataclass(frozen=True)
class JunctionParameters:
    """The fitted parameters: ``load_factor`` (1) and ``junction_length`` (um)."""

    load_factor: float
    junction_length: float

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "load_factor",
            number("JunctionParameters", "load_factor", self.load_factor, ge=0, le=HUGE),
        )
        object.__setattr__(
            self,
            "junction_length",
            positive("JunctionParameters", "junction_length", self.junction_length),
        )


@dataclass(frozen=True)
class JunctionStderr:
    """One standard error of each fitted parameter; NaN where the fit cannot tell (two
    pressures for two parameters leave no residual)."""

    load_factor: float
    junction_length: float


def junction_deformation(
    channel: Channel, cell: JunctionCell, params: JunctionParameters, pressure: np.ndarray
) -> np.ndarray:
    """Taylor deformation D (1) at driving pressures ``pressure`` (kPa); see module docstring."""
    pressure = numbers_array("junction_deformation", "pressure", pressure, ge=TINY, le=HUGE)
    return _deformation(channel, cell, params.load_factor, params.junction_length, pressure)


def _deformation(
    channel: Channel, cell: JunctionCell, load_factor: float, length: float, pressure: np.ndarray
) -> np.ndarray:
    """:func:`junction_deformation` without the argument checks (the fit's inner loop)."""
    velocity = channel.mean_velocity(pressure)
    stress = load_factor * 8.0 * channel.viscosity * velocity * cell.diameter / channel.radius**2
    relaxation = cell.rheology.viscosity(velocity / cell.diameter) / cell.modulus
    residence = length / velocity
    return stress / cell.modulus * (1.0 - np.exp(-residence / relaxation))


def axis_ratio(deformation: np.ndarray) -> np.ndarray:
    """Minor over major axis ``(1 - D) / (1 + D)`` from the Taylor deformation D."""
    return (1.0 - deformation) / (1.0 + deformation)


@dataclass(frozen=True)
class JunctionFit:
    """Fitted parameters, their standard errors, and the ratio predicted at every pressure."""

    params: JunctionParameters
    stderr: JunctionStderr
    fit_pressures: tuple[float, ...]
    pressure: np.ndarray
    ratio: np.ndarray
    success: bool


def fit_junction_model(
    channel: Channel,
    cell: JunctionCell,
    pressure: np.ndarray,
    ratio: np.ndarray,
    fit_pressures: Sequence[float],
    source: str = "deformation table",
) -> JunctionFit:
    """Fit ``load_factor`` and ``junction_length`` on ``fit_pressures`` (kPa, 2 or 3 of the
    table's pressures) to the measured ratios; predict the ratio at every pressure.

    Residuals are relative ratio errors; the two parameters are fitted as logarithms (both
    positive, orders of magnitude apart).
    """
    low, high, _ = QUANTITIES["pressure_kPa"]
    pressure = numbers_array(source, "pressure", pressure, ge=low, le=high)
    ratio = numbers_array(source, "ratio", ratio, gt=0, le=1)
    if pressure.ndim != 1 or pressure.size < 2 or ratio.shape != pressure.shape:
        raise InputError(
            source, "pressure, ratio", "two 1-D columns of equal length, at least 2 rows"
        )
    picks = [int(np.argmin(np.abs(pressure - p))) for p in fit_pressures]
    if not 2 <= len(set(picks)) <= 3 or any(
        not np.isclose(pressure[i], p, rtol=1e-9) for i, p in zip(picks, fit_pressures, strict=True)
    ):
        raise InputError(
            source,
            "fit_pressures",
            "two or three distinct pressures taken from the table "
            f"({', '.join(f'{p:g}' for p in pressure)} kPa)",
            got=list(fit_pressures),
        )
    idx = np.array(sorted(set(picks)))

    def predict(x: np.ndarray, p: np.ndarray) -> np.ndarray:
        return axis_ratio(_deformation(channel, cell, *np.exp(x), p))

    def residuals(x: np.ndarray) -> np.ndarray:
        return predict(x, pressure[idx]) / ratio[idx] - 1.0

    x0 = np.log([1.0, 10.0 * channel.diameter])
    sol = least_squares(residuals, x0, x_scale="jac", xtol=1e-14, ftol=1e-14, gtol=1e-14)
    dof = max(idx.size - 2, 1)
    cov = np.linalg.pinv(sol.jac.T @ sol.jac) * (2.0 * sol.cost / dof if idx.size > 2 else 1.0)
    values = np.exp(sol.x)
    errors = values * np.sqrt(np.diag(cov)) if idx.size > 2 else np.full(2, np.nan)
    return JunctionFit(
        JunctionParameters(*values),
        JunctionStderr(*(float(e) for e in errors)),
        tuple(float(pressure[i]) for i in idx),
        pressure,
        predict(sol.x, pressure),
        bool(sol.success),
    )
