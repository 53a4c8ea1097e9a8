"""Paired comparison of trackers on perturbed copies of the same sequences.

A pooled benchmark figure over 12-24 sequences carries a part that is chance: the hard
sequences' outcomes (a loss in the fast push, a re-detection that may or may not find the
spindle) flip under a change of the frames far below their noise. Multiplying every frame by

    I' = I (1 + eps n),   n ~ N(0, 1) per pixel, one draw per copy and sequence,

with ``eps`` = 1e-4 (0.2 e- on a pixel of 2000 e-, 200 times below its shot noise) moves a
draw's pooled precision @20 px by up to 0.04-0.06 (docs/tracking.md, "How much of a figure is
chance"). Two trackers run on the SAME copies differ by much less from copy to copy, so the
paired difference ``d_k = P_k(tracker) - P_k(baseline)`` over copies ``k`` separates a small
real gain from that chance: its mean and its range are what this module reports.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from oocyte_fe.tracking.benchmark import BenchmarkResult


def perturbed(render: Callable, eps: float, copy: int) -> Callable:
    """A renderer like ``render`` (spec -> sequence) whose frames are multiplied by
    ``1 + eps n`` (module doc); the draw of ``n`` is fixed by ``copy`` and the spec's seed,
    so every tracker sees the same copy."""
    if not 0 <= eps < 1:  # NaN fails too; from 1 on, intensities may turn negative
        raise ValueError(f"eps must be a relative perturbation in [0, 1), got {eps}")
    if copy < 0:
        raise ValueError(f"copy must be >= 0, got {copy}")

    def render_copy(spec):
        seq = render(spec)
        rng = np.random.default_rng([copy, spec.seed])
        noise = rng.standard_normal(seq.frames.shape)
        return replace(seq, frames=seq.frames * (1.0 + eps * noise))

    return render_copy


FIGURES = ("precision_20px", "success_auc")


def figures(result: BenchmarkResult, tracker: str) -> np.ndarray:
    """Pooled precision @20 px and success AUC of ``tracker`` over every sequence."""
    summary = result.summary(tracker)
    if summary is None:
        raise ValueError(f"no scores of tracker {tracker!r}")
    return np.array([summary[k] for k in FIGURES])


def _per_copy(copies: list[BenchmarkResult], tracker: str) -> np.ndarray:
    """The tracker's :func:`figures` on each copy, (copies, 2)."""
    return np.array([figures(r, tracker) for r in copies])


def paired_differences(
    copies: list[BenchmarkResult], tracker: str, baseline: str = "MFAKCF"
) -> np.ndarray:
    """``d_k`` (copies, 2): the tracker's pooled figures less the baseline's on each copy."""
    return _per_copy(copies, tracker) - _per_copy(copies, baseline)


def paired_table(copies: list[BenchmarkResult], trackers: list[str], baseline: str) -> str:
    """Markdown: each tracker's figures per copy, and its paired difference from the
    baseline (mean and range over the copies)."""
    head = "| tracker | " + " | ".join(f"copy {k + 1}" for k in range(len(copies)))
    lines = [head + " | paired difference, mean (range) |", "|---" * (len(copies) + 2) + "|"]
    base = _per_copy(copies, baseline)
    for name in trackers:
        own = _per_copy(copies, name)
        cells = [" / ".join(f"{v:.3f}" for v in row) for row in own]
        if name == baseline:
            diff = "-"
        else:
            d = own - base
            diff = " / ".join(
                f"{m:+.3f} ({lo:+.3f} to {hi:+.3f})"
                for m, lo, hi in zip(d.mean(0), d.min(0), d.max(0), strict=True)
            )
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {diff} |")
    return "\n".join(lines)
