"""Layered oocyte and verification meshes: named groups, exact areas/volumes/lengths within
mesh-size-dependent tolerances, refinement, parameter validation and the mesh cache."""

from __future__ import annotations

import gmsh
import numpy as np
import pytest
import skfem
from skfem import Basis, ElementTriP1, ElementTriP2, FacetBasis, Functional

from oocyte_fe.errors import InputError
from oocyte_fe.mesh import (
    LayeredOocyte,
    annulus_quarter_mesh,
    block_mesh,
    layered_oocyte_mesh,
    spherical_shell_mesh,
)
from oocyte_fe.mesh.cache import cache_path

RC, T = 75.0, 15.0
R = RC + T
H = 10.0  # coarse global element size (um)


@pytest.fixture(autouse=True, scope="module")
def mesh_cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        folder = tmp_path_factory.mktemp("mesh_cache")
        mp.setenv("OOCYTE_FE_CACHE", str(folder))
        yield folder


@Functional
def _area(w):
    return 1.0 + 0.0 * w.x[0]


@Functional
def _revolved_volume(w):
    """Volume of revolution about the y axis: integral of 2 pi r dA (um^3)."""
    return 2.0 * np.pi * w.x[0]


def _element(mesh: skfem.Mesh):
    return ElementTriP2() if isinstance(mesh, skfem.MeshTri2) else ElementTriP1()


def _cells(mesh, subdomain=None):
    elements = None if subdomain is None else mesh.subdomains[subdomain]
    return Basis(mesh, _element(mesh), elements=elements, intorder=4)


def _facets(mesh, boundary):
    return FacetBasis(mesh, _element(mesh), facets=mesh.boundaries[boundary], intorder=4)


def _polygon_tol(size_um: float, radius_um: float) -> float:
    """Relative area deficit of an inscribed polygon of edge ~size: h^2 / (6 R^2), with margin."""
    return 1.5 * size_um**2 / (6.0 * radius_um**2)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("form", ["axisymmetric", "plane_strain"])
def test_layered_groups_and_areas(form, order):
    mesh = layered_oocyte_mesh(LayeredOocyte(form=form, order=order, size_um=H))
    assert isinstance(mesh, skfem.MeshTri2 if order == 2 else skfem.MeshTri1)
    assert set(mesh.subdomains) == {"cytoplasm", "zona"}
    expected = {"outer_surface", "interface"} | ({"axis"} if form == "axisymmetric" else set())
    assert set(mesh.boundaries) == expected
    # every element is in exactly one layer
    both = np.concatenate([mesh.subdomains["cytoplasm"], mesh.subdomains["zona"]])
    assert np.array_equal(np.sort(both), np.arange(mesh.t.shape[1]))

    share = 0.5 if form == "axisymmetric" else 1.0
    tol = _polygon_tol(H, RC) if order == 1 else 1e-5
    for sub, area in (("cytoplasm", np.pi * RC**2), ("zona", np.pi * (R**2 - RC**2))):
        got = _area.assemble(_cells(mesh, sub))
        assert got == pytest.approx(share * area, rel=tol * (R / RC) ** 2)
    length = _area.assemble(_facets(mesh, "interface"))
    assert length == pytest.approx(2 * share * np.pi * RC, rel=tol)


@pytest.mark.parametrize("form", ["axisymmetric", "plane_strain"])
def test_interface_is_shared_and_bonded(form):
    """Interface facets are interior: one side in the cytoplasm, the other in the zona."""
    mesh = layered_oocyte_mesh(LayeredOocyte(form=form, size_um=H))
    facets = mesh.boundaries["interface"]
    left, right = mesh.f2t[:, facets]
    assert np.all(right >= 0)
    region = np.zeros(mesh.t.shape[1], dtype=int)
    region[mesh.subdomains["zona"]] = 1
    assert np.all(region[left] != region[right])
    # and no other facet separates the layers
    interior = np.nonzero(mesh.f2t[1] >= 0)[0]
    crossing = interior[region[mesh.f2t[0, interior]] != region[mesh.f2t[1, interior]]]
    assert set(crossing) == set(facets)
    nodes = np.unique(mesh.facets[:, facets])
    assert np.allclose(np.hypot(*mesh.p[:, nodes]), RC)
    assert np.allclose(
        np.hypot(*mesh.p[:, np.unique(mesh.facets[:, mesh.boundaries["outer_surface"]])]), R
    )
    assert set(mesh.boundaries["outer_surface"]) <= set(mesh.boundary_facets())


