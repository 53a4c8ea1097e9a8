"""Issue 28 B: the viscoelastic option of ``afm_fit_files`` run from a case folder (no Python).

The shipped case ``cases/afm_ramp_viscoelastic`` holds the project's FE ramps (a Prony cell,
E_inf 0.4 kPa, E_i 0.3 kPa, tau 0.05 and 0.5 s) as afmformats HDF5 files; the tests run it as
the CLI does and read fits.csv, the material file and the metrics.
"""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from afm.curve_io import write_curve
from afm.material_file import read_material
from afm.ramp_io import read_ramps
from afm.synthetic import indentation_curve
from oocyte_fe.errors import InputError
from oocyte_fe.runner.run import plan, run_cases

CASE = Path(__file__).parents[1] / "cases" / "afm_ramp_viscoelastic"


def _run(case: Path, out: Path):
    [result] = run_cases(plan([case], quick=True), out, quick=True)
    return result, out / case.name


def test_case_folder_recovers_the_prony_series_from_two_speeds(tmp_path):
    result, folder = _run(CASE, tmp_path / "out")
    assert result.status == "PASS", result.reason
    metrics = json.loads((folder / "metrics.json").read_text())
    metrics = metrics.get("metrics", metrics)
    assert metrics["ve_E_inf_kPa"] == pytest.approx(0.4, rel=0.03)  # -2.6 %
    assert metrics["ve_E1_kPa"] == pytest.approx(0.3, rel=0.03)
    assert metrics["ve_E2_kPa"] == pytest.approx(0.3, rel=0.03)
    assert metrics["ve_tau1_s"] == pytest.approx(0.05, rel=0.10)
    assert metrics["ve_tau2_s"] == pytest.approx(0.5, rel=0.10)
    material = read_material(folder / "material_cell.toml")
    assert material.E_kPa == pytest.approx(1.0, rel=0.03)
    assert material.g == pytest.approx((0.3, 0.3), rel=0.03)
    assert material.tau_s == pytest.approx((0.05, 0.5), rel=0.10)
    assert "ramp fit" in material.source and "good" in material.source
    with (folder / "fits.csv").open() as fh:
        rows = {Path(r["file"]).name: r for r in csv.DictReader(fh)}
    fast, slow = rows["ramp_T0.1s.h5"], rows["ramp_T1s.h5"]
    # one speed alone leaves a time unresolved: flagged per curve
    assert fast["ve_quality"] == "poor" and "tau_2" in fast["ve_undetermined"]
    assert slow["ve_quality"] == "poor" and "tau_1" in slow["ve_undetermined"]
    assert float(fast["ramp_speed_um_per_s"]) == pytest.approx(2.0, rel=0.02)
    assert float(slow["ramp_speed_um_per_s"]) == pytest.approx(0.2, rel=0.02)
    assert fast["ve_relaxation"] == "prony" and fast["ve_used_retract"] == "true"
    assert abs(float(fast["ve_drag_offset_nN"])) < 1e-9  # the FE has no drag
    assert fast["ve_plot"] == "curve_plots/ramp_T0.1s_ramp_fit.png"
    assert (folder / fast["ve_plot"]).stat().st_size > 10_000
    report = (folder / "report.md").read_text()
    assert "Viscous drag" in report and "ramp_cell.png" in report
    assert (folder / "ramp_cell.png").stat().st_size > 10_000


def _copy(tmp_path: Path, old: str, new: str) -> Path:
    """The shipped case with ``old`` replaced by ``new`` in its inputs, without its checks."""
    case = tmp_path / "case"
    shutil.copytree(CASE, case)
    toml = (case / "case.toml").read_text().replace(old, new)
    (case / "case.toml").write_text(toml[: toml.index("[reference")])
    return case


def test_power_law_gives_no_material_series(tmp_path):
    # a power law gives no Prony series: the group's material stays elastic, and says why
    case = _copy(tmp_path, 'relaxation = "prony", terms = 2', 'relaxation = "power_law"')
    result, folder = _run(case, tmp_path / "out")
    assert result.status == "PASS", result.reason
    metrics = json.loads((folder / "metrics.json").read_text())
    metrics = metrics.get("metrics", metrics)
    assert 0.0 < metrics["ve_beta"] < 1.0
    material = read_material(folder / "material_cell.toml")
    assert material.g == () and "elastic" in material.source
    assert "a power law" in (folder / "report.md").read_text()


def test_a_creep_record_wins_over_the_ramp_fit(tmp_path):
    case = _copy(tmp_path, "nu = 0.5\n", 'nu = 0.5\ncreep = { cell = "creep/cell.csv" }\n')
    (case / "creep").mkdir()
    shutil.copy(CASE.parent / "afm_fit_files" / "creep" / "zp_creep.csv", case / "creep/cell.csv")
    result, folder = _run(case, tmp_path / "out")
    assert result.status == "PASS", result.reason
    material = read_material(folder / "material_cell.toml")
    assert "creep cell.csv" in material.source and "ramp fit" not in material.source
    report = (folder / "report.md").read_text()
    assert "the creep record gives the material file; the ramp fit is reported only" in report


