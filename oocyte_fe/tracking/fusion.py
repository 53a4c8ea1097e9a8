"""Reliability of a correlation response and the adaptive fusion of two feature responses.

Reliability measure: the average peak-to-correlation energy (APCE) of Wang, Liu and Huang 2017
("Large margin object tracking with circulant feature maps", CVPR, eq 4)::

    APCE = |F_max - F_min|^2 / mean_{w,h} (F_{w,h} - F_min)^2

Why APCE rather than the peak-to-sidelobe ratio ``PSR = (F_max - mu_s) / sigma_s`` of Bolme
et al. 2010 (MOSSE, CVPR): PSR looks only at a sidelobe ring outside an arbitrary exclusion
window (11 x 11 in MOSSE), which on a cell-wise map of 10-30 cells is most of the map; APCE
uses the whole map with no window to choose, and it falls sharply when a second peak appears
(a lipid droplet next to the spindle) or the map becomes flat and noisy (occlusion, light
drop), the two failures this tracker has to see. LMCF used the same measure to gate the model
update, so one measure serves both fusion and update (:mod:`.update`).

Fusion (seed 000, Algorithm 1, line 5, at the response level: each feature has its own
filter)::

    phi = w_hog phi_hog + w_gray phi_gray,   w_k = q_k / sum_j q_j,   q_k = APCE_k / <APCE_k>

``<APCE_k>`` is the mean APCE of feature k over the frames accepted as reliable so far, so
each feature is judged against its own normal sharpness and the weights are 1/2, 1/2 when
both behave as usual; a feature whose response degrades hands its weight to the other.
"""

from __future__ import annotations

import numpy as np


def apce(response: np.ndarray) -> float:
    """Average peak-to-correlation energy of a response map (dimensionless, >= 1)."""
    fmax = float(response.max())
    fmin = float(response.min())
    energy = float(np.mean((response - fmin) ** 2))
    return (fmax - fmin) ** 2 / energy if energy > 0 else 0.0


def fusion_weights(apces: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``w_k = q_k / sum q``, ``q_k = APCE_k / <APCE_k>``; equal weights if all q are 0."""
    q = np.asarray(apces, dtype=float) / np.maximum(np.asarray(reference, dtype=float), 1e-12)
    total = q.sum()
    return q / total if total > 0 else np.full(q.shape, 1.0 / q.size)


def fuse(responses: list[np.ndarray], weights: np.ndarray) -> np.ndarray:
    """``phi = sum_k w_k phi_k`` over responses on the same cell grid."""
    return sum(w * r for w, r in zip(weights, responses, strict=True))
