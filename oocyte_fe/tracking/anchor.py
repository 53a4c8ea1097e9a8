"""Re-find check against an anchor template: the target as it looked in its first frames.

The adaptive template of :mod:`.kcf` follows the target's appearance, and with it whatever
static structure it learned while the target was faint (a droplet, the zona's edge, the
pipette's wall, docs/tracking.md). A lost target is searched for with that template
(:mod:`.tracker`), and on a faint spindle the best window it finds is often such a structure.
The anchor keeps a second, frozen copy of each feature's filter, the mean over the first
``n`` frames the tracker accepted with full reliability (``r >= 1``, :mod:`.update`)::

    x_hat_A = (1 / n) sum_i x_hat_i,   alpha_hat_A = (1 / n) sum_i alpha_hat_i

(the running mean ``x_hat_A <- x_hat_A + (x_hat_i - x_hat_A) / i``, the template update of
:class:`.kcf.KcfModel` with the rate ``1 / i``). Its score of a window ``z`` centred on a
candidate is the mean of the features' anchor responses near zero shift::

    A(z) = max_{|d_x|, |d_y| <= 1 cell}  (1 / K) sum_k f_A,k(z)[d]

and ``<A>`` is the mean of ``A`` over the tracked frames with ``r >= 1`` after the anchor is
complete (every 4th such frame: the check costs two kernel correlations). A re-detected
candidate is taken back only if ``A(z) >= verify <A>``; otherwise the target stays lost and
the search goes on. This is the long-term / short-term split of long-term correlation
trackers (Ma, Yang, Zhang and Yang 2015, LCT, CVPR: a conservatively updated filter decides
re-detection; here it is frozen after the first frames), with the scale-free appearance
check the adaptive template cannot give against itself. ``verify`` = 0.6 and ``n`` = 30 were
chosen on the benchmark's tuning subset (docs/tracking.md).

Assumption: the first ``n`` reliable frames show the target (the operator's box is right,
as the benchmark's and the enucleation loop's first frames do).
"""

from __future__ import annotations

import numpy as np

from oocyte_fe.tracking.kcf import KcfModel, respond_models, update_models

NEAR = np.array([-1, 0, 1])
"""Cell shifts within one cell of zero, in both axes (the response is periodic)."""


class ScoreReference:
    """The mean score of the tracked frames noted so far: what a candidate's score is
    compared with (the anchor's ``<A>``, the rotation bank's ``<B>``)."""

    def __init__(self) -> None:
        self.score_sum = 0.0
        self.score_n = 0

    def note(self, score: float) -> None:
        """Add a tracked frame's score to the reference."""
        self.score_sum += score
        self.score_n += 1

    @property
    def reference(self) -> float | None:
        """The mean score, or None before any tracked frame was scored."""
        return self.score_sum / self.score_n if self.score_n else None


class Anchor(ScoreReference):
    """The frozen first-frames filters and their reference score (module doc)."""

    def __init__(self, models: list[KcfModel], n_frames: int) -> None:
        if n_frames < 1:
            raise ValueError(f"the anchor needs n_frames >= 1, got {n_frames}")
        self.models = [KcfModel(m.xf.copy(), m.alphaf.copy(), m.sigma, m.lam) for m in models]
        self.n_frames = n_frames
        self.n = 1
        super().__init__()

    @property
    def complete(self) -> bool:
        """True once ``n_frames`` frames are in the mean (then it is frozen)."""
        return self.n >= self.n_frames

    def learn(self, feats: list[np.ndarray], yf: np.ndarray) -> None:
        """Add one reliable frame's feature DFTs to the mean (no-op once complete)."""
        if self.complete:
            return
        self.n += 1
        update_models(self.models, feats, yf, 1.0 / self.n)

    def score(self, feats: list[np.ndarray]) -> float:
        """``A(z)``: the mean anchor response's maximum within one cell of zero shift."""
        response = sum(respond_models(self.models, feats))
        near = response[np.ix_(NEAR, NEAR)] / len(self.models)  # shifts -1, 0, 1 (wrapped)
        return float(near.max())
