"""Adaptive template update, loss detection and re-detection (seed 000, Section II.A: "a
template adaptive update mechanism ... to mitigate the influence of lipid droplets").

After each frame the fused response gives its peak ``F_max`` and :func:`.fusion.apce`. Both
are compared with their running means over the frames accepted so far (the update criterion
of Wang et al. 2017, LMCF, Section 3.3, who update only if ``F_max >= beta_1 <F_max>`` and
``APCE >= beta_2 <APCE>`` with beta_1 = 0.7, beta_2 = 0.45). Here the two ratios become one
reliability::

    r = min( (F_max / <F_max>) / beta_1,  (APCE / <APCE>) / beta_2 )

and the learning rate falls linearly from ``eta_0`` at ``r >= 1`` to zero at ``r <= r_stop``::

    eta = eta_0 clip((r - r_stop) / (1 - r_stop), 0, 1)

so the template stops learning while a droplet covers the spindle or the light collapses, and
resumes when the response recovers. The running means are updated only with frames of
``r >= 1``. When ``r < r_lost`` the target is declared lost: the tracker then searches a wider
area (a grid of windows around the last position, :mod:`.tracker`) each frame and takes the
best candidate back once its ``r >= r_found``. ``r_lost`` = 0.42 and ``r_found`` = 0.7 were
chosen on 5 of the 24 benchmark sequences among (0.5, 0.8), (0.42, 0.7) and (0.35, 0.6): mean
precision at 20 px about 0.73, 0.89 and 0.76 on those five (docs/tracking.md says so beside the
table); ``beta_1``, ``beta_2`` are LMCF's. With the motion model (:mod:`.motion`) ``r_stop``
also bounds the doubtful band ``r_lost <= r < r_stop`` in which the centre coasts, and inside
the validation gate a lost target is taken back at ``r_lost``: both rules were chosen on the
benchmark's 6-sequence tuning subset (docs/tracking.md).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class UpdatePolicy:
    """Thresholds of the adaptive update (dimensionless; see module doc)."""

    eta0: float = 0.02
    beta_peak: float = 0.7
    beta_apce: float = 0.45
    r_stop: float = 0.6
    r_lost: float = 0.42
    r_found: float = 0.7
    warmup: int = 5

    def __post_init__(self) -> None:
        if not 0 <= self.eta0 <= 1:
            raise ValueError(f"eta0 must be in [0, 1], got {self.eta0}")
        if not 0 <= self.r_lost <= self.r_stop < 1:
            raise ValueError("expected 0 <= r_lost <= r_stop < 1")


@dataclass
class ReliabilityHistory:
    """Running means of ``F_max`` and APCE over the accepted frames."""

    policy: UpdatePolicy
    n: int = 0
    peak_sum: float = 0.0
    apce_sum: float = 0.0

    def reliability(self, peak: float, apce_value: float) -> float:
        """``r`` of the module doc; 1 before any frame has been accepted."""
        if self.n < self.policy.warmup:
            return 1.0
        rp = peak * self.n / max(self.peak_sum, 1e-12) / self.policy.beta_peak
        ra = apce_value * self.n / max(self.apce_sum, 1e-12) / self.policy.beta_apce
        return min(rp, ra)

    def learning_rate(self, r: float) -> float:
        """``eta = eta_0 clip((r - r_stop) / (1 - r_stop), 0, 1)``."""
        p = self.policy
        return p.eta0 * min(max((r - p.r_stop) / (1.0 - p.r_stop), 0.0), 1.0)

    def accept(self, peak: float, apce_value: float, r: float) -> None:
        """Add a frame to the running means if it is fully reliable (``r >= 1``); the first
        ``policy.warmup`` frames are taken as they come (they set the reference)."""
        if r >= 1.0 or self.n < self.policy.warmup:
            self.n += 1
            self.peak_sum += peak
            self.apce_sum += apce_value
