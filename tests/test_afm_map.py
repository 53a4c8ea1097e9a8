"""Issue 28 speed: an afmformats HDF5 force map read in one pass and fitted in two processes
gives the same curves and fits as afmformats' own loader and one process."""

from __future__ import annotations

import types
from pathlib import Path

import numpy as np
import pytest

from afm.batch import fit_batch
from afm.curve_io import iter_curves, read_curves
from afm.instrument_io import curve_from_record, load_records
from afm.synthetic import indentation_curve

afmformats = pytest.importorskip("afmformats")
h5py = pytest.importorskip("h5py")


def _write_map(path: Path, side: int, n_points: int = 300) -> Path:
    """A side x side map of synthetic curves through afmformats' own HDF5 exporter."""
    with h5py.File(path, "w") as h5:
        for i in range(side * side):
            curve = indentation_curve(
                2.0 + 0.05 * i,
                3.0,
                max_piezo_um=6.0,
                n_points=n_points,
                noise_fraction=0.01,
                seed=i,
            )
            force, height = curve.force_nN * 1e-9, -curve.piezo_um * 1e-6
            data = {
                "force": np.concatenate([force, force[::-1]]),
                "height (measured)": np.concatenate([height, height[::-1]]),
                "height (piezo)": np.concatenate([height, height[::-1]]) * 1.01,
                "segment": np.repeat([False, True], n_points),
                "time": np.linspace(0.0, 1.0, 2 * n_points),
            }
            metadata = {
                "enum": i,
                "path": path,
                "imaging mode": "force-distance",
                "spring constant": 0.07,
                "sensitivity": 5e-8,
                "position x": 5e-6 * (i % side),
                "position y": 5e-6 * (i // side),
                "grid shape x": side,
                "grid shape y": side,
                "point count": 2 * n_points,
                "duration": 1.0,
            }
            afmformats.AFMForceDistance(data, metadata).export_data(h5, fmt="hdf5")
    return path


def test_hdf5_map_reads_as_afmformats_does(tmp_path):
    path = _write_map(tmp_path / "map.h5", 4)
    curves = iter_curves(path)
    assert isinstance(curves, types.GeneratorType)  # taken as read: fitting overlaps reading
    ours = {c.curve_index: c for c in curves}
    assert sorted(ours) == list(range(16))
    for record in load_records(path):  # afmformats' own loader, one curve at a time
        index = int(record.metadata["enum"])
        theirs = curve_from_record(record, f"{path} (curve {index})", "auto", "", index)
        mine = ours[index]
        np.testing.assert_array_equal(mine.piezo_um, theirs.piezo_um)
        np.testing.assert_array_equal(mine.force_nN, theirs.force_nN)
        np.testing.assert_array_equal(mine.time_s, theirs.time_s)
        assert mine.map_position_um == pytest.approx(theirs.map_position_um, abs=1e-12)
        assert mine.spring_constant_nN_per_um == theirs.spring_constant_nN_per_um == 70.0
        assert mine.height_channel == "height (measured)" and mine.source == theirs.source
    piezo = read_curves(path, height_channel="height (piezo)")
    np.testing.assert_allclose(piezo[3].piezo_um, 1.01 * ours[3].piezo_um, rtol=1e-12)


def test_two_fitting_processes_give_the_rows_of_one(tmp_path):
    path = _write_map(tmp_path / "map.h5", 12)  # 144 curves: three chunks of 64 or fewer
    serial = fit_batch([path], geometry={"half_angle_deg": 10.0})
    reported: list[tuple[int, int]] = []
    parallel = fit_batch(
        [path], geometry={"half_angle_deg": 10.0}, workers=2, progress=lambda *p: reported.append(p)
    )
    assert reported == [(64, 144), (128, 144), (144, 144)]  # three chunks, as they come back
    assert len(parallel.rows) == 144
    for a, b in zip(serial.rows, parallel.rows, strict=True):
        assert (a.curve_index, a.map_position_um, a.error) == (b.curve_index, b.map_position_um, "")
        assert b.fit.E_kPa == a.fit.E_kPa and b.fit.rating == a.fit.rating
    moduli = [r.fit.E_kPa for r in parallel.rows]
    np.testing.assert_allclose(moduli, 2.0 + 0.05 * np.arange(144), rtol=0.03)
