"""Mesh checks (inverted, degenerate, curved-inverted elements; missing groups) and reading a
user-supplied gmsh file with its physical names (MSH 4.1 and 2.2)."""

from __future__ import annotations

from dataclasses import replace

import gmsh
import meshio
import numpy as np
import pytest
import skfem

from oocyte_fe.errors import InputError
from oocyte_fe.mesh import block_mesh, check_mesh, read_mesh, require_groups
from oocyte_fe.mesh.quality import DEGENERATE_RTOL, shape_quality


@pytest.fixture(autouse=True, scope="module")
def mesh_cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("OOCYTE_FE_CACHE", str(tmp_path_factory.mktemp("mesh_cache")))
        yield


def _interior_vertex_and_element(mesh: skfem.Mesh) -> tuple[int, int, np.ndarray]:
    """An interior vertex, one element around it, and the element's opposite corners."""
    boundary = set(np.unique(mesh.facets[:, mesh.boundary_facets()]))
    vertex = next(v for v in range(mesh.t.max() + 1) if v not in boundary)
    element = int(np.nonzero((mesh.t[:3] == vertex).any(axis=0))[0][0])
    others = mesh.t[:3, element][mesh.t[:3, element] != vertex]
    return vertex, element, others


def _moved(mesh: skfem.Mesh, vertex: int, xy: np.ndarray) -> skfem.Mesh:
    doflocs = mesh.doflocs.copy()
    doflocs[:, vertex] = xy
    return replace(mesh, doflocs=doflocs)


def test_valid_meshes_pass():
    for order in (1, 2):
        mesh = block_mesh(40.0, 30.0, 5.0, order=order)
        assert check_mesh(mesh, "block") is None  # passes: no InputError
        # what "valid" means, checked on the numbers: every triangle above the degenerate
        # bound, and the unsigned corner areas tile the 40 x 30 um rectangle exactly (an
        # inverted or overlapping element would add area): 1200 um^2 to round-off (1e-12)
        assert shape_quality(mesh).min() > DEGENERATE_RTOL
        a, b, c = (mesh.p[:, mesh.t[i]] for i in range(3))
        area = 0.5 * np.abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        assert area.sum() == pytest.approx(40.0 * 30.0, rel=1e-12)


def test_inverted_element_is_caught():
    mesh = block_mesh(40.0, 30.0, 5.0)
    vertex, _, (a, b) = _interior_vertex_and_element(mesh)
    pa, pb, pv = mesh.p[:, a], mesh.p[:, b], mesh.p[:, vertex]
    # reflect the vertex across the opposite edge: that element flips over its neighbour
    edge = (pb - pa) / np.linalg.norm(pb - pa)
    foot = pa + edge * np.dot(pv - pa, edge)
    bad = _moved(mesh, vertex, 2.0 * foot - pv)
    with pytest.raises(InputError, match="inverted") as err:
        check_mesh(bad, "user.msh")
    assert str(err.value).startswith("user.msh: mesh: expected no inverted")


def test_degenerate_element_is_caught():
    mesh = block_mesh(40.0, 30.0, 5.0)
    vertex, element, (a, b) = _interior_vertex_and_element(mesh)
    bad = _moved(mesh, vertex, 0.5 * (mesh.p[:, a] + mesh.p[:, b]))
    assert shape_quality(bad)[element] < 1e-12
    with pytest.raises(InputError, match="degenerate") as err:
        check_mesh(bad, "user.msh")
    assert "1 degenerate element(s)" in str(err.value)


def test_curved_inverted_element_is_caught():
    mesh = block_mesh(40.0, 30.0, 5.0, order=2)
    # pull one interior mid-edge node across the whole element
    element = 0
    corners = mesh.p[:, mesh.t[:, element]]
    mid_dof = mesh.dofs.element_dofs[3, element]
    doflocs = mesh.doflocs.copy()
    centroid = corners.mean(axis=1)
    doflocs[:, mid_dof] = centroid - 3.0 * (doflocs[:, mid_dof] - centroid)
    with pytest.raises(InputError, match="1 inverted curved element"):
        check_mesh(replace(mesh, doflocs=doflocs), "curved.msh")


def test_require_groups_names_missing_and_present():
    mesh = block_mesh(40.0, 30.0, 5.0)
    require_groups(mesh, subdomains=["body"], boundaries=["top", "left"], source="b.msh")
    with pytest.raises(InputError) as err:
        require_groups(mesh, subdomains=["body"], boundaries=["outer_surface"], source="b.msh")
    msg = str(err.value)
    assert "'outer_surface'" in msg and "bottom, left, right, top" in msg
    assert msg.startswith("b.msh:")
    with pytest.raises(InputError, match="subdomain named 'zona'"):
        require_groups(mesh, subdomains=["zona"], source="b.msh")


def _write_user_msh(path, order: int) -> None:
    """A user's own model: unit-free square with a disc inclusion, names of their choosing."""
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        occ = gmsh.model.occ
        square = occ.addRectangle(-20, -20, 0, 40, 40)
        disc = occ.addDisk(0, 0, 0, 8, 8)
        out, _ = occ.fragment([(2, square)], [(2, disc)])
        occ.synchronize()
        surfaces = [tag for dim, tag in out if dim == 2]
        areas = {s: occ.getMass(2, s) for s in surfaces}
        inclusion = min(areas, key=areas.get)
        matrix = max(areas, key=areas.get)
        for dim, tags, name in (
            (2, [inclusion], "inclusion"),
            (2, [matrix], "matrix"),
            (1, [b for _, b in gmsh.model.getBoundary([(2, inclusion)])], "ring"),
        ):
            group = gmsh.model.addPhysicalGroup(dim, tags)
            gmsh.model.setPhysicalName(dim, group, name)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 3.0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


@pytest.mark.parametrize("order", [1, 2])
def test_read_user_msh_keeps_names(tmp_path, order):
    path = tmp_path / "user.msh"
    _write_user_msh(path, order)
    mesh = read_mesh(path, subdomains=["inclusion", "matrix"], boundaries=["ring"])
    assert isinstance(mesh, skfem.MeshTri2 if order == 2 else skfem.MeshTri1)
    ring = mesh.boundaries["ring"]
    assert np.all(mesh.f2t[1, ring] >= 0)  # interior facets kept
    assert np.allclose(np.hypot(*mesh.p[:, np.unique(mesh.facets[:, ring])]), 8.0)
    n = mesh.t.shape[1]
    assert len(mesh.subdomains["inclusion"]) + len(mesh.subdomains["matrix"]) == n

    # the same mesh as MSH 2.2 (one physical tag per element) reads alike
    legacy = tmp_path / "user22.msh"
    meshio.write(legacy, meshio.read(path), file_format="gmsh22", binary=False)
    old = read_mesh(legacy, subdomains=["inclusion", "matrix"], boundaries=["ring"])
    assert np.array_equal(np.sort(old.boundaries["ring"]).size, ring.size)
    assert len(old.subdomains["inclusion"]) == len(mesh.subdomains["inclusion"])

    with pytest.raises(InputError, match="'zona'.*inclusion, matrix"):
        read_mesh(path, subdomains=["zona"])


def test_read_mesh_bad_files(tmp_path):
    garbage = tmp_path / "garbage.msh"
    garbage.write_text("not a mesh\n")
    with pytest.raises(InputError, match="garbage.msh"):
        read_mesh(garbage)
    with pytest.raises(InputError, match="missing.msh"):
        read_mesh(tmp_path / "missing.msh")
