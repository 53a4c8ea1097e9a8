"""Real instrument files (afmformats 0.18.7's test data): channel, routing, errors, maps, creep.

Files come from tests/data/instrument (shipped, see its README) or the download in
tests/instrument_data.py; afmformats itself is the peer that reads the raw columns.
"""

import numpy as np
import pytest

from afm.batch import fit_batch, write_batch_table
from afm.creep import fit_creep
from afm.curve_io import read_creep, read_curve, read_curves
from afm.fit import fit_indentation
from afm.plotting import plot_modulus_map
from oocyte_fe.errors import InputError
from tests.instrument_data import instrument_file

afmformats = pytest.importorskip("afmformats")

SPOT3 = "fmt-jpk-fd_spot3-0192.jpk-force"
WORKSHOP = "fmt-afm-workshop-fd_single_2020-02-14_13.41.25.csv"
WORKSHOP_NO_META = "fmt-afm-workshop-fd_single_2018-08-01_13.06.09.csv"
QI_MAP = "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data"
CREEP = "fmt-jpk-cc_pr14-polymergel-2021.06.30.jpk-force"
JPK_SOFTWARE_E_KPA = 348.6  # JPK data processing, cone 30 deg, nu 0.5 (issue 17)


def test_jpk_curve_uses_the_measured_height_and_matches_the_jpk_software():
    # the piezo channel gave 10 245 kPa ("good"); the JPK software gives 348.6 kPa
    curve = read_curve(instrument_file(SPOT3))
    assert curve.height_channel == "height (measured)"
    fit = fit_indentation(curve, "sneddon_cone", {"half_angle_deg": 30.0}, 0.5)
    assert fit.height_channel == "height (measured)"
    assert fit.E_kPa == pytest.approx(JPK_SOFTWARE_E_KPA, rel=0.03)


def test_height_channel_override_is_used_and_reported():
    path = instrument_file(SPOT3)
    piezo = read_curve(path, height_channel="height (piezo)")
    (record,) = afmformats.load_data(path)
    np.testing.assert_allclose(piezo.piezo_um, -record.appr["height (piezo)"] * 1e6)
    fit = fit_indentation(piezo, "sneddon_cone", {"half_angle_deg": 30.0}, 0.5)
    assert fit.height_channel == "height (piezo)" and fit.E_kPa > 10 * JPK_SOFTWARE_E_KPA
    with pytest.raises(InputError, match="height_channel"):
        read_curve(path, height_channel="tip position")


def test_jittering_measured_height_is_fitted_as_recorded():
    path = instrument_file(SPOT3)
    (record,) = afmformats.load_data(path)
    measured = -np.asarray(record.appr["height (measured)"]) * 1e6
    assert np.count_nonzero(np.diff(measured) < 0) > 10  # the sensor jitters back
    curve = read_curve(path)
    np.testing.assert_array_equal(curve.piezo_um, measured)  # not sorted, not filtered


def test_afm_workshop_csv_goes_to_afmformats():
    path = instrument_file(WORKSHOP)
    with pytest.raises(InputError, match="spring constant") as info:
        read_curve(path)  # the file has force in nN but no spring constant for the tip position
    assert str(path) in str(info.value)
    curve = read_curve(path, spring_constant_N_per_m=20.0)
    (record,) = afmformats.load_data(path)
    np.testing.assert_allclose(curve.piezo_um, -record.appr["height (measured)"] * 1e6)
    np.testing.assert_allclose(curve.force_nN, record.appr["force"] * 1e9)
    assert curve.height_channel == "height (measured)"


def test_missing_metadata_is_our_error_and_the_batch_goes_on(tmp_path):
    bad = instrument_file(WORKSHOP_NO_META)
    with pytest.raises(InputError, match="spring constant and sensitivity") as info:
        read_curve(bad)  # afmformats raises MissingMetaDataError, a BaseException
    assert str(bad) in str(info.value)
    result = fit_batch(
        [bad, instrument_file(SPOT3)],
        model="sneddon_cone",
        geometry={"half_angle_deg": 30.0},
    )
    assert [bool(r.error) for r in result.rows] == [True, False]
    assert "sensitivity" in result.rows[0].error
    table = write_batch_table(result, tmp_path / "fits.csv").read_text().splitlines()
    assert "height_channel" in table[0] and "height (measured)" in table[2]