def test_axisymmetric_volume_order2_much_closer():
    """2 pi r integrated over the half-section equals 4/3 pi R^3; curved P2 is far closer."""
    exact = 4.0 / 3.0 * np.pi * R**3
    errors = {}
    for order in (1, 2):
        mesh = layered_oocyte_mesh(LayeredOocyte(order=order, size_um=H))
        errors[order] = abs(_revolved_volume.assemble(_cells(mesh)) / exact - 1.0)
        area = _area.assemble(_cells(mesh))
        assert area == pytest.approx(np.pi * R**2 / 2, rel=_polygon_tol(H, R))
    assert errors[1] < 2.0 * _polygon_tol(H, R)
    assert errors[2] < 1e-5
    assert errors[2] < errors[1] / 100.0


def test_axis_nodes_on_axis_and_offset_centre():
    z0 = 12.5
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=H, centre_offset_um=z0))
    nodes = np.unique(mesh.facets[:, mesh.boundaries["axis"]])
    assert np.allclose(mesh.p[0, nodes], 0.0)
    assert mesh.p[1, nodes].min() == pytest.approx(z0 - R)
    assert mesh.p[1, nodes].max() == pytest.approx(z0 + R)
    assert np.all(mesh.p[0] >= -1e-12)
    length = _area.assemble(_facets(mesh, "axis"))
    assert length == pytest.approx(2 * R, rel=1e-12)


def _edge_lengths(mesh, facets):
    a, b = mesh.facets[:, facets]
    return np.hypot(*(mesh.p[:, a] - mesh.p[:, b]))


@pytest.mark.parametrize("form", ["axisymmetric", "plane_strain"])
def test_refined_window_of_outer_surface(form):
    fine = 2.0
    geom = LayeredOocyte(form=form, size_um=H, refine_polar_deg=(0.0, 30.0), refine_size_um=fine)
    mesh = layered_oocyte_mesh(geom)
    facets = mesh.boundaries["outer_surface"]
    mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
    polar = np.degrees(np.arctan2(np.abs(mid[0]), mid[1]))
    length = _edge_lengths(mesh, facets)
    inside, outside = length[polar < 28.0], length[polar > 90.0]
    assert inside.max() < 1.3 * fine
    assert outside.mean() > 0.7 * H
    # a mirrored window in plane strain: both sides refined alike
    if form == "plane_strain":
        left = length[(polar < 28.0) & (mid[0] < 0)]
        right = length[(polar < 28.0) & (mid[0] > 0)]
        assert left.size and right.size
        assert left.mean() == pytest.approx(right.mean(), rel=0.2)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"size_um": -1.0}, "size_um"),
        ({"cytoplasm_radius_um": 0.0}, "cytoplasm_radius_um"),
        ({"zona_thickness_um": float("nan")}, "zona_thickness_um"),
        ({"form": "3d"}, "form"),
        ({"order": 3}, "order"),
        ({"size_um": 50.0}, "size_um"),
        ({"refine_polar_deg": (30.0, 10.0), "refine_size_um": 1.0}, "refine_polar_deg"),
        ({"refine_polar_deg": (0.0, 30.0)}, "refine_polar_deg/refine_size_um"),
        ({"refine_polar_deg": (0.0, 30.0), "refine_size_um": 20.0}, "refine_size_um"),
    ],
)
def test_layered_rejects_bad_parameters(kwargs, field):
    with pytest.raises(InputError) as err:
        LayeredOocyte(**kwargs)
    assert err.value.field == field
    assert "LayeredOocyte" in str(err.value)


