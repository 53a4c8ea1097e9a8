"""Self-contact of a boundary (fe/self_contact.py) and the outline's crossing check
(experiment/outline.py): the pair's gap derivatives against finite differences, two blocks
pressed together through their own contact against the closed form of plane-strain
compression, and the crossing count against polygons with known crossings."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq
from skfem import MeshTri

from oocyte_fe.errors import InputError
from oocyte_fe.experiment.outline import (
    body_outline_um,
    crossing_points,
    facet_length_um,
    polygon_crossings,
)
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.loads import Prescribed
from oocyte_fe.fe.material import Material
from oocyte_fe.fe.self_contact import SelfContact, gap_derivatives
from oocyte_fe.fe.solver import Problem
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh


def test_the_gap_gradient_and_hessian_match_finite_differences():
    """g = s (e x r) / |e| of random pairs: central differences (h = 1e-6) agree with the
    analytic gradient and Hessian within 1e-7 (their truncation error is O(h^2))."""
    rng = np.random.default_rng(3)
    q = rng.normal(size=(6, 6))
    side = np.array([1.0, -1.0, 1.0, -1.0, 1.0, 1.0])

    def at(qq):
        return gap_derivatives(qq[:, 0:2], qq[:, 2:4], qq[:, 4:6], side)

    _, dg, hg = at(q)
    h = 1e-6
    for j in range(6):
        step = np.zeros(6)
        step[j] = h
        gp, dgp, _ = at(q + step)
        gm, dgm, _ = at(q - step)
        assert np.allclose((gp - gm) / (2 * h), dg[:, j], atol=1e-7)
        assert np.allclose((dgp - dgm) / (2 * h), hg[:, :, j], atol=1e-7)


W, H, GAP = 1.0, 1.0, 0.1  # two W x H blocks, GAP apart (um)


def _two_blocks(n_left: int, n_right: int) -> MeshTri:
    """Two square blocks side by side, meshed apart (nodes not facing each other)."""
    a = MeshTri.init_tensor(
        np.linspace(-W - GAP / 2, -GAP / 2, n_left + 1), np.linspace(0, H, n_left + 1)
    )
    b = MeshTri.init_tensor(
        np.linspace(GAP / 2, W + GAP / 2, n_right + 1), np.linspace(0, H, n_right + 1)
    )
    mesh = MeshTri(np.hstack([a.p, b.p]), np.hstack([a.t, b.t + a.p.shape[1]]))
    tol = 1e-9
    return mesh.with_boundaries(
        {
            "left": lambda x: np.abs(x[0] + W + GAP / 2) < tol,
            "right": lambda x: np.abs(x[0] - W - GAP / 2) < tol,
            "bottom": lambda x: np.abs(x[1]) < tol,
            "faces": lambda x: np.abs(np.abs(x[0]) - GAP / 2) < tol,
        }
    ).with_subdomains({"solid": lambda x: np.ones(x.shape[1], dtype=bool)})


def test_two_blocks_pressed_together_meet_plane_strain_compression():
    """Two incompressible neo-Hookean blocks (E = 3 kPa) on rollers, pushed together by
    0.15 um at their outer ends, touch across their facing sides (one boundary, its own
    contact). Each is then in plane-strain uniaxial compression: F = diag(lambda,
    1 / lambda), nominal stress P = mu (lambda^-3 - lambda), with the approach
    W (1 - lambda) = delta - (GAP - g_hat + pen) / 2 and the penalty's give
    pen = P / (2 eps) (both sides' nodes push on the other's segments). The force per unit
    depth agrees within 0.5 % (meshes 4 and 5 across, not facing node to node), and the two
    ends' reactions balance to round-off (the contact forces are internal)."""
    E, delta, eps, g_hat = 3.0, 0.15, 200 * 3.0 / 0.2, 0.02
    body = Body(_two_blocks(4, 5), {"solid": Material(E, 0.5)}, "plane_strain")
    problem = Problem(
        body,
        [
            Prescribed("left", 0, lambda t: delta * t),
            Prescribed("right", 0, lambda t: -delta * t),
            Prescribed("bottom", 1),
        ],
        self_contact=SelfContact("faces", eps, g_hat, depth_um=0.2),
    )
    x = problem.solve(np.linspace(0.1, 1.0, 10)).frames[-1].x
    r, _, _ = problem.assemble(x, 1.0, 0.1)
    left = r[body.boundary_dofs("left", 0)].sum()
    right = r[body.boundary_dofs("right", 0)].sum()
    mu = E / 3

    def approach(lam: float) -> float:
        pen = mu * (lam**-3 - lam) / (2 * eps)
        return W * (1 - lam) - (delta - (GAP - g_hat + pen) / 2)

    lam = brentq(approach, 0.5, 1.0)
    assert left == pytest.approx(mu * (lam**-3 - lam) * H, rel=5e-3)
    assert left + right == pytest.approx(0.0, abs=1e-10 * abs(left))
    assert problem.self_contact_pairs().gap.min() > 0.0  # the faces never pass through


