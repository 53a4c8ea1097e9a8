"""Nodal arrays on a mesh: shape checks and corner-to-all-nodes interpolation."""

from __future__ import annotations

import numpy as np
import skfem


def nodal_values(mesh: skfem.Mesh, values: np.ndarray, components: int, name: str) -> np.ndarray:
    """``values`` at every node of ``mesh`` (``mesh.doflocs``), shape ``(n,)`` or
    ``(n, components)``.

    Accepts ``(n,)``/``(n, c)``/``(c, n)`` arrays given at all ``n`` nodes, or at the corner
    nodes only of a quadratic mesh; mid-edge values are then the mean of the two corners
    (linear interpolation along the edge). Raises ``ValueError`` naming ``name`` otherwise.
    """
    n_all, n_corner = mesh.doflocs.shape[1], mesh.nvertices
    arr = np.asarray(values, dtype=float)
    if components > 1 and arr.ndim == 2 and arr.shape[0] == components != arr.shape[1]:
        arr = arr.T
    trailing = () if components == 1 else (components,)
    if arr.ndim == 0 or arr.shape[0] not in (n_all, n_corner) or arr.shape[1:] != trailing:
        expected = "(n,)" if components == 1 else f"(n, {components}) or ({components}, n)"
        raise ValueError(
            f"{name}: expected shape {expected} with n = {n_all} nodes or {n_corner} corner"
            f" nodes, got {arr.shape}"
        )
    if arr.shape[0] == n_all:
        return arr
    full = np.empty((n_all, *trailing))
    full[:n_corner] = arr
    full[mesh.dofs.facet_dofs[0]] = 0.5 * (arr[mesh.facets[0]] + arr[mesh.facets[1]])
    return full
