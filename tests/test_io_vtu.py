"""VTU/PVD field series (round trip through meshio, whole-or-nothing), history CSV and the
off-screen section PNG."""

from __future__ import annotations

import os
import subprocess
import sys
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
        u = m.point_data["displacement_um"]
        assert u.shape == (mesh.doflocs.shape[1], 3)
        assert np.allclose(u[:, :2], _field(mesh, t).T) and np.all(u[:, 2] == 0)
        assert np.allclose(m.point_data["pressure_kPa"], 2.0 * t)  # mid-edge interpolated
        assert np.allclose(m.point_data["von_Mises_kPa"], t * mesh.doflocs[0])
        assert set(m.point_data) == {
            "displacement_um",
            "pressure_kPa",
            "von_Mises_kPa",
            "contact_pressure_kPa",
        }
        region = m.cell_data["region_id"][0]
        assert np.all(region[mesh.subdomains["cytoplasm"]] == 1)
        assert np.all(region[mesh.subdomains["zona"]] == 2)

    # VTK's own readers (as ParaView uses them) see the series, its times and the fields
    reader = pv.get_reader(str(folder / "fields.pvd"))
    assert reader.time_values == times
    reader.set_active_time_value(times[-1])
    grid = reader.read()[0]
    assert set(grid.celltypes) == {22 if order == 2 else 5}  # VTK (quadratic) triangle
    assert np.allclose(grid.point_data["displacement_um"][:, :2], _field(mesh, times[-1]).T)


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
    assert sorted(p.name for p in folder.iterdir()) == [
        "fields.pvd",
        "fields_0000.vtu",
        "view_fields.py",
    ]
    assert [p.name for p in tmp_path.iterdir()] == ["fields"]


def _plate(t: float) -> np.ndarray:
    """A flat plate (um) coming down onto the section's top as t grows."""
    return np.array([[0.0, 95.0 - 5.0 * t], [40.0, 95.0 - 5.0 * t]])


def _series_with_plate(folder, mesh, times):
    with FieldSeriesWriter(folder, mesh, "press", axisymmetric=True) as series:
        for t in times:
            p = np.full(mesh.nvertices, t)
            series.write(t, _field(mesh, t), pressure=p, obstacles={"plate": _plate(t)})


def test_obstacles_are_their_own_series(tmp_path):
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0))
    times = [0.0, 0.5, 1.0]
    _series_with_plate(tmp_path / "fields", mesh, times)
    reader = pv.get_reader(str(tmp_path / "fields" / "press_plate.pvd"))
    assert reader.time_values == times
    for t in times:
        reader.set_active_time_value(t)
        plate = reader.read()[0]
        assert set(plate.celltypes) == {3}  # VTK_LINE
        assert np.allclose(plate.points[:, :2], _plate(t))
    with pytest.raises(ValueError, match="obstacle 'plate'"):
        with FieldSeriesWriter(tmp_path / "bad", mesh) as series:
            series.write(0.0, _field(mesh, 0.0), obstacles={"plate": np.zeros(2)})
    assert not (tmp_path / "bad").exists()


def test_viewer_script_renders_the_series_off_screen(tmp_path):
    """The script beside the series runs on its own (pyvista only) and draws the section."""
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0, order=2))
    _series_with_plate(tmp_path / "fields", mesh, [0.0, 1.0])
    script = tmp_path / "fields" / "view_press.py"
    png = tmp_path / "view.png"
    done = subprocess.run(
        [sys.executable, str(script), "--time", "1", "--screenshot", str(png)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        env=dict(os.environ, PYVISTA_OFF_SCREEN="true"),
    )
    assert done.returncode == 0, done.stderr[-2000:]
    from PIL import Image

    image = np.asarray(Image.open(png).convert("RGB"), dtype=float)
    assert image.std() > 20.0 and (np.ptp(image, axis=2) > 60).mean() > 0.05
    # mirrored: the coloured section spans both sides of the image centre line (r = 0)
    coloured = np.ptp(image, axis=2) > 60
    cols = np.flatnonzero(coloured.any(axis=0))
    centre = image.shape[1] / 2
    assert cols.min() < centre - 100 and cols.max() > centre + 100


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


def test_section_window_draws_only_the_window(tmp_path):
    """A window around the top pole: the section fills the view, nothing else of the disc."""
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=15.0))
    whole = plot_section(tmp_path / "w.png", mesh, _field(mesh, 1.0), window_size=(400, 300))
    part = plot_section(
        tmp_path / "p.png",
        mesh,
        _field(mesh, 1.0),
        mirror=True,
        window=(-30.0, 30.0, 50.0, 95.0),
        window_size=(400, 300),
    )
    assert _colourful_fraction(part)[1] > 1.5 * _colourful_fraction(whole)[1]
    with pytest.raises(ValueError, match="no element inside the window"):
        plot_section(tmp_path / "x.png", mesh, window=(500.0, 600.0, 0.0, 10.0))
