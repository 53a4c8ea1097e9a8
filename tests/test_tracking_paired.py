"""Paired comparison on perturbed copies (:mod:`oocyte_fe.tracking.paired`)."""

from __future__ import annotations

import numpy as np
import pytest

from oocyte_fe.tracking.benchmark import BenchmarkResult, SequenceScore
from oocyte_fe.tracking.paired import paired_differences, paired_table, perturbed
from oocyte_fe.tracking.synthetic import Sequence, benchmark_grid

SPEC = benchmark_grid()[0]


def _flat(spec) -> Sequence:
    frames = np.full((3, 40, 50), 2000.0)
    boxes = np.tile([10.0, 10.0, 20.0, 10.0], (3, 1))
    return Sequence(spec, frames, boxes, np.zeros(3, dtype=bool))


def test_a_copy_is_the_frames_times_one_plus_eps_noise_and_repeats():
    a = perturbed(_flat, 1e-4, 1)(SPEC).frames
    rel = a / 2000.0 - 1.0
    assert rel.std() == pytest.approx(1e-4, rel=0.05)  # 6000 pixels: the std within 5 %
    np.testing.assert_array_equal(a, perturbed(_flat, 1e-4, 1)(SPEC).frames)  # same copy
    assert not np.array_equal(a, perturbed(_flat, 1e-4, 2)(SPEC).frames)  # another copy
    np.testing.assert_array_equal(perturbed(_flat, 0.0, 3)(SPEC).frames, _flat(SPEC).frames)


@pytest.mark.parametrize(
    "eps, copy", [(-1e-4, 1), (float("nan"), 1), (float("inf"), 1), (1.0, 1), (1e-4, -1)]
)
def test_nonsense_perturbations_are_refused(eps: float, copy: int):
    with pytest.raises(ValueError, match="eps|copy"):
        perturbed(_flat, eps, copy)


def _result(errors: dict[str, list[float]]) -> BenchmarkResult:
    scores = [
        SequenceScore(name, SPEC.name, np.array(e), np.full(len(e), 0.5), 100.0, [])
        for name, e in errors.items()
    ]
    return BenchmarkResult(scores, {SPEC.name: SPEC}, None, list(errors))


def test_the_paired_difference_is_taken_copy_by_copy():
    # copy 1: baseline 4 of 4 frames within 20 px, the other 2 of 4; copy 2: 2 and 3 of 4
    copies = [
        _result({"MFAKCF": [0, 1, 2, 3], "other": [0, 1, 30, 40]}),
        _result({"MFAKCF": [0, 1, 30, 40], "other": [0, 1, 2, 40]}),
    ]
    d = paired_differences(copies, "other")
    np.testing.assert_allclose(d[:, 0], [-0.5, 0.25])
    np.testing.assert_allclose(d[:, 1], [0.0, 0.0])  # the same overlaps
    table = paired_table(copies, ["MFAKCF", "other"], "MFAKCF")
    assert "-0.125 (-0.500 to +0.250)" in table
