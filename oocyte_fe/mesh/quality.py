"""Mesh checks before any solve: inverted or degenerate triangles, missing named groups.

Degenerate: an element whose shape quality ``q = 4 sqrt(3) A / (l1^2 + l2^2 + l3^2)``
(1 for the equilateral triangle, 0 for collinear corners; ``A`` area, ``li`` edge lengths,
all in um) is below ``rtol``; the test is free of the length scale.

Inverted: an element folded over a neighbour. Across every interior edge the two opposite
corners must lie on opposite sides of the edge line; if they lie on the same side, one of the
two elements has a negative signed area relative to the other. This test does not depend on
the node-ordering convention of the mesh (scikit-fem may reorder element corners). For
quadratic (6-node) triangles the Jacobian determinant of the isoparametric map must also
keep one sign within each element, evaluated at its six nodes; a mid-edge node pulled
across the element flips it there.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np
import skfem

from oocyte_fe.errors import InputError

DEGENERATE_RTOL = 1e-3
"""Default lower bound of the shape quality ``q`` (0 collinear, 1 equilateral)."""


def _signed_areas(p: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Signed area of each triangle (um^2); positive for counter-clockwise corners."""
    a, b, c = (p[:, t[i]] for i in range(3))
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def shape_quality(mesh: skfem.Mesh) -> np.ndarray:
    """Shape quality ``q = 4 sqrt(3) |A| / sum(l_i^2)`` of each triangle, in [0, 1]."""
    p, t = mesh.p, mesh.t[:3]
    edges2 = sum(np.sum((p[:, t[i]] - p[:, t[(i + 1) % 3]]) ** 2, axis=0) for i in range(3))
    return 4.0 * np.sqrt(3.0) * np.abs(_signed_areas(p, t)) / edges2


def _folded_elements(mesh: skfem.Mesh) -> np.ndarray:
    """Indices of elements on an interior edge whose opposite corners lie on one side."""
    p, t = mesh.p, mesh.t[:3]
    interior = np.nonzero(mesh.f2t[1] >= 0)[0]
    e0, e1 = mesh.facets[:, interior]
    t1, t2 = mesh.f2t[:, interior]

    def opposite(elems: np.ndarray) -> np.ndarray:
        return t[:, elems].sum(axis=0) - e0 - e1

    edge = p[:, e1] - p[:, e0]

    def side(vertex: np.ndarray) -> np.ndarray:
        rel = p[:, vertex] - p[:, e0]
        return edge[0] * rel[1] - edge[1] * rel[0]

    same_side = side(opposite(t1)) * side(opposite(t2)) > 0.0
    return np.unique(np.concatenate([t1[same_side], t2[same_side]]))


def _curved_inverted(mesh: skfem.Mesh) -> np.ndarray:
    """Quadratic elements whose Jacobian determinant changes sign at their six nodes."""
    nodes = skfem.ElementTriP2.doflocs.T  # reference-element node coordinates, shape (2, 6)
    det = mesh._mapping().detDF(nodes)  # shape (n_elements, 6)
    return np.nonzero(np.min(det, axis=1) * np.max(det, axis=1) <= 0.0)[0]


def check_mesh(mesh: skfem.Mesh, source: str | Path, rtol: float = DEGENERATE_RTOL) -> None:
    """Raise :class:`InputError` naming ``source`` if ``mesh`` has degenerate or inverted
    triangles (see the module docstring); the message gives the count, the first element
    index and its centroid in um."""
    p, t = mesh.p, mesh.t[:3]

    def fail(kind: str, bad: np.ndarray, expected: str) -> None:
        centroid = p[:, t[:, bad[0]]].mean(axis=1)
        raise InputError(
            source,
            "mesh",
            expected,
            f"{len(bad)} {kind} element(s), first #{bad[0]} at "
            f"({centroid[0]:.4g}, {centroid[1]:.4g}) um",
        )

    bad = np.nonzero(shape_quality(mesh) < rtol)[0]
    if len(bad):
        fail("degenerate", bad, f"triangles of shape quality >= {rtol:g}")
    bad = _folded_elements(mesh)
    if len(bad):
        fail("inverted", bad, "no inverted (folded) triangles")
    if isinstance(mesh, skfem.MeshTri2):
        bad = _curved_inverted(mesh)
        if len(bad):
            fail("inverted curved", bad, "quadratic triangles with a Jacobian of one sign")


def require_groups(
    mesh: skfem.Mesh,
    subdomains: Iterable[str] = (),
    boundaries: Iterable[str] = (),
    source: str | Path = "mesh",
) -> None:
    """Raise :class:`InputError` naming the first missing physical group and the groups
    present, if ``mesh`` lacks one of the named subdomains or boundaries (or it is empty)."""
    for kind, wanted, present in (
        ("subdomain", subdomains, mesh.subdomains or {}),
        ("boundary", boundaries, mesh.boundaries or {}),
    ):
        for name in wanted:
            if name not in present or len(present[name]) == 0:
                listed = ", ".join(sorted(present)) or "none"
                raise InputError(
                    source,
                    f"physical group '{name}'",
                    f"a non-empty {kind} named '{name}' ({kind} groups present: {listed})",
                )
