"""Indentation fits against synthetic curves with known E and contact point (issue 4 numbers)."""

import re
from pathlib import Path

import numpy as np
import pytest

from afm.batch import fit_batch
from afm.curve_io import read_curves
from afm.fit import FitRange, fit_indentation
from afm.pierce import fit_pierce
from afm.synthetic import indentation_curve, pierce_curve
from oocyte_fe.errors import InputError

E_ZP, E_CYT = 7.01, 1.55  # seed 001, Section 3.1

GEOMETRIES = {
    "sneddon_cone": {"half_angle_deg": 10.0},
    "hertz_paraboloid": {"radius_um": 5.0},
    "hertz_sphere": {"radius_um": 5.0},
    "pyramid": {"face_angle_deg": 35.0},
    "pyramid_3s": {"face_angle_deg": 35.0},
}


@pytest.mark.parametrize("model", sorted(GEOMETRIES))
def test_noise_free_curve_gives_E_within_half_percent_and_contact_within_10_nm(model):
    curve = indentation_curve(E_ZP, 5.0, model=model, geometry=GEOMETRIES[model])
    fit = fit_indentation(curve, model=model, geometry=GEOMETRIES[model])
    assert fit.E_kPa == pytest.approx(E_ZP, rel=0.005)
    assert abs(fit.contact_point_um - 5.0) < 0.010
    assert fit.quality == "good"
    assert fit.contact_method == "fit"


def test_noise_and_tilt_over_20_seeds_median_E_within_3_percent_contact_within_50_nm():
    errors, contacts = [], []
    for seed in range(20):
        curve = indentation_curve(
            E_ZP, 5.0, noise_fraction=0.01, tilt_nN_per_um=0.05, offset_nN=0.3, seed=seed
        )
        fit = fit_indentation(curve)
        errors.append(abs(fit.E_kPa / E_ZP - 1))
        contacts.append(abs(fit.contact_point_um - 5.0))
    assert np.median(errors) < 0.03
    assert np.median(contacts) < 0.050


def test_deviation_contact_is_reported_and_close_on_clean_data():
    fit = fit_indentation(indentation_curve(E_ZP, 5.0), contact_method="deviation")
    assert fit.contact_method == "deviation"
    assert abs(fit.contact_point_um - 5.0) < 0.01
    assert fit.E_kPa == pytest.approx(E_ZP, rel=0.01)


def test_fit_range_by_depth_and_force_fraction_limit_the_window():
    curve = indentation_curve(E_ZP, 5.0)
    deep = fit_indentation(curve)
    by_depth = fit_indentation(curve, fit_range=FitRange(max_indentation_um=1.0))
    by_force = fit_indentation(curve, fit_range=FitRange(max_force_fraction=0.5))
    assert by_depth.indentation_um.max() <= 1.0 + 0.01
    assert by_force.force_nN.max() <= 0.5 * deep.force_nN.max() + 1e-9
    assert by_depth.E_kPa == pytest.approx(E_ZP, rel=0.005)
    assert by_force.E_kPa == pytest.approx(E_ZP, rel=0.005)


def test_pointwise_modulus_is_flat_when_the_model_holds_and_drifts_when_not():
    curve = indentation_curve(E_ZP, 5.0)
    delta, modulus = fit_indentation(curve).pointwise_modulus(0.2)
    np.testing.assert_allclose(modulus, E_ZP, rtol=1e-3)
    # a paraboloid fitted to cone data (F ~ delta^2, model ~ delta^1.5): E(delta) is not flat
    wrong = fit_indentation(curve, model="hertz_paraboloid", geometry={"radius_um": 5.0})
    delta, modulus = wrong.pointwise_modulus(0.2)
    assert modulus.max() > 1.3 * modulus.min()


def test_pierce_curve_gives_both_moduli_within_5_percent():
    curve = pierce_curve(E_ZP, E_CYT, noise_fraction=0.01, tilt_nN_per_um=0.05, seed=3)
    fit = fit_pierce(curve)
    assert fit.zp.E_kPa == pytest.approx(E_ZP, rel=0.05)
    assert fit.cytoplasm.E_kPa == pytest.approx(E_CYT, rel=0.05)
    assert fit.event.drop_nN > 0.5 * fit.event.peak_force_nN


