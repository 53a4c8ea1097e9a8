"""Sensitivity indices of a sweep: intervals, the zero flag, the sample-count warning."""

from __future__ import annotations

import numpy as np

from oocyte_fe.sweep.report import _sensitivity_table
from oocyte_fe.sweep.statistics import RECOMMENDED, Z95, bootstrap_conf, sensitivity


def _design(n: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """``y = 2 x0 + 0.1 noise`` on the unit square; ``x1`` has no influence."""
    rng = np.random.default_rng(seed)
    x = rng.random((n, 2))
    return x, 2.0 * x[:, 0] + 0.1 * rng.standard_normal(n)


def test_bootstrap_half_width_of_a_mean_matches_its_standard_error() -> None:
    """For the mean, the bootstrap SD is the standard error s / sqrt(n) (to a few %)."""
    rng = np.random.default_rng(0)
    y = rng.normal(5.0, 2.0, 400)
    conf = bootstrap_conf(lambda _x, ys: np.array([ys.mean()]), y[:, None], y, seed=1)
    expected = Z95 * y.std(ddof=1) / np.sqrt(len(y))
    assert abs(conf[0] / expected - 1) < 0.15  # 200 resamples: SD of an SD estimate ~5 %


def test_rbd_fast_flags_the_inert_input_and_resolves_the_active_one() -> None:
    x, y = _design(128)
    s = sensitivity(x, y, ["a", "b"], "rbd_fast", seed=0)
    assert s is not None and s.n == 128
    assert s.index["a"] > 0.8 and not s.spans_zero("a")
    assert abs(s.index["b"]) < 0.1 and s.spans_zero("b")
    assert not s.too_few


def test_pawn_gets_a_bootstrap_interval() -> None:
    x, y = _design(200)
    s = sensitivity(x, y, ["a", "b"], "pawn", seed=0)
    assert s is not None
    assert all(0.0 < s.conf[n] < 0.3 for n in "ab")  # SALib gives none; ours is finite
    assert not s.spans_zero("a") and s.index["a"] > s.index["b"] + 2 * s.conf["b"]
    assert not s.too_few  # 200 samples >= the 100 recommended for PAWN


def test_report_warns_below_the_recommended_count_and_marks_zero_intervals() -> None:
    x, y = _design(32)
    s = sensitivity(x, y, ["a", "b"], "rbd_fast", seed=0)
    assert s is not None and s.too_few
    text = _sensitivity_table({"y": s}, ["a", "b"], "rbd_fast", 32)
    assert f"below the {RECOMMENDED['rbd_fast']} recommended" in text
    row = next(line for line in text.splitlines() if line.startswith("| y |")).split("|")
    assert "(0 in interval)" in row[3] and "(0 in interval)" not in row[2]  # b, not a
    assert "1 of 2 indices" in text
    x, y = _design(96)
    s = sensitivity(x, y, ["a", "b"], "rbd_fast", seed=0)
    assert s is not None
    assert "Warning" not in _sensitivity_table({"y": s}, ["a", "b"], "rbd_fast", 96)
