"""Rigid obstacle geometry: signed distance, normal and level-set curvature (exact values)."""

from __future__ import annotations

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.fe.obstacles import Circle, Polyline, rounded_corners, wedge_tip


def test_sharp_wedge_distances_to_mouth_flank_and_corner() -> None:
    # mouth at x = 0 between y = -10 and 10, advancing along -x; flanks open behind at 12.5 deg
    w = wedge_tip((0.0, 0.0), (-1.0, 0.0), 20.0, 25.0, 50.0)
    x = np.array([[-5.0, 2.0, -3.0], [0.0, 0.0, 14.0]])
    g, n, kappa = w.distance_curvature(x)
    assert g[0] == pytest.approx(5.0) and n[:, 0] == pytest.approx([-1.0, 0.0])
    assert g[1] == pytest.approx(-2.0)  # inside the glass, 2 um behind the mouth
    assert g[2] == pytest.approx(5.0)  # nearest to the corner (0, 10): |(-3, 4)|
    assert n[:, 2] == pytest.approx([-0.6, 0.8])
    # faces are straight; about the corner n turns at the rate 1 / distance
    assert kappa == pytest.approx([0.0, 0.0, 0.2])


@pytest.mark.parametrize("radius", [0.5, 2.0])
def test_rounded_wedge_edges_are_arcs_tangent_to_mouth_and_flank(radius: float) -> None:
    """A mouth edge of interior angle 2 beta = 90 + 12.5 deg rounded with radius r: the arc's
    centre lies r / sin(beta) from the corner on the bisector, so a point D beyond the corner
    on the bisector is D + r / sin(beta) - r from the glass (the chords' ends are on the arc:
    at an end, exactly); the mouth's middle and the flank far from the edge are unchanged."""
    sharp = wedge_tip((0.0, 0.0), (-1.0, 0.0), 20.0, 25.0, 50.0)
    w = wedge_tip((0.0, 0.0), (-1.0, 0.0), 20.0, 25.0, 50.0, edge_radius=radius)
    beta = np.deg2rad(0.5 * (90.0 + 12.5))
    u = np.array([0.0, -1.0])  # from the corner (0, 10) along the mouth
    v = np.array([np.cos(np.deg2rad(12.5)), np.sin(np.deg2rad(12.5))])  # along the flank
    bis = -(u + v) / np.linalg.norm(u + v)  # outwards, away from the glass
    centre = np.array([0.0, 10.0]) - bis * radius / np.sin(beta)
    pts = np.array(w.points)
    on_arc = np.abs(np.linalg.norm(pts - centre, axis=1) - radius) < 1e-12
    assert on_arc.sum() == 8  # 7 chords for the 77.5 deg turn (8 per quarter circle)
    ends = pts[on_arc][[0, -1]] - np.array([0.0, 10.0])
    cut = radius / np.tan(beta)
    assert sorted(np.linalg.norm(ends, axis=1)) == pytest.approx([cut, cut], rel=1e-12)
    D = 3.0
    x = (np.array([0.0, 10.0]) + D * bis)[:, None]
    chord_sag = radius * (1 - np.cos(0.5 * np.deg2rad(77.5) / 7))  # largest gap arc - chords
    g = w.distance(x)[0][0]
    assert D + radius / np.sin(beta) - radius <= g <= D + radius / np.sin(beta) - radius + chord_sag
    far = np.array([[-5.0, 5.0], [0.0, 30.0]])  # mouth middle; beside the flank, far back
    assert w.distance(far)[0] == pytest.approx(sharp.distance(far)[0], abs=1e-12)


def test_rounding_keeps_a_vertex_where_the_polyline_runs_straight_on() -> None:
    pts = rounded_corners([(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0)], 0.5)
    assert pts[:2] == [(0.0, 0.0), (1.0, 0.0)]  # the straight vertex kept, no NaN
    assert pts[2] == pytest.approx((1.5, 0.0)) and pts[-2] == pytest.approx((2.0, 0.5))
    assert np.all(np.isfinite(pts))


def test_an_edge_radius_that_does_not_fit_the_mouth_is_refused() -> None:
    with pytest.raises(InputError, match="radius"):
        wedge_tip((0.0, 0.0), (-1.0, 0.0), 2.0, 25.0, 50.0, edge_radius=2.0)


def test_curvature_is_the_rate_at_which_the_normal_turns() -> None:
    """dn/dx = kappa t t^T, checked by central differences: circle outside and inside, and
    the reflex corner of an L-shaped solid (n turns about the vertex inside the glass)."""
    circle = Circle((0.0, 0.0), 1.5)
    ell = Polyline(((-2.0, 0.5), (0.0, 0.5), (0.0, -1.5)))  # solid: y > 0.5 or x > 0
    cases = [
        (circle, np.array([[2.0, 0.3], [1.0, -0.8]])),
        (ell, np.array([[0.1, 0.2, 0.05], [0.6, 0.7, 0.9]])),
    ]
    h = 1e-6
    for obstacle, x in cases:
        g, n, kappa = obstacle.distance_curvature(x)
        t = np.stack([-n[1], n[0]])
        for j in range(2):
            dx = np.zeros_like(x)
            dx[j] = h
            dn = (obstacle.distance(x + dx)[1] - obstacle.distance(x - dx)[1]) / (2 * h)
            np.testing.assert_allclose(dn, kappa * t * t[j], atol=1e-6)
    assert circle.distance_curvature(np.array([[2.0], [0.0]]))[2] == pytest.approx([0.5])
    g, _, kappa = ell.distance_curvature(np.array([[0.3], [0.9]]))
    assert g[0] == pytest.approx(-0.5) and kappa[0] == pytest.approx(-2.0)  # inside, at the vertex
