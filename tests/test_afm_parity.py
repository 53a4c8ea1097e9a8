"""Parity with nanite on real files: E within 1 %, contact point within 10 nm.

Runs ``benchmarks/afm_parity.py``'s comparison (nanite's default preprocessing and fit against
``afm.nanite_pipeline.fit_nanite_default`` re-derived here) on a subset of afmformats 0.18.7's
test files that takes seconds; the benchmark prints the whole table.
"""

import importlib.util
import sys
from pathlib import Path

import pytest

from afm.nanite_pipeline import fit_nanite_default
from afm.synthetic import indentation_curve
from tests.instrument_data import instrument_file

BENCHMARK = Path(__file__).resolve().parents[1] / "benchmarks" / "afm_parity.py"
SUBSET = [
    "fmt-jpk-fd_spot3-0192.jpk-force",
    "fmt-afm-workshop-fd_single_2020-02-14_13.41.25.csv",
    "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data",
    "fmt-hdf5-fd_version_0.13.3.h5",
    "fmt-igor-fd_U3_3_p10004.ibw",
    "fmt-igor-fd_SiN_FD_plot.ibw",
    "fmt-jpk-fd_flipsign_2015.05.22-15.31.49.352.jpk-force",
    # nearly flat (E ~ 20 Pa): the contact point is barely determined, so it tells whether
    # both tools follow the same optimiser path on the same model (the three-sided pyramid)
    "fmt-jpk-fd_single-modified_2023.jpk-force",
]


def _benchmark():
    if "afm_parity" not in sys.modules:
        spec = importlib.util.spec_from_file_location("afm_parity", BENCHMARK)
        module = importlib.util.module_from_spec(spec)
        sys.modules["afm_parity"] = module  # dataclasses look their module up there
        spec.loader.exec_module(module)
    return sys.modules["afm_parity"]


def test_nanite_route_recovers_a_known_modulus():
    curve = indentation_curve(7.01, 5.0, n_points=2000, noise_fraction=0.01, offset_nN=0.2, seed=3)
    fit = fit_nanite_default(curve)
    assert fit.E_kPa == pytest.approx(7.01, rel=0.02)
    assert fit.contact_point_um == pytest.approx(5.0, abs=0.02)


@pytest.mark.parametrize("name", SUBSET)
def test_same_modulus_and_contact_as_nanite(name):
    pytest.importorskip("nanite", reason="nanite (the 'bench' extra) is not installed")
    path = instrument_file(name)
    rows = _benchmark().parity_rows(path)
    assert rows and all(not r.note for r in rows)
    for r in rows:
        assert abs(r.difference) < 0.01, r
        assert abs(r.contact_diff_nm) < 10.0, r


CLEAN = [
    "fmt-jpk-fd_spot3-0192.jpk-force",
    "fmt-igor-fd_U3_3_p10004.ibw",
    "fmt-hdf5-fd_version_0.13.3.h5",
    "fmt-tab-fd_version_0.13.3.tab",
]


@pytest.mark.parametrize("name", CLEAN)
def test_default_analysis_differs_from_nanite_by_its_contact_weighting(name):
    # fit_indentation (baseline line, unweighted) against nanite with its contact-point
    # weighting switched off (weight_cp = 0): within 1 % on clean indentation curves; the
    # larger difference from nanite's default (up to 10 % here) is that weighting
    pytest.importorskip("nanite", reason="nanite (the 'bench' extra) is not installed")
    rows = _benchmark().parity_rows(instrument_file(name))
    assert rows and all(not r.note for r in rows), rows  # a file not read gives one noted row
    for r in rows:
        # clean curves: no criterion but E(delta)'s change near contact rates them poor (U3's
        # paraboloid 27 -> 36 kPa, issue 28; spot3's 19 -> 14 kPa within its first 30 nm)
        assert r.default_quality == "good" or "E(delta) changes" in r.default_quality, r
        assert ";" not in r.default_quality, r
        assert abs(r.default_unweighted_difference) < 0.01, r


def test_ninefold_difference_from_nanite_is_its_contact_weighting():
    # the shipped AFM-Workshop curve: nanite's weighted cone fit gives 8x our E (it settles on
    # a contact point ~0.13 um up the rise); unweighted, nanite agrees with ours within 3 %
    # (the rest: baseline line against nanite's constant offset, docs/afm.md)
    pytest.importorskip("nanite", reason="nanite (the 'bench' extra) is not installed")
    path = instrument_file("fmt-afm-workshop-fd_single_2018-08-01_13.06.09.csv")
    rows = _benchmark().parity_rows(path, models=("sneddon_cone",))
    [r] = rows
    assert r.default_quality == "good"
    assert r.E_nanite_kPa > 7 * r.E_default_kPa
    assert abs(r.default_unweighted_difference) < 0.03, r