def test_pierce_curve_noise_free_is_exact():
    fit = fit_pierce(pierce_curve(E_ZP, E_CYT, residual_fraction=0.3))
    assert fit.zp.E_kPa == pytest.approx(E_ZP, rel=1e-3)
    assert fit.cytoplasm.E_kPa == pytest.approx(E_CYT, rel=1e-3)
    assert fit.cytoplasm.offset_nN == pytest.approx(0.3 * 8.0, rel=1e-3)


def test_curve_without_pierce_is_refused():
    with pytest.raises(InputError, match="pierce event"):
        fit_pierce(indentation_curve(E_ZP, 5.0))


def test_fit_range_outside_the_data_is_refused():
    curve = indentation_curve(E_ZP, 5.0, max_piezo_um=6.0)
    with pytest.raises(InputError, match="max_indentation_um"):
        fit_indentation(curve, fit_range=FitRange(max_indentation_um=5.0))
    with pytest.raises(InputError, match="max_force_fraction"):
        FitRange(max_force_fraction=1.5)


def test_curve_that_never_reaches_contact_is_refused():
    curve = indentation_curve(E_ZP, 20.0, max_piezo_um=8.0, noise_fraction=0.0)
    curve = curve.with_force(curve.force_nN + np.random.default_rng(0).normal(0, 0.01, 2000))
    with pytest.raises(InputError, match="reaches contact"):
        fit_indentation(curve)


@pytest.mark.parametrize(
    ("contact_um", "approach_um", "tolerance_um"),
    [(1.5, 5.0, 0.010), (3.0, 5.0, 0.010), (4.0, 5.0, 0.010), (3.0, 8.0, 0.010), (2.0, 8.0, 0.020)],
)
def test_contact_accuracy_does_not_depend_on_where_contact_lies(
    contact_um, approach_um, tolerance_um
):
    # issue 17 item 10: contact at 3 um of 8 gave 80 nm median, at 2 um 209 nm (the baseline line
    # reached into contact and tilted); with the refined baseline < 10 nm from 30 % of the
    # approach on; at 25 % the noise (1 % of a larger maximum force) gives 14 nm
    errors = []
    for seed in range(20):
        curve = indentation_curve(
            E_ZP,
            contact_um,
            max_piezo_um=approach_um,
            noise_fraction=0.01,
            tilt_nN_per_um=0.05,
            offset_nN=0.2,
            seed=seed,
        )
        fit = fit_indentation(curve)
        errors.append(abs(fit.contact_point_um - contact_um))
        assert fit.baseline.n_points < np.count_nonzero(curve.piezo_um < contact_um)
    assert np.median(errors) < tolerance_um


QI_MAP = (
    Path(__file__).parent / "data" / "instrument" / "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data"
)


def test_qi_curves_that_barely_reach_contact_are_refused_saying_why():
    # the 4 curves of this JPK QI map (afmformats' test data) rise above the noise only in
    # their last 3-5 points: nanite gives 0.27-0.45 kPa with its contact weighting and 32-89
    # kPa without it (benchmarks/afm_parity.py). The default analysis refuses them with the
    # threshold and what the curve did, never "fit range" (none was given), and a batch
    # reports every one as an error row without a modulus
    pytest.importorskip("afmformats", reason="reading JPK files needs afmformats (afm extra)")
    curves = read_curves(QI_MAP)
    assert len(curves) == 4
    for curve in curves:
        with pytest.raises(InputError, match="reaches contact") as info:
            fit_indentation(curve, "sneddon_cone", {"half_angle_deg": 30.0})
        message = str(info.value)
        assert "fit range" not in message
        assert re.search(r"got '(no contact: .* nN|\d points past the contact estimate)", message)
    batch = fit_batch([QI_MAP], geometry={"half_angle_deg": 30.0})
    assert [r.fit for r in batch.rows] == [None] * 4
    assert all("reaches contact" in r.error for r in batch.rows)
