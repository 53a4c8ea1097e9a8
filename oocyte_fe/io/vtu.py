"""Field output for ParaView: one VTU file per step and a ``.pvd`` collection with the times.

Points are the mesh nodes in the reference configuration (um; x = r, y = z when
axisymmetric, z = 0); quadratic meshes are written as 6-node VTK triangles. Point data,
each array named with its unit:

* ``displacement_um``, 3 components with the third zero, so ParaView's *Warp By Vector*
  shows the deformed section;
* ``pressure_kPa`` (``-tr(sigma)/3``), ``von_Mises_kPa``, ``contact_pressure_kPa``, when
  given; values given at the corner nodes only of a quadratic mesh are interpolated linearly
  to the mid-edge nodes;
* any extra nodal scalars, under the names given (which should end in their unit).

Cell data: ``region_id``, ``k + 1`` for the ``k``-th named subdomain of the mesh (in the
order of ``mesh.subdomains``; 0 for elements in none), listed in a comment of the ``.pvd``.

Rigid obstacles (pipette wall, plates, indenter) given to :meth:`FieldSeriesWriter.write`
as polylines (``(m, 2)`` points in um, current position) are written as their own series,
``<name>_<obstacle>_0000.vtu`` ... and ``<name>_<obstacle>.pvd`` (line cells, z = 0), with
the same times. Beside the series, ``view_<name>.py`` is a pyvista script that opens it as
the report's section figures show it (:mod:`oocyte_fe.io.viewer_script`).

The series is written whole or not at all: files go to a hidden temporary folder beside the
target, which is renamed into place when the writer closes without error (an older folder of
the same name is then replaced); on an exception the temporary folder is deleted.
"""

from __future__ import annotations

import os
import shutil
import uuid
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path
from types import TracebackType

import meshio
import numpy as np
import skfem

from oocyte_fe.io.viewer_script import write_viewer_script
from oocyte_fe.mesh.nodal import nodal_values

_VTK_CELL = {skfem.MeshTri1: "triangle", skfem.MeshTri2: "triangle6"}


def region_ids(mesh: skfem.Mesh) -> np.ndarray:
    """Per element: 1 + index of its named subdomain in ``mesh.subdomains`` (0 if none)."""
    ids = np.zeros(mesh.t.shape[1], dtype=np.int32)
    for k, elements in enumerate((mesh.subdomains or {}).values()):
        ids[elements] = k + 1
    return ids


