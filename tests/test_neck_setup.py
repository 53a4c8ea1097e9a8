"""Neck passage setup: pipette profile, seal mask, suction update, peripheral measures."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import Basis, ElementTriP2, ElementVector

from oocyte_fe.errors import InputError
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
from oocyte_fe.neck.periphery import POLAR_DEG, MaterialPoints
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.neck.suction import seal_mask


def test_wall_radius_bore_taper_neck() -> None:
    p = NeckedPipette(100.0, 75.0, 200.0)
    z = np.array([-500.0, -200.0, -100.0, 0.0, 300.0])
    # cosine taper: midway the radius is the mean of bore and neck
    assert np.allclose(p.wall_radius(z), [100.0, 100.0, 87.5, 75.0, 75.0], atol=1e-9)
    assert p.taper_half_angle_deg == pytest.approx(np.degrees(np.arctan(np.pi * 25 / 400)))


@pytest.mark.parametrize("clearance", [0.1, 2.0, -1e-4])
def test_touching_places_the_sphere_at_the_clearance(clearance: float) -> None:
    p = NeckedPipette().touching(90.0, clearance)
    gap, _ = p.obstacle().distance(np.zeros((2, 1)))
    assert gap[0] == pytest.approx(90.0 + clearance, abs=1e-7)
    # the sphere fits the bore but not the neck: the touching point is on the taper
    assert p.z_neck_um - p.taper_length_um < 0.0 < p.z_neck_um + 90.0


def test_pipette_rejects_a_neck_wider_than_the_bore() -> None:
    with pytest.raises(InputError, match="bore_radius_um"):
        NeckedPipette(bore_radius_um=70.0, neck_radius_um=75.0)


def test_seal_mask_is_the_surface_ahead_of_the_rearmost_wall_contact() -> None:
    p = NeckedPipette(100.0, 75.0, 200.0)  # neck from Z = 0
    z = np.array([-300.0, -150.0, -50.0, 20.0, 60.0])
    r = p.wall_radius(z) - np.array([20.0, 5.0, 0.1, 0.2, 30.0])  # 3rd, 4th at the wall
    mask = seal_mask(p, 0.5)(np.stack([r, z]))
    assert mask[:2].tolist() == [0.0, 0.0] and mask[3:].tolist() == [1.0, 1.0]
    assert 0.0 < mask[2] < 1.0  # the seal's rear edge sits on the ramp
    assert not seal_mask(p, 0.5)(np.stack([r - 1.0, z])).any()  # no contact: no seal


def test_seal_mask_is_continuous_in_the_configuration() -> None:
    p = NeckedPipette(100.0, 75.0, 200.0)
    z = np.linspace(-200.0, 100.0, 301)
    where = seal_mask(p, 0.5)
    base = where(np.stack([p.wall_radius(z) - 0.3, z]))
    moved = where(np.stack([p.wall_radius(z) - 0.3 - 1e-6, z]))  # a tiny move off the wall
    assert np.max(np.abs(moved - base)) < 1e-4


def test_periphery_points_sit_at_the_exact_polar_angles_on_the_surface() -> None:
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=10.0))
    pts = MaterialPoints.on_surface(mesh)
    assert np.allclose(pts.polar_deg, POLAR_DEG, atol=1e-9)
    # on the polygon of the meshed surface: within the chord sag (h^2 / 8R) of R = 90 um
    radius = np.hypot(*pts.position_um)
    assert np.all(radius <= 90.0 + 1e-9) and np.all(radius > 90.0 - 10.0**2 / (8 * 90.0))


def test_periphery_measures_evaluate_the_p2_field_exactly() -> None:
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=10.0))
    pts = MaterialPoints.on_surface(mesh)
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    # a quadratic field lies in P2: its trace is reproduced exactly at any surface point
    eps, w, c = 0.05, 37.0, 1e-4

    def field(x: np.ndarray) -> np.ndarray:
        return np.stack([-eps * x[0] + c * x[0] * x[1], -eps * x[1] + w + c * x[0] ** 2])

    u = basis.project(field)
    up = pts.displacement(basis, u)
    assert np.allclose(up, field(pts.position_um), atol=1e-9)
    assert np.allclose(pts.radial_inward(up), -field(pts.position_um)[0], atol=1e-9)
    rel = field(pts.position_um) - np.array([[0.0], [w]])
    assert np.allclose(pts.deformation(up, w), np.hypot(*rel), atol=1e-9)