def test_every_map_curve_is_read_with_its_position(tmp_path):
    path = instrument_file(QI_MAP)
    records = afmformats.load_data(path)
    curves = read_curves(path)
    assert len(curves) == len(records) == 4
    for curve, record in zip(curves, records, strict=True):
        expected = (record.metadata["position x"] * 1e6, record.metadata["position y"] * 1e6)
        assert curve.map_position_um == pytest.approx(expected)
        assert curve.curve_index == record.metadata["enum"]
    result = fit_batch([path])
    assert [r.curve_index for r in result.rows] == [0, 1, 2, 3]
    assert all(r.map_position_um is not None for r in result.rows)
    png = plot_modulus_map(result, path, tmp_path / "map.png")
    assert png.stat().st_size > 5_000


def test_force_map_gives_a_modulus_per_position(tmp_path):
    path = instrument_file("fmt-jpk-fd_map2x2_extracted.jpk-force-map")
    result = fit_batch([path], model="sneddon_cone", geometry={"half_angle_deg": 30.0})
    assert len(result.rows) == 4 and not result.failures
    positions = {r.map_position_um for r in result.rows}
    assert len(positions) == 4
    moduli = [r.fit.E_kPa for r in result.rows]
    assert all(m > 0 for m in moduli) and len(set(np.round(moduli, 3))) == 4
    # each E is the least-squares modulus of its own window (the fit's normal equation in E,
    # dF/dE = shape): E = sum F s / sum s^2 with Sneddon's cone s = 2 tan(alpha) delta^2 /
    # (pi (1 - nu^2)) at the fitted contact, alpha = 30 deg, nu = 0.5 (measured 1e-13; 1e-8)
    for r in result.rows:
        delta = np.clip(r.fit.indentation_um, 0.0, None)
        shape = 2.0 / np.pi * np.tan(np.radians(30.0)) / (1.0 - 0.5**2) * delta**2
        force = r.fit.force_nN - r.fit.offset_nN
        assert r.fit.E_kPa == pytest.approx(np.dot(force, shape) / np.dot(shape, shape), rel=1e-8)
    assert plot_modulus_map(result, path, tmp_path / "map.png").stat().st_size > 5_000


def test_instrument_creep_file_gives_compliance_and_prony_series():
    path = instrument_file(CREEP)
    (record,) = afmformats.load_data(path)
    data = read_creep(path)
    hold = record.intr
    assert data.time_s.size == len(hold["force"])
    np.testing.assert_allclose(data.time_s, hold["time"] - hold["time"][0])
    # indentation changes by exactly the tip travel during the hold (tip = piezo - F/k)
    k = record.metadata["spring constant"]
    tip = -(np.asarray(hold["height (measured)"]) + np.asarray(hold["force"]) / k) * 1e6
    np.testing.assert_allclose(np.diff(data.indentation_um), np.diff(tip), atol=1e-9)
    assert data.indentation_um[-1] > data.indentation_um[0]  # the gel creeps
    fit = fit_creep(data, half_angle_deg=30.0, nu=0.5)
    assert fit.relative_rms < 0.01
    assert fit.E0_kPa > fit.E_inf_kPa > 0


def test_force_distance_file_is_not_a_creep_file():
    with pytest.raises(InputError, match="creep-compliance"):
        read_creep(instrument_file(SPOT3))


def test_tip_position_column_is_preferred_and_kept():
    n, k = 200, 0.05  # N/m
    height = np.linspace(2e-6, 0.0, n)  # afmformats' sign: decreasing towards the sample
    force = np.where(height < 1e-6, (1e-6 - height) * 2e-3, 0.0)
    tip = height + force / k
    data = {
        "force": force,
        "height (measured)": height,
        "tip position": tip,
        "segment": np.zeros(n, dtype=bool),
    }
    meta = {"spring constant": k, "imaging mode": "force-distance", "enum": 0, "path": "x"}
    from afm.instrument_io import curve_from_record

    curve = curve_from_record(afmformats.AFMForceDistance(data, meta), "x")
    assert curve.height_channel == "tip position"
    np.testing.assert_allclose(curve.tip_position_um, -tip * 1e6, atol=1e-9)
    measured = curve_from_record(afmformats.AFMForceDistance(data, meta), "x", "height (measured)")
    np.testing.assert_allclose(measured.piezo_um, -height * 1e6)