@pytest.mark.parametrize(
    ("field", "value"), [("penalty", 0.0), ("range_um", -1.0), ("depth_um", float("nan"))]
)
def test_self_contact_refuses_a_non_positive_setting(field: str, value: float):
    kwargs = {"penalty": 1.0, "range_um": 0.1, "depth_um": 1.0, field: value}
    with pytest.raises(InputError, match=field):
        SelfContact("outer", **kwargs)


def test_crossings_of_polygons_with_known_counts():
    """A circle: none; a figure eight and a limacon with an inner loop (r = 1/2 + cos t):
    one each; a square's vertices taken in a bow-tie order: one, at its centre."""
    t = np.linspace(0, 2 * np.pi, 51, endpoint=False) + 0.01
    r = 0.5 + np.cos(t)
    assert polygon_crossings(np.c_[np.cos(t), np.sin(t)]) == 0
    assert polygon_crossings(np.c_[np.sin(t), np.sin(2 * t)]) == 1
    assert polygon_crossings(np.c_[r * np.cos(t), r * np.sin(t)]) == 1
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    assert polygon_crossings(square[[0, 2, 1, 3]]) == 1
    assert crossing_points(square[[0, 2, 1, 3]]) == pytest.approx(np.array([[0.5, 0.5]]))


def _brute_force(x: np.ndarray) -> int:
    k, count = len(x), 0
    for i in range(k):
        for j in range(i + 2, k):
            if i == 0 and j == k - 1:
                continue
            p, q, r, s = x[i], x[(i + 1) % k], x[j], x[(j + 1) % k]

            def o(a, b, c):
                return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

            count += o(p, q, r) * o(p, q, s) < 0 and o(r, s, p) * o(r, s, q) < 0
    return count


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=4, max_value=40), st.integers(min_value=0, max_value=2**31))
def test_the_pruned_crossing_count_equals_the_brute_force_one(k: int, seed: int):
    """Random polygons (uneven edges: the k-d tree's radius is the longest edge)."""
    x = np.random.default_rng(seed).normal(size=(k, 2)) * [1.0, 0.2]
    assert polygon_crossings(x) == _brute_force(x)


@pytest.mark.parametrize("form", ["plane_strain", "axisymmetric"])
def test_the_outline_through_the_nodes_and_the_facet_length_of_a_disc(form: str):
    """A layered disc (outer radius 90 um, size 6 um), moved rigidly by (3, -2) um (plane
    strain; axisymmetric: along the axis only): the outline with its nodes has the outer
    vertices besides the quadrature points, all at the radius (the vertices exactly, the
    quadrature points of the chords within the sagitta h^2 / 8 R), and crosses itself
    nowhere; the facet length at a point on the surface is that facet's, within the mesh
    size's range."""
    mesh = layered_oocyte_mesh(
        LayeredOocyte(cytoplasm_radius_um=75.0, zona_thickness_um=15.0, size_um=6.0, form=form)
    )
    body = Body(mesh, {"zona": Material(7.0, 0.45), "cytoplasm": Material(1.55, 0.45)}, form)
    shift = np.array([3.0, -2.0]) if form == "plane_strain" else np.array([0.0, -2.0])
    x = np.zeros(body.n_u)
    x[: body.n_u] = body.ubasis.project(lambda X: shift[:, None, None] + 0.0 * X)
    plain, full = body_outline_um(body, x), body_outline_um(body, x, nodes=True)
    outer = np.unique(mesh.facets[:, body.facets("outer_surface")])
    half = 2 if form == "axisymmetric" else 1
    assert len(full) - len(plain) == half * len(outer)
    radius = np.hypot(*(full - shift).T)
    assert radius.max() == pytest.approx(90.0, abs=1e-9)
    assert radius.min() > 90.0 - 6.0**2 / (8 * 90.0) * 1.5
    assert polygon_crossings(full) == 0
    vertex = mesh.p[:, outer[0]] + shift
    h = facet_length_um(body, x, vertex[None] * (1 - 1e-3))
    lengths = np.linalg.norm(
        np.diff(mesh.p[:, mesh.facets[:, body.facets("outer_surface")]], axis=1), axis=0
    )
    assert 0.5 * 6.0 < h[0] < 1.5 * 6.0
    assert np.min(np.abs(lengths - h[0])) < 1e-12