def test_file_without_times_is_refused_in_one_line(tmp_path):
    case = tmp_path / "case"
    (case / "curves").mkdir(parents=True)
    curve = indentation_curve(2.0, 3.0, max_piezo_um=6.0, n_points=300, seed=1)
    path = write_curve(curve, case / "curves" / "no_time.csv")  # piezo_um, force_nN only
    (case / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "test"\n[inputs]\ncurves = "curves"\n'
        'viscoelastic = { relaxation = "sls" }\n'
    )
    with pytest.raises(InputError) as err:
        read_ramps(path)
    assert str(err.value) == (
        f"{path}: time_s: expected a time_s column (the viscoelastic fit needs times)"
    )
    result, _ = _run(case, tmp_path / "out")
    assert result.status == "ERROR"
    assert "time_s: expected a time_s column" in result.reason and "\n" not in result.reason


def test_csv_table_with_times_reads_approach_and_retract(tmp_path):
    t = np.linspace(0.0, 2.0, 201)
    piezo = 3.0 - np.abs(t - 1.0) * 3.0  # up 3 um in 1 s and back
    force = np.clip(piezo - 2.0, 0.0, None) ** 1.5
    path = tmp_path / "ramp.csv"
    body = "\n".join(f"{a:.6g},{b:.6g},{c:.6g}" for a, b, c in zip(t, piezo, force, strict=True))
    path.write_text(f"# spring_constant_N_per_m = 0.05\ntime_s,piezo_um,force_nN\n{body}\n")
    [ramp] = read_ramps(path)
    assert ramp.n_approach == 101 and ramp.time_s.size == 201
    assert ramp.speed_um_per_s == pytest.approx(3.0, rel=1e-6)
    assert ramp.spring_constant_nN_per_um == pytest.approx(50.0)


def test_instrument_record_without_times_is_refused_in_one_line():
    afmformats = pytest.importorskip("afmformats")
    from afm.instrument_io import ramp_from_record

    n = 100
    height = np.r_[np.linspace(2e-6, 0.0, n), np.linspace(0.0, 2e-6, n)]
    data = {
        "force": np.clip(1e-6 - height, 0.0, None) * 2e-3,
        "height (measured)": height,
        "segment": np.repeat([False, True], n),
    }
    meta = {"spring constant": 0.05, "imaging mode": "force-distance", "enum": 0, "path": "x"}
    record = afmformats.AFMForceDistance(data, meta)
    with pytest.raises(InputError) as err:
        ramp_from_record(record, "x.jpk-force")
    assert str(err.value) == (
        "x.jpk-force: time: expected a time column (the viscoelastic fit needs times)"
    )
    data["time"] = np.linspace(0.0, 2.0, 2 * n)
    ramp = ramp_from_record(afmformats.AFMForceDistance(data, meta), "x.jpk-force")
    assert ramp.n_approach == n and ramp.time_s.size == 2 * n
    assert ramp.speed_um_per_s == pytest.approx(2.0 / (99 / 199 * 2.0), rel=1e-9)
    np.testing.assert_allclose(ramp.piezo_um[:n], -height[:n] * 1e6)


def test_a_real_approach_is_elastic_to_the_ramp_fit_and_the_fit_says_so():
    # afmformats' JPK curve (30 deg cone): the approach alone shows no relaxation, so the power
    # law reduces to the elastic Sneddon fit (beta at its bound 0, flagged) and E0 equals
    # fit_indentation's modulus within 5 % (the contact point is found two ways); with the
    # retract the hysteresis gives a positive exponent (measured 0.093) and a lower E0
    from afm.curve_io import read_curve
    from afm.fit import fit_indentation
    from afm.ramp_io import ramp_curve
    from afm.viscoelastic import fit_ramp

    path = Path(__file__).parent / "data" / "instrument" / "fmt-jpk-fd_spot3-0192.jpk-force"
    tip = {"half_angle_deg": 30.0}
    elastic = fit_indentation(read_curve(path), "sneddon_cone", tip, nu=0.5)
    ramp = ramp_curve(read_ramps(path)[0])
    approach = fit_ramp(ramp, "sneddon_cone", tip, 0.5, "power_law", use_retract=False)
    assert approach.theta[0] == pytest.approx(0.0, abs=1e-6)
    assert any("beta" in why and "bound" in why for why in approach.undetermined)
    assert approach.amplitudes_kPa[0] == pytest.approx(elastic.E_kPa, rel=0.05)
    both = fit_ramp(ramp, "sneddon_cone", tip, 0.5, "power_law", use_retract=True)
    assert 0.05 < both.theta[0] < 0.15 and not both.undetermined
    assert both.amplitudes_kPa[0] < approach.amplitudes_kPa[0]