@pytest.mark.parametrize("order", [1, 2])
def test_spherical_shell_and_annulus(order):
    a, b, h = 10.0, 20.0, 2.0
    shell = spherical_shell_mesh(a, b, h, order)
    assert set(shell.boundaries) == {"inner", "outer", "axis", "symmetry"}
    ring = annulus_quarter_mesh(a, b, h, order)
    assert set(ring.boundaries) == {"inner", "outer", "left", "bottom"}
    tol = _polygon_tol(h, a) if order == 1 else 1e-5
    assert _area.assemble(_cells(shell)) == pytest.approx(np.pi * (b**2 - a**2) / 4, rel=tol)
    exact_volume = 2.0 / 3.0 * np.pi * (b**3 - a**3)  # half of the spherical shell (z >= 0)
    assert _revolved_volume.assemble(_cells(shell)) == pytest.approx(exact_volume, rel=tol)
    assert _area.assemble(_facets(shell, "inner")) == pytest.approx(np.pi * a / 2, rel=tol)
    nodes = np.unique(shell.facets[:, shell.boundaries["symmetry"]])
    assert np.allclose(shell.p[1, nodes], 0.0)
    nodes = np.unique(ring.facets[:, ring.boundaries["left"]])
    assert np.allclose(ring.p[0, nodes], 0.0)


def test_block_refined_near_corner():
    w, h, fine = 100.0, 80.0, 0.5
    mesh = block_mesh(w, h, H, refine_point=(0.0, h), refine_size_um=fine)
    assert set(mesh.boundaries) == {"left", "right", "bottom", "top"}
    assert _area.assemble(_cells(mesh)) == pytest.approx(w * h, rel=1e-12)
    top = mesh.boundaries["top"]
    x_mid = mesh.p[0, mesh.facets[:, top]].mean(axis=0)
    length = _edge_lengths(mesh, top)
    assert length[x_mid < 4.0].max() < 1.3 * fine
    assert length[x_mid > 60.0].mean() > 0.7 * H
    nodes = np.unique(mesh.facets[:, mesh.boundaries["right"]])
    assert np.allclose(mesh.p[0, nodes], w)
    with pytest.raises(InputError, match="refine_point"):
        block_mesh(w, h, H, refine_point=(-1.0, 0.0), refine_size_um=fine)


def test_cache_hit_does_not_call_gmsh(monkeypatch, mesh_cache):
    geom = LayeredOocyte(size_um=12.0, order=2)
    path = cache_path(geom)
    assert not path.exists()
    first = layered_oocyte_mesh(geom)
    assert path.exists() and path.parent == mesh_cache
    assert not list(mesh_cache.glob(".tmp-*"))

    def no_gmsh(*args, **kwargs):
        raise AssertionError("gmsh called on a cache hit")

    monkeypatch.setattr(gmsh, "initialize", no_gmsh)
    second = layered_oocyte_mesh(LayeredOocyte(size_um=12.0, order=2))
    assert np.array_equal(first.doflocs, second.doflocs)
    assert np.array_equal(first.t, second.t)
    for name in first.boundaries:
        assert np.array_equal(first.boundaries[name], second.boundaries[name])
    # other parameters: another key, so gmsh is needed
    assert cache_path(LayeredOocyte(size_um=12.0, order=1)) != path
    with pytest.raises(AssertionError, match="cache hit"):
        layered_oocyte_mesh(LayeredOocyte(size_um=12.0, order=1))
    assert not list(mesh_cache.glob(".tmp-*"))


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_inputs_off_by_round_off_draw_the_same_mesh(tmp_path, monkeypatch, sign: float):
    """gmsh is not continuous in its inputs: a radius or size x (1 + 1e-9) gave another mesh
    (other vertex count, or nodes renumbered and moved). The mesh is drawn for the inputs
    rounded to 7 significant digits, so each built afresh (own cache) is the same mesh; a
    change of 1e-5 still draws another one."""
    geom = dict(
        cytoplasm_radius_um=41.7985,
        zona_thickness_um=16.014,
        form="plane_strain",
        size_um=8.0,
        refine_polar_deg=(60.0, 120.0),
        refine_size_um=3.3,
        refine_depth_um=20.0,
        order=2,
    )

    def mesh(factor: float, folder: str) -> skfem.Mesh:
        monkeypatch.setenv("OOCYTE_FE_CACHE", str(tmp_path / folder))
        scaled = {k: v * factor if isinstance(v, float) else v for k, v in geom.items()}
        return layered_oocyte_mesh(LayeredOocyte(**scaled))

    base = mesh(1.0, "a")
    off = mesh(1.0 + sign * 1e-9, "b")
    assert np.array_equal(base.t, off.t) and np.array_equal(base.p, off.p)
    other = mesh(1.0 + sign * 1e-5, "c")
    assert other.p.shape != base.p.shape or np.abs(other.p - base.p).max() > 1e-3
