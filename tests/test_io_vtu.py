"""VTU/PVD field series (round trip through meshio, whole-or-nothing), history CSV and the
off-screen section PNG."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
import pyvista as pv

from oocyte_fe.io import FieldSeriesWriter, write_history_csv
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
from oocyte_fe.plotting import plot_section


@pytest.fixture(autouse=True, scope="module")
def mesh_cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("OOCYTE_FE_CACHE", str(tmp_path_factory.mktemp("mesh_cache")))
        yield


def _field(mesh, t):
    """A smooth test displacement (um) at all nodes: radial expansion growing with t."""
    x, y = mesh.doflocs
    return np.array([0.01 * t * x, 0.02 * t * y])


@pytest.mark.parametrize("order", [1, 2])
def test_series_round_trip(tmp_path, order):
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0, order=order))
    times = [0.0, 0.1, 0.35]  # uneven steps
    folder = tmp_path / "fields"
    n_corner = mesh.nvertices
    with FieldSeriesWriter(folder, mesh) as series:
        for t in times:
            series.write(
                t,
                displacement=_field(mesh, t),
                pressure=np.full(n_corner, 2.0 * t),  # corner values, linear field
                von_mises=t * mesh.doflocs[0],
                contact_pressure=np.zeros(mesh.doflocs.shape[1]),
            )
        assert not folder.exists()  # nothing in place before a successful close
    assert not list(tmp_path.glob(".fields*"))

    root = ET.parse(folder / "fields.pvd").getroot()
    datasets = root.find("Collection").findall("DataSet")
    assert [float(d.get("timestep")) for d in datasets] == times
    for t, dataset in zip(times, datasets, strict=True):
        m = meshio.read(folder / dataset.get("file"))
        cell_type = "triangle6" if order == 2 else "triangle"
        assert np.array_equal(m.cells_dict[cell_type], mesh.dofs.element_dofs.T)
        u = m.point_data["displacement"]
        assert u.shape == (mesh.doflocs.shape[1], 3)
        assert np.allclose(u[:, :2], _field(mesh, t).T) and np.all(u[:, 2] == 0)
        assert np.allclose(m.point_data["pressure"], 2.0 * t)  # mid-edge nodes interpolated
        assert np.allclose(m.point_data["von_Mises"], t * mesh.doflocs[0])
        region = m.cell_data["region_id"][0]
        assert np.all(region[mesh.subdomains["cytoplasm"]] == 1)
        assert np.all(region[mesh.subdomains["zona"]] == 2)

    # VTK's own readers (as ParaView uses them) see the series, its times and the fields
    reader = pv.get_reader(str(folder / "fields.pvd"))
    assert reader.time_values == times
    reader.set_active_time_value(times[-1])
    grid = reader.read()[0]
    assert set(grid.celltypes) == {22 if order == 2 else 5}  # VTK (quadratic) triangle
    assert np.allclose(grid.point_data["displacement"][:, :2], _field(mesh, times[-1]).T)


def test_series_left_out_on_error_and_replaces_old(tmp_path):
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0))
    folder = tmp_path / "fields"
    with pytest.raises(RuntimeError, match="diverged"):
        with FieldSeriesWriter(folder, mesh) as series:
            series.write(0.0, displacement=_field(mesh, 0.0))
            raise RuntimeError("diverged")
    assert list(tmp_path.iterdir()) == []

    with pytest.raises(ValueError, match="displacement: expected shape"):
        with FieldSeriesWriter(folder, mesh) as series:
            series.write(0.0, displacement=np.zeros((5, 2)))
    assert list(tmp_path.iterdir()) == []

    for steps in (3, 1):  # a second run replaces the first series whole
        with FieldSeriesWriter(folder, mesh) as series:
            for k in range(steps):
                series.write(float(k), displacement=_field(mesh, k))
    assert sorted(p.name for p in folder.iterdir()) == ["fields.pvd", "fields_0000.vtu"]
    assert [p.name for p in tmp_path.iterdir()] == ["fields"]


def test_history_csv_units_in_header(tmp_path):
    time_s = np.array([0.0, 0.5, 1.0])
    force = np.array([0.0, 12.5, 30.25])
    path = write_history_csv(
        tmp_path / "history.csv",
        {"time": time_s, "force_pipette": force, "volume_ratio": force / 30.25},
        {"time": "s", "force_pipette": "nN", "volume_ratio": ""},
    )
    lines = path.read_text().splitlines()
    assert lines[0] == "time_s,force_pipette_nN,volume_ratio"
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert np.array_equal(data[:, 1], force)
    with pytest.raises(ValueError, match="no unit"):
        write_history_csv(tmp_path / "bad.csv", {"time": time_s}, {})
    with pytest.raises(ValueError, match="one length"):
        write_history_csv(tmp_path / "bad.csv", {"a": time_s, "b": force[:2]}, {"a": "s", "b": ""})
    assert not (tmp_path / "bad.csv").exists()


def _colourful_fraction(path) -> tuple[float, float]:
    """Pixel standard deviation and fraction of strongly coloured (not white/grey) pixels."""
    from PIL import Image

    image = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    assert image.shape == (300, 400, 3)
    return image.std(), (np.ptp(image, axis=2) > 60).mean()


@pytest.mark.parametrize("order", [1, 2])
def test_section_png_is_not_blank(tmp_path, order):
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0, order=order))
    wall = np.array([[30.0, 150.0], [30.0, 85.0], [40.0, 80.0]])
    path = plot_section(
        tmp_path / "section.png",
        mesh,
        _field(mesh, 1.0),
        mirror=True,
        obstacles=[wall],
        window_size=(400, 300),
    )
    spread, colourful = _colourful_fraction(path)
    assert spread > 20.0  # not a blank canvas
    assert colourful > 0.05  # the coloured section is drawn
    # mirrored about the axis: a full disc of the same height, about twice the coloured area
    fraction = {}
    for mirror in (False, True):
        path = plot_section(
            tmp_path / "plain.png",
            mesh,
            _field(mesh, 1.0),
            mirror=mirror,
            show_edges=False,
            window_size=(400, 300),
        )
        fraction[mirror] = _colourful_fraction(path)[1]
    assert fraction[True] == pytest.approx(2.0 * fraction[False], rel=0.25)
