"""Read a gmsh ``.msh`` file (through meshio) into a scikit-fem mesh with its named groups.

Triangles (3-node -> ``MeshTri1``, 6-node -> ``MeshTri2`` with curved edges) become the
elements; every named physical group of surfaces becomes a subdomain (element indices) and
every named physical group of curves a boundary (facet indices; interior facets allowed, as
for the interface between two layers). Coordinates are taken as um, x the radial coordinate
r and y the axis z for axisymmetric models. Unnamed physical groups are ignored. MSH 4.1
(also groups sharing entities) and MSH 2.2 files are read.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import meshio
import numpy as np
import skfem

from oocyte_fe.errors import InputError
from oocyte_fe.mesh.quality import check_mesh, require_groups

_TRIANGLES = {"triangle": skfem.MeshTri1, "triangle6": skfem.MeshTri2}
_EDGES = ("line", "line3")


def _named_sets(m: meshio.Mesh) -> dict[str, dict[str, np.ndarray]]:
    """``{group name: {meshio cell type: indices into m.cells_dict[type]}}``."""
    named = {
        name: {ctype: np.asarray(idx, dtype=np.int64) for ctype, idx in sets.items()}
        for name, sets in m.cell_sets_dict.items()
        if not name.startswith("gmsh:")
    }
    if named or "gmsh:physical" not in m.cell_data_dict:
        return named
    # MSH 2.2: one physical tag per element, names in field_data {name: [tag, dim]}
    tags = m.cell_data_dict["gmsh:physical"]
    for name, (tag, _dim) in m.field_data.items():
        named[name] = {ctype: np.nonzero(tag_of == tag)[0] for ctype, tag_of in tags.items()}
    return named


def skfem_mesh_from_meshio(m: meshio.Mesh, source: str | Path) -> skfem.Mesh:
    """Build the scikit-fem mesh with named subdomains and boundaries (module docstring)."""
    cells = m.cells_dict
    kinds = [ctype for ctype in _TRIANGLES if ctype in cells]
    if len(kinds) != 1:
        raise InputError(
            source, "cells", "one kind of triangle (3- or 6-node)", sorted(cells) or "none"
        )
    ctype = kinds[0]
    conn = cells[ctype]
    # number the corner nodes first (scikit-fem keeps vertex dofs first), then mid-edge nodes
    corners = np.unique(conn[:, :3])
    used = np.concatenate([corners, np.setdiff1d(conn, corners)])
    new_index = np.full(len(m.points), -1)
    new_index[used] = np.arange(len(used))
    t = np.ascontiguousarray(new_index[conn].T)
    points = np.ascontiguousarray(m.points[used, :2].T)
    if ctype == "triangle":
        mesh = skfem.MeshTri1(points, t, sort_t=False)
    else:
        mesh = skfem.MeshTri2(points, t)

    facet_of = {tuple(pair): i for i, pair in enumerate(np.sort(mesh.facets, axis=0).T)}
    subdomains: dict[str, np.ndarray] = {}
    boundaries: dict[str, np.ndarray] = {}
    for name, sets in _named_sets(m).items():
        if ctype in sets and len(sets[ctype]):
            subdomains[name] = np.sort(sets[ctype]).astype(np.int32)
        edges = [cells[e][sets[e], :2] for e in _EDGES if e in sets and len(sets[e])]
        if not edges:
            continue
        ends = np.sort(new_index[np.concatenate(edges)], axis=1)
        missing = [tuple(e) for e in ends if tuple(e) not in facet_of]
        if missing:
            raise InputError(
                source,
                f"physical group '{name}'",
                "curve elements that are edges of the triangles",
                f"{len(missing)} edge(s) not in the mesh",
            )
        boundaries[name] = np.unique([facet_of[tuple(e)] for e in ends]).astype(np.int32)
    return type(mesh)(mesh.doflocs, mesh.t, boundaries or None, subdomains or None, sort_t=False)


def read_mesh(
    path: str | Path, subdomains: Iterable[str] = (), boundaries: Iterable[str] = ()
) -> skfem.Mesh:
    """Read a user-supplied gmsh ``.msh`` file (um), keep its physical names and check it.

    Raises :class:`InputError` naming the file if it cannot be read, holds no single kind of
    triangle, has degenerate or inverted elements (:func:`check_mesh`) or lacks one of the
    named ``subdomains``/``boundaries`` (:func:`require_groups`).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "", "an existing gmsh .msh file")
    try:  # the format reader itself: meshio.read would sys.exit on a bad file
        m = meshio.gmsh.read(str(path))
    except (meshio.ReadError, ValueError, KeyError, IndexError, UnicodeDecodeError) as err:
        detail = str(err) or type(err).__name__
        raise InputError(path, "", f"a readable gmsh .msh file ({detail})") from err
    mesh = skfem_mesh_from_meshio(m, path)
    check_mesh(mesh, path)
    require_groups(mesh, subdomains, boundaries, path)
    return mesh
