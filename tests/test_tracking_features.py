"""HOG cell votes (oocyte_fe.tracking.features) on images of known gradient direction."""

from __future__ import annotations

import numpy as np
import pytest

from oocyte_fe.tracking.features import orientation_votes


def _ramp(angle_deg: float, n: int = 16) -> np.ndarray:
    y, x = np.mgrid[0:n, 0:n].astype(float)
    a = np.radians(angle_deg)
    return 3.0 * (np.cos(a) * x + np.sin(a) * y)  # |grad I| = 3 inside the border


@pytest.mark.parametrize(
    ("angle", "bins"),
    [
        (0.0, {8: 0.5, 0: 0.5}),  # theta = 0: half a bin below bin 0's centre, wraps to bin 8
        (90.0, {4: 1.0}),  # theta = pi/2: the centre of bin 4 (bins of 20 deg, centres 10 + 20k)
        (170.0, {8: 1.0}),  # the last bin's centre
        (-30.0, {7: 1.0}),  # a falling ramp: unsigned orientation 150 deg, bin 7's centre
        (45.0, {1: 0.25, 2: 0.75}),  # 45 deg = 2.25 bins: a quarter to bin 1, 3/4 to bin 2
    ],
)
def test_votes_split_between_the_two_nearest_orientation_bins(angle: float, bins: dict):
    votes = orientation_votes(_ramp(angle), 4, 9)
    inner = votes[1:-1, 1:-1]  # cells clear of the zero-gradient border
    expected = np.zeros(9)
    for k, share in bins.items():
        expected[k] = share * 3.0 * 16  # |grad I| x 16 pixels per cell
    np.testing.assert_allclose(inner, np.broadcast_to(expected, inner.shape), atol=1e-9)
