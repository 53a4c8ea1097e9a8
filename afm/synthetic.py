"""Synthetic AFM data with known parameters, for tests, cases and benchmarks.

* :func:`indentation_curve`: an approach curve of a registered model with known E and contact
  point, baseline offset and tilt, Gaussian force noise, on a uniform piezo grid.
* :func:`pierce_curve`: the same, with the probe piercing a first layer (ZP) at a given force;
  the force drops to a residual level and rises again in the second layer (cytoplasm), whose
  indentation is counted from the tip position right after the drop.
* :func:`creep_indentation`: indentation of a cone under a clamped force for a known Prony
  relaxation series (through the exact creep compliance and the Lee-Radok relation).

At every piezo position z the force solves F = F_res + E shape(z - F/k - x_ref), found by
Newton's method on the indentation (monotonic and convex, so Newton converges from above).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from scipy.optimize import brentq

from afm.creep import indentation_from_compliance
from afm.curve import ForceCurve
from afm.models import POISSON_RATIO, IndentationModel, get_model
from afm.prony_series import RelaxationProny, creep_from_relaxation
from oocyte_fe.checks import integer, number, positive
from oocyte_fe.errors import InputError

_NEWTON_STEPS = 60


def _indentation_at(
    travel_um: np.ndarray,
    E_kPa: float,
    model: IndentationModel,
    geometry: Mapping[str, float],
    nu: float,
    k: float,
    residual_force_nN: float = 0.0,
) -> np.ndarray:
    """Indentation d >= 0 solving d + (F_res + E shape(d))/k = travel (travel = z - x_ref)."""
    travel = np.clip(np.asarray(travel_um, dtype=float) - residual_force_nN / k, 0.0, None)
    d = travel.copy()
    for _ in range(_NEWTON_STEPS):
        g = d + E_kPa * model.shape(d, geometry, nu) / k - travel
        step = g / (1.0 + E_kPa * model.dshape(d, geometry, nu) / k)
        d = np.clip(d - step, 0.0, None)
        if np.all(np.abs(step) < 1e-13 * (1.0 + travel)):
            break
    return d


def _depth_at(
    force_nN: float,
    E_kPa: float,
    model: IndentationModel,
    geometry: Mapping[str, float],
    nu: float,
) -> float:
    """Indentation [um] at which the model force reaches ``force_nN`` (within 1000 um)."""

    def excess(d: float) -> float:
        return E_kPa * model.shape(np.array([d]), geometry, nu)[0] - force_nN

    if not excess(1e3) > 0:
        raise InputError("<input>", "E_kPa", f"a modulus that reaches {force_nN:g} nN within 1 mm")
    return brentq(excess, 0, 1e3)


def _check_common(
    n_points: object,
    k_nN_per_um: object,
    nu: object,
    offset_nN: object,
    tilt_nN_per_um: object,
    noise_fraction: object,
    seed: object,
) -> None:
    """Refuse nonsense shared arguments of the generators (InputError naming them)."""
    integer("<input>", "n_points", n_points, 10, 10_000_000)
    positive("<input>", "k_nN_per_um", k_nN_per_um, expected="a positive spring constant in nN/um")
    POISSON_RATIO.check(nu)
    number("<input>", "offset_nN", offset_nN)
    number("<input>", "tilt_nN_per_um", tilt_nN_per_um)
    if not 0 <= number("<input>", "noise_fraction", noise_fraction) <= 1:
        raise InputError("<input>", "noise_fraction", "a fraction in [0, 1]", noise_fraction)
    if seed is not None:
        integer("<input>", "seed", seed, 0, 2**63 - 1)


def _measure(
    piezo: np.ndarray,
    force: np.ndarray,
    offset_nN: float,
    tilt_nN_per_um: float,
    noise_nN: float,
    seed: int | None,
) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return force + offset_nN + tilt_nN_per_um * piezo + noise_nN * rng.standard_normal(piezo.size)


def indentation_curve(
    E_kPa: float,
    contact_point_um: float = 5.0,
    *,
    max_piezo_um: float = 8.0,
    n_points: int = 2000,
    k_nN_per_um: float = 70.0,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    offset_nN: float = 0.0,
    tilt_nN_per_um: float = 0.0,
    noise_fraction: float = 0.0,
    seed: int | None = None,
    source: str = "<synthetic>",
    group: str = "",
) -> ForceCurve:
    """Approach curve on piezo 0..``max_piezo_um``; noise SD = ``noise_fraction`` * max force."""
    _check_common(n_points, k_nN_per_um, nu, offset_nN, tilt_nN_per_um, noise_fraction, seed)
    E_kPa = positive("<input>", "E_kPa", E_kPa, expected="a positive modulus in kPa")
    positive("<input>", "max_piezo_um", max_piezo_um, expected="a positive piezo travel in um")
    number(
        "<input>", "contact_point_um", contact_point_um
    )  # beyond the travel: a curve without contact
    tip = get_model(model)
    geometry = tip.check_geometry(geometry or {})
    piezo = np.linspace(0.0, max_piezo_um, n_points)
    delta = _indentation_at(piezo - contact_point_um, E_kPa, tip, geometry, nu, k_nN_per_um)
    force = E_kPa * tip.shape(delta, geometry, nu)
    noise = noise_fraction * float(force.max())
    measured = _measure(piezo, force, offset_nN, tilt_nN_per_um, noise, seed)
    return ForceCurve(piezo, measured, k_nN_per_um, source, group)


def pierce_curve(
    E_zp_kPa: float,
    E_cytoplasm_kPa: float,
    contact_point_um: float = 4.0,
    *,
    pierce_force_nN: float = 8.0,
    residual_fraction: float = 0.3,
    trigger_force_nN: float = 12.0,
    n_points: int = 2000,
    k_nN_per_um: float = 100.0,
    model: str = "sneddon_cone",
    geometry: Mapping[str, float] | None = None,
    nu: float = 0.5,
    offset_nN: float = 0.0,
    tilt_nN_per_um: float = 0.0,
    noise_fraction: float = 0.0,
    seed: int | None = None,
    source: str = "<synthetic>",
    group: str = "",
) -> ForceCurve:
    """Pierce-through curve: ZP up to ``pierce_force_nN``, drop to ``residual_fraction`` of it,
    then cytoplasm from the tip position after the drop, up to ``trigger_force_nN`` (where the
    instrument stops the approach). Noise SD is ``noise_fraction`` of the pierce force."""
    tip = get_model(model)
    geometry = tip.check_geometry(geometry or {})
    _check_common(n_points, k_nN_per_um, nu, offset_nN, tilt_nN_per_um, noise_fraction, seed)
    E_zp_kPa = positive("<input>", "E_zp_kPa", E_zp_kPa, expected="a positive modulus in kPa")
    E_cytoplasm_kPa = positive(
        "<input>", "E_cytoplasm_kPa", E_cytoplasm_kPa, expected="a positive modulus"
    )
    number("<input>", "contact_point_um", contact_point_um)
    pierce_force_nN = positive(
        "<input>", "pierce_force_nN", pierce_force_nN, expected="a positive force"
    )
    trigger_force_nN = positive("<input>", "trigger_force_nN", trigger_force_nN, expected="a force")
    if not 0 <= number("<input>", "residual_fraction", residual_fraction) < 1:
        raise InputError("<input>", "residual_fraction", "a fraction in [0, 1)", residual_fraction)
    k = k_nN_per_um
    residual = residual_fraction * pierce_force_nN
    if not trigger_force_nN > pierce_force_nN:
        raise InputError(
            "<input>", "trigger_force_nN", f"a force above pierce_force_nN ({pierce_force_nN:g})"
        )
    d_pierce = _depth_at(pierce_force_nN, E_zp_kPa, tip, geometry, nu)
    d_end = _depth_at(trigger_force_nN - residual, E_cytoplasm_kPa, tip, geometry, nu)
    z_pierce = contact_point_um + d_pierce + pierce_force_nN / k
    piezo = np.linspace(0.0, z_pierce + d_end + (trigger_force_nN - residual) / k, n_points)
    delta1 = _indentation_at(piezo - contact_point_um, E_zp_kPa, tip, geometry, nu, k)
    force = E_zp_kPa * tip.shape(delta1, geometry, nu)
    first = int(np.argmax(force >= pierce_force_nN * (1 - 1e-12)))
    x_ref = piezo[first] - residual / k  # tip position right after the drop
    delta2 = _indentation_at(piezo[first:] - x_ref, E_cytoplasm_kPa, tip, geometry, nu, k, residual)
    force[first:] = residual + E_cytoplasm_kPa * tip.shape(delta2, geometry, nu)
    noise = noise_fraction * pierce_force_nN
    measured = _measure(piezo, force, offset_nN, tilt_nN_per_um, noise, seed)
    return ForceCurve(piezo, measured, k, source, group)


def check_pierce_visible(
    E_zp_kPa: float,
    E_cytoplasm_kPa: float,
    contact_point_um: float,
    *,
    pierce_force_nN: float,
    residual_fraction: float,
    trigger_force_nN: float,
    k_nN_per_um: float,
    geometry: Mapping[str, float],
    nu: float,
    tilt_nN_per_um: float,
    min_drop_fraction: float = 0.1,
) -> None:
    """Raise :class:`InputError` unless :func:`afm.pierce.detect_pierce` finds the pierce of the
    noise-free :func:`pierce_curve` of these moduli: the drop, ``pierce_force_nN x (1 -
    residual_fraction)``, must exceed ``min_drop_fraction`` of the force range, which the
    trigger force and the baseline tilt over the approach make up. The error names
    ``pierce_force_nN`` if the drop is too small even without tilt, else ``tilt_nN_per_um``."""
    from afm.pierce import detect_pierce  # afm.pierce does not import this module

    options = dict(
        pierce_force_nN=pierce_force_nN,
        residual_fraction=residual_fraction,
        trigger_force_nN=trigger_force_nN,
        k_nN_per_um=k_nN_per_um,
        geometry=geometry,
        nu=nu,
    )
    for tilt, field in ((0.0, "pierce_force_nN"), (tilt_nN_per_um, "tilt_nN_per_um")):
        curve = pierce_curve(
            E_zp_kPa, E_cytoplasm_kPa, contact_point_um, tilt_nN_per_um=tilt, **options
        )  # type: ignore[arg-type]
        try:
            detect_pierce(curve, min_drop_fraction)
        except InputError:
            drop = pierce_force_nN * (1 - residual_fraction)
            span = float(np.ptp(curve.force_nN))
            raise InputError(
                "<input>",
                field,
                f"a pierce drop (pierce_force_nN x (1 - residual_fraction) = {drop:.3g} nN) above "
                f"{min_drop_fraction:g} of the curve's force range ({span:.3g} nN with "
                f"tilt_nN_per_um = {tilt:g}, at the mean moduli): else no pierce is detected",
                pierce_force_nN if field == "pierce_force_nN" else tilt_nN_per_um,
            ) from None


def creep_indentation(
    relaxation: RelaxationProny,
    time_s: np.ndarray,
    force_nN: float,
    half_angle_deg: float = 10.0,
    nu: float = 0.5,
) -> np.ndarray:
    """Indentation [um] of a cone under a force step ``force_nN`` for a shear relaxation series."""
    compliance = creep_from_relaxation(relaxation)
    return indentation_from_compliance(compliance(time_s), force_nN, half_angle_deg, nu)
