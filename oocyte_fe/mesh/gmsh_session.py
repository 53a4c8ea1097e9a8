"""One quiet gmsh session that builds a 2D model, meshes it and writes a ``.msh`` file.

gmsh keeps one global model per process and is not thread-safe, so every use goes through
:func:`write_gmsh_mesh`: it holds a process-wide lock, initialises gmsh without reading the
user's configuration files (the result must depend on the parameters only, for the cache),
runs the caller's geometry builder, meshes in 2D, raises the order if asked, writes MSH 4.1
and always finalises, also on error.

Size control is one background field: the global size ``size_um`` and, optionally, a finer
size near a set of points or curves, growing linearly with the distance (``GRADING``).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from pathlib import Path

import gmsh

GRADING = 0.3
"""Largest growth of the element size per unit distance (um/um) away from a refined zone."""

_LOCK = threading.Lock()


def gmsh_version() -> str:
    """The version of the gmsh library in use (part of every cache key)."""
    return str(gmsh.__version__)


def write_gmsh_mesh(build: Callable[[], float], order: int, path: Path) -> None:
    """Run ``build`` in a fresh gmsh model, mesh it and write ``path`` (MSH 4.1, ASCII).

    ``build`` adds the geometry (built-in kernel), synchronises, adds the physical groups
    and returns the global element size in um, which is set as the largest size. Only
    elements of physical groups are written. ``order`` 2 gives 6-node triangles whose
    mid-edge nodes lie on the curved geometry.
    """
    with _LOCK:
        if gmsh.isInitialized():
            raise RuntimeError("gmsh is already initialised in this process by other code")
        gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add("oocyte_fe")
            size_um = build()
            gmsh.option.setNumber("Mesh.MeshSizeMax", size_um)
            gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
            gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
            gmsh.option.setNumber("Mesh.SaveAll", 0)
            gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
            gmsh.option.setNumber("Mesh.Binary", 0)
            gmsh.model.mesh.generate(2)
            if order == 2:
                gmsh.model.mesh.setOrder(2)
            gmsh.write(str(path))
        finally:
            gmsh.finalize()


def distance_to_point(x_um: float, y_um: float) -> int:
    """A gmsh field: distance (um) to the point ``(x_um, y_um)``."""
    field = gmsh.model.mesh.field.add("MathEval")
    gmsh.model.mesh.field.setString(field, "F", f"Sqrt((x-({x_um!r}))^2+(y-({y_um!r}))^2)")
    return field


def distance_to_curves(curves: Sequence[int]) -> int:
    """A gmsh field: distance (um) to the given curves (sampled at 400 points each)."""
    field = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(field, "CurvesList", list(curves))
    gmsh.model.mesh.field.setNumber(field, "Sampling", 400)
    return field


def refine_near(distance: int, size_um: float, refine_size_um: float, plateau_um: float) -> None:
    """Background size field: ``refine_size_um`` where the ``distance`` field is below
    ``plateau_um``, rising linearly to ``size_um`` over ``(size_um - refine_size_um) / GRADING``.

    Call inside a ``build`` function after ``synchronize``.
    """
    field = gmsh.model.mesh.field
    thr = field.add("Threshold")
    field.setNumber(thr, "InField", distance)
    field.setNumber(thr, "SizeMin", refine_size_um)
    field.setNumber(thr, "SizeMax", size_um)
    field.setNumber(thr, "DistMin", plateau_um)
    field.setNumber(thr, "DistMax", plateau_um + (size_um - refine_size_um) / GRADING)
    field.setAsBackgroundMesh(thr)


def add_physical(dim: int, tags: Sequence[int], name: str) -> None:
    """A named physical group of the given entities (dim 1: curves, dim 2: surfaces)."""
    group = gmsh.model.addPhysicalGroup(dim, list(tags))
    gmsh.model.setPhysicalName(dim, group, name)
