"""Agreement between the FE press and the NMSD press: force curves and displacement fields.

Force (both in nN, the FE force per unit thickness times the effective thickness): RMSE,
``R^2`` and cosine similarity of :func:`nmsd.calibration.fit_metrics`, with the FE curve as the
reference. Displacement at reference points ``X_j`` (um) and pipette advances ``s_k``::

    e_jk = | u_FE(X_j, s_k) - u_NMSD(X_j, s_k) |                       (um)

The spindle goal of issue 9 at each advance: ``e_spindle <= max(a, r |u_FE(spindle)|)`` with
``a`` = 2 um and ``r`` = 10 % (whichever is larger); ``e / tolerance <= 1`` meets it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nmsd.calibration import FitMetrics, fit_metrics


@dataclass(frozen=True, eq=False)
class DisplacementAgreement:
    """Errors at the advances ``advance_um`` (k,): point errors (k, p) um, the spindle (row
    ``spindle``) displacement of both models (k, 2) um, its error and tolerance (k,) um."""

    advance_um: np.ndarray
    error_um: np.ndarray
    spindle_fe_um: np.ndarray
    spindle_nmsd_um: np.ndarray
    spindle_error_um: np.ndarray
    spindle_tolerance_um: np.ndarray

    @property
    def max_error_um(self) -> float:
        """Largest point error over all points and advances, um."""
        return float(self.error_um.max())

    @property
    def spindle_ratio(self) -> np.ndarray:
        """Spindle error over its tolerance at each advance (<= 1 meets the goal)."""
        return self.spindle_error_um / self.spindle_tolerance_um


def spindle_tolerance_um(u_fe_um: np.ndarray, abs_um: float = 2.0, rel: float = 0.10) -> np.ndarray:
    """``max(abs_um, rel |u_FE|)`` for displacement vectors (..., 2) um."""
    return np.maximum(abs_um, rel * np.linalg.norm(u_fe_um, axis=-1))


def displacement_agreement(
    advance_um: np.ndarray,
    u_fe_um: np.ndarray,
    u_nmsd_um: np.ndarray,
    spindle: int = 0,
    abs_um: float = 2.0,
    rel: float = 0.10,
) -> DisplacementAgreement:
    """Point errors for displacements (k, p, 2) um of both models at the same advances."""
    u_fe, u_nm = np.asarray(u_fe_um), np.asarray(u_nmsd_um)
    if u_fe.shape != u_nm.shape or u_fe.ndim != 3 or u_fe.shape[2] != 2:
        raise ValueError(f"displacement_agreement: shapes {u_fe.shape} and {u_nm.shape}")
    error = np.linalg.norm(u_fe - u_nm, axis=2)
    return DisplacementAgreement(
        np.asarray(advance_um, dtype=float),
        error,
        u_fe[:, spindle],
        u_nm[:, spindle],
        error[:, spindle],
        spindle_tolerance_um(u_fe[:, spindle], abs_um, rel),
    )


def force_agreement(model_nN: np.ndarray, reference_nN: np.ndarray) -> FitMetrics:
    """RMSE (nN), R^2 and similarity of a model force curve against a reference curve."""
    return fit_metrics(np.asarray(model_nN), np.asarray(reference_nN))


def largest_departure(advance_um: np.ndarray, model_nN: np.ndarray, reference_nN: np.ndarray):
    """Advance (um) and value (nN) of the largest |model - reference| force difference."""
    diff = np.asarray(model_nN) - np.asarray(reference_nN)
    k = int(np.argmax(np.abs(diff)))
    return float(advance_um[k]), float(diff[k])