class FieldSeriesWriter:
    """Write a time series of fields on ``mesh`` into the folder ``folder``.

    Use as a context manager; call :meth:`write` once per step::

        with FieldSeriesWriter(out / "fields", mesh) as series:
            for t, u, p in steps:
                series.write(t, displacement=u, pressure=p)

    ``folder`` then holds ``fields_0000.vtu`` ... and ``fields.pvd`` (open the ``.pvd``),
    one series per named obstacle, and ``view_fields.py``; ``axisymmetric`` makes that
    script mirror the half-section about r = 0, ``view_window`` (um) show only that part.
    """

    def __init__(
        self,
        folder: str | Path,
        mesh: skfem.Mesh,
        name: str = "fields",
        *,
        axisymmetric: bool = False,
        view_window: tuple[float, float, float, float] | None = None,
    ) -> None:
        if type(mesh) not in _VTK_CELL:
            raise TypeError(f"FieldSeriesWriter: a MeshTri1 or MeshTri2, got {type(mesh)}")
        self.folder = Path(folder)
        self.mesh = mesh
        self.name = name
        self._points = np.column_stack([mesh.doflocs.T, np.zeros(mesh.doflocs.shape[1])])
        self._cells = [(_VTK_CELL[type(mesh)], np.ascontiguousarray(mesh.dofs.element_dofs.T))]
        self._regions = region_ids(mesh)
        self.axisymmetric = axisymmetric
        self.view_window = view_window
        self._steps: list[tuple[float, str]] = []
        self._obstacle_steps: dict[str, list[tuple[float, str]]] = {}
        self._tmp: Path | None = None

    def __enter__(self) -> FieldSeriesWriter:
        self.folder.parent.mkdir(parents=True, exist_ok=True)
        self._tmp = self.folder.parent / f".{self.folder.name}.partial-{uuid.uuid4().hex[:8]}"
        self._tmp.mkdir()
        return self

    def write(
        self,
        time_s: float,
        displacement: np.ndarray,
        pressure: np.ndarray | None = None,
        von_mises: np.ndarray | None = None,
        contact_pressure: np.ndarray | None = None,
        extra_point_data: Mapping[str, np.ndarray] | None = None,
        obstacles: Mapping[str, np.ndarray] | None = None,
    ) -> Path:
        """Write one step at time ``time_s`` (s): nodal displacement (um, 2 components),
        pressure, von Mises stress and contact pressure (kPa), any extra nodal scalars (named
        with their unit), and each obstacle's polyline (``(m, 2)``, um) into its own series.
        Returns the path the VTU will have once the series is closed."""
        if self._tmp is None:
            raise RuntimeError("FieldSeriesWriter.write outside its 'with' block")
        if self._steps and time_s < self._steps[-1][0]:
            raise ValueError(f"FieldSeriesWriter: time {time_s} s before the previous step")
        u = nodal_values(self.mesh, displacement, 2, "displacement")
        data = {"displacement_um": np.column_stack([u, np.zeros(len(u))])}
        named = {
            "pressure_kPa": pressure,
            "von_Mises_kPa": von_mises,
            "contact_pressure_kPa": contact_pressure,
        }
        named.update(extra_point_data or {})
        for key, values in named.items():
            if values is not None:
                data[key] = nodal_values(self.mesh, values, 1, key)
        file = f"{self.name}_{len(self._steps):04d}.vtu"
        out = meshio.Mesh(
            self._points, self._cells, point_data=data, cell_data={"region_id": [self._regions]}
        )
        meshio.write(self._tmp / file, out, file_format="vtu")
        self._steps.append((float(time_s), file))
        for label, points in (obstacles or {}).items():
            self._write_obstacle(float(time_s), label, points)
        return self.folder / file

    def _write_obstacle(self, time_s: float, label: str, points: np.ndarray) -> None:
        """One step of the obstacle ``label``: its polyline as VTK line cells (um, z = 0)."""
        assert self._tmp is not None
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise ValueError(f"FieldSeriesWriter: obstacle {label!r}: expected (m >= 2, 2) um")
        steps = self._obstacle_steps.setdefault(label, [])
        file = f"{self.name}_{label}_{len(steps):04d}.vtu"
        segments = np.column_stack([np.arange(len(pts) - 1), np.arange(1, len(pts))])
        line = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]), [("line", segments)])
        meshio.write(self._tmp / file, line, file_format="vtu")
        steps.append((time_s, file))

    def _write_pvd(
        self, folder: Path, name: str, steps: list[tuple[float, str]], comment: str
    ) -> None:
        root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
        root.append(ET.Comment(comment))
        collection = ET.SubElement(root, "Collection")
        for time_s, file in steps:
            ET.SubElement(
                collection, "DataSet", timestep=repr(time_s), group="", part="0", file=file
            )
        ET.indent(root)
        ET.ElementTree(root).write(folder / f"{name}.pvd", encoding="utf-8", xml_declaration=True)

    def _write_collections(self, folder: Path) -> None:
        """The ``.pvd`` of the fields and of each obstacle, and the viewer script."""
        names = ", ".join(f"{k + 1} = {n}" for k, n in enumerate(self.mesh.subdomains or {}))
        comment = f" time in s; lengths in um; region_id: {names or 'none'}, 0 = none "
        self._write_pvd(folder, self.name, self._steps, comment)
        for label, steps in self._obstacle_steps.items():
            comment = f" rigid obstacle {label}: polyline, current position, um; time in s "
            self._write_pvd(folder, f"{self.name}_{label}", steps, comment)
        obstacles = [f"{self.name}_{label}.pvd" for label in self._obstacle_steps]
        write_viewer_script(folder, self.name, obstacles, self.axisymmetric, self.view_window)

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        tmp, self._tmp = self._tmp, None
        if tmp is None:
            return
        if exc_type is not None:
            shutil.rmtree(tmp, ignore_errors=True)
            return
        try:
            self._write_collections(tmp)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        old = None
        if self.folder.exists():
            old = tmp.with_name(f".{self.folder.name}.old-{uuid.uuid4().hex[:8]}")
            os.replace(self.folder, old)
        os.replace(tmp, self.folder)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
