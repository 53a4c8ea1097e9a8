"""The NMSD press against the FE press beyond the calibrated force curve.

* the NMSD ring's spring factor from the FE layers (relaxed or instantaneous modulus ratio);
* the spindle goal ratio: the largest ``|u_FE - u_NMSD| / max(goal_abs, goal_rel |u_FE|)``
  over the advances (um / um);
* the spread of that ratio over the calibration's near-best fits (eq 7 cannot tell them apart:
  docs/nmsd.md, "Starts that cannot be pressed, and near-equal fits");
* the spindle error with the NMSD drag scaled down (a diagnostic of the dashpots' share);
* the rate check: the calibrated NMSD pressed at a second speed against the FE there (force
  R^2 and spindle goal ratio), which a force-only fit at one speed does not fix.
"""

from __future__ import annotations

import logging
from dataclasses import replace

import numpy as np

from nmsd.calibration import CalibrationResult, near_best
from nmsd.displacement_field import DisplacementField, press_displacements
from nmsd.errors import NmsdDivergence
from nmsd.parameters import NmsdParameters
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement
from oocyte_fe.crosscheck.agreement import displacement_agreement, force_agreement
from oocyte_fe.experiment.layers import LayerMaterials


def zona_ring_ratio(reading: float | str, materials: LayerMaterials) -> float:
    """The NMSD ring's spring factor: a number, or the FE layers' modulus ratio
    (``"afm_relaxed"``: ``E0 g_inf`` of each layer; ``"afm_instantaneous"``: ``E0``)."""
    if isinstance(reading, str):
        return materials.stiffness_ratio(relaxed=reading == "afm_relaxed")
    return float(reading)


def spindle_goal_ratio(
    field: DisplacementField,
    advances: np.ndarray,
    u_fe_spindle: np.ndarray,
    goal_abs_um: float,
    goal_rel: float,
) -> float:
    """Largest spindle error / goal over ``advances`` of an NMSD press against the FE's
    spindle displacements (k, 1, 2) um."""
    u_nm = np.array([field.at_points[float(a)] for a in advances])
    agree = displacement_agreement(advances, u_fe_spindle, u_nm, 0, goal_abs_um, goal_rel)
    return float(agree.spindle_ratio.max())


def near_best_spindle_ratios(
    setup: PressSetup,
    cal: CalibrationResult,
    advances: np.ndarray,
    spindle: np.ndarray,
    u_fe_spindle: np.ndarray,
    goal_abs_um: float,
    goal_rel: float,
) -> list[float]:
    """Spindle goal ratio of every start within 10 % of the best RMSE (diverged ones left out)."""
    ratios = []
    for end in near_best(cal, 0.1):
        try:
            field = press_displacements(setup, end.params, advances, spindle)
        except NmsdDivergence:
            continue
        ratios.append(spindle_goal_ratio(field, advances, u_fe_spindle, goal_abs_um, goal_rel))
    return ratios


def drag_scaled_error(
    setup: PressSetup,
    params: NmsdParameters,
    advances: np.ndarray,
    spindle: np.ndarray,
    u_fe_spindle: np.ndarray,
    drag_scale: float,
) -> tuple[float, np.ndarray]:
    """Spindle error (um) with the NMSD drag scaled by ``drag_scale`` (or ten times that if
    the nearly undamped lattice diverges), and the scale used; NaN if both diverge."""
    for scale in (drag_scale, 10 * drag_scale):
        slow = params.with_values(d0=params.d0 * scale, d1=params.d1 * scale)
        try:
            field = press_displacements(setup, slow, advances, spindle[None, :])
        except NmsdDivergence:
            continue
        u = np.array([field.at_points[float(a)][0] for a in advances])
        return scale, np.linalg.norm(u - u_fe_spindle, axis=1)
    return drag_scale, np.full(len(advances), np.nan)


def rate_check(
    check: tuple[ForceDisplacement, np.ndarray] | None,
    setup: PressSetup,
    params: NmsdParameters,
    points: np.ndarray,
    check_speed_um_s: float,
    goal_abs_um: float,
    goal_rel: float,
    log: logging.Logger,
) -> tuple[float, float]:
    """The NMSD pressed at ``check_speed_um_s`` with ``params`` against the FE press there
    (``check``: its force curve and point displacements (k, p, 2) um): force R^2 and the
    spindle goal ratio; (NaN, NaN) when the check is off or the NMSD diverges."""
    if check is None:
        return float("nan"), float("nan")
    curve, u_fe = check
    slow = replace(setup, speed_um_s=check_speed_um_s)
    advances = curve.displacement_um[1:]
    try:
        field = press_displacements(slow, params, advances, points[:1])
    except NmsdDivergence as exc:
        log.warning("rate check: the NMSD press diverged at the check speed: %s", exc)
        return float("nan"), float("nan")
    nmsd_nN = field.press.force_at(curve.displacement_um)
    ratio = spindle_goal_ratio(field, advances, u_fe[1:, :1], goal_abs_um, goal_rel)
    return force_agreement(nmsd_nN, curve.force_nN).r2, ratio
