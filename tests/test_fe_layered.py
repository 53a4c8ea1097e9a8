"""The layered (ZP/cytoplasm) gmsh oocyte in the FE core, derived fields, the AFM material chain."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from afm.material_file import MaterialFile, write_material
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.fields import stress_fields
from oocyte_fe.fe.loads import FollowerPressure, PinnedPoint, Prescribed
from oocyte_fe.fe.material import Material, read_material_file
from oocyte_fe.fe.solver import Problem
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
from tests.fe_geometry import rectangle


def composite_sphere_ur(r, a, b, K1, mu1, K2, mu2, p):
    """Bonded solid sphere (radius a) in a shell (a..b) under outer pressure p, small strain.

    Core ``u = A1 r``; shell ``u = A2 r + B2 / r^2``; ``sigma_rr = 3K A - 4 mu B / r^3``;
    continuity of ``u`` and ``sigma_rr`` at ``a``; ``sigma_rr(b) = -p``.
    """
    M = np.array(
        [
            [a, -a, -1 / a**2],
            [3 * K1, -3 * K2, 4 * mu2 / a**3],
            [0.0, 3 * K2, -4 * mu2 / b**3],
        ]
    )
    A1, A2, B2 = np.linalg.solve(M, [0.0, 0.0, -p])
    return np.where(r <= a, A1 * r, A2 * r + B2 / r**2)


def test_layered_sphere_under_pressure_matches_composite_lame() -> None:
    geom = LayeredOocyte(cytoplasm_radius_um=75.0, zona_thickness_um=15.0, size_um=6.0)
    mesh = layered_oocyte_mesh(geom)
    zp, cyto = Material(7.0, 0.3), Material(1.55, 0.45)
    body = Body(mesh, {"zona": zp, "cytoplasm": cyto}, "axisymmetric")
    p = 0.01  # kPa
    prob = Problem(
        body,
        [Prescribed("axis", 0), PinnedPoint((0.0, 0.0), 1)],  # u_Z(centre) = 0: no rigid motion
        [FollowerPressure("outer_surface", lambda t: p * t)],
    )
    x = prob.solve([1.0]).frames[-1].x
    u = prob.body.vertex_displacement(x)
    r = np.hypot(*mesh.p)
    ok = r > 1.0
    ur = (u[0, ok] * mesh.p[0, ok] + u[1, ok] * mesh.p[1, ok]) / r[ok]
    K = [m.E_kPa / (3 * (1 - 2 * m.nu)) for m in (cyto, zp)]
    exact = composite_sphere_ur(r[ok], 75.0, 90.0, K[0], cyto.mu, K[1], zp.mu, p)
    assert np.max(np.abs(ur - exact)) / np.max(np.abs(exact)) < 0.01


def test_von_mises_and_mean_stress_in_uniaxial_tension() -> None:
    E, strain = 3.0, 1e-3
    body = Body(rectangle(1.0, 1.0, 3, 3), {"solid": Material(E, 0.5)}, "axisymmetric")
    prob = Problem(
        body,
        [
            Prescribed("left", 0),
            Prescribed("bottom", 1),
            Prescribed("top", 1, lambda t: strain * t),
        ],
    )
    x = prob.solve([1.0]).frames[-1].x
    fields = stress_fields(prob, x)
    sigma = E * strain  # small strain, incompressible: sigma_zz = 3 G eps = E eps
    assert np.allclose(fields["von_mises"], sigma, rtol=5e-3)
    assert np.allclose(fields["mean_stress"], sigma / 3, rtol=5e-3)


def test_material_file_written_by_afm_is_read_by_fe(tmp_path: Path) -> None:
    path = write_material(
        MaterialFile("zona_pellucida", "test", 7.01, 0.5, (0.3, 0.2), (0.2, 1.5)),
        tmp_path / "zp.toml",
    )
    mat = read_material_file(path)
    assert mat.E_kPa == pytest.approx(7.01) and mat.nu == 0.5
    assert mat.prony.g == (0.3, 0.2) and mat.prony.tau_s == (0.2, 1.5)
    assert mat.mu == pytest.approx(7.01 / 3)
    assert mat.prony.relaxation(np.array([0.0]))[0] == pytest.approx(1.0)
