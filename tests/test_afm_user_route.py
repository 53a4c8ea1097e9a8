"""Issue 28 A: the afm_fit_files route as a new user meets it (items 1-4, 8 and 9).

Each test builds a case folder of synthetic or shipped instrument files, runs it as the CLI
does and reads what a user reads: ``fits.csv``, the report, the material files.
"""

from __future__ import annotations

import csv
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from afm.creep import fit_creep_tip
from afm.creep_data import CreepData
from afm.curve_io import read_curve, write_creep, write_curve
from afm.fit import FitRange, fit_indentation
from afm.material_file import read_material
from afm.prony_series import RelaxationProny, creep_from_relaxation
from afm.synthetic import indentation_curve
from oocyte_fe.runner.registry import get_kind
from oocyte_fe.runner.run import plan, run_cases
from oocyte_fe.runner.scaffold import new_case

CASE = Path(__file__).parents[1] / "cases" / "afm_fit_files"
INSTRUMENT = Path(__file__).parent / "data" / "instrument"
WORKSHOP_VOLTS = "fmt-afm-workshop-fd_single_2018-08-01_13.06.09.csv"  # no k, no sensitivity
WORKSHOP_FORCE = "fmt-afm-workshop-fd_single_2020-02-14_13.41.25.csv"  # force in nN, no k


def _run(case: Path, out: Path):
    [result] = run_cases(plan([case], quick=True), out, quick=True)
    return result, out / case.name


def _rows(folder: Path) -> list[dict[str, str]]:
    with (folder / "fits.csv").open() as fh:
        return list(csv.DictReader(fh))


def _case(folder: Path, inputs: str) -> Path:
    (folder / "case.toml").write_text(
        f'kind = "afm_fit_files"\ndescription = "test"\n[inputs]\ncurves = "curves"\n{inputs}'
    )
    return folder


def _curve_file(folder: Path, name: str, E_kPa: float, **options) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    options = {"noise_fraction": 0.01, "seed": 1, "n_points": 600, **options}
    return write_curve(indentation_curve(E_kPa, 3.0, max_piezo_um=6.0, **options), folder / name)


def test_new_case_on_own_files_says_done_and_needs_no_known_moduli(tmp_path):
    # item 1: `oocyte-fe new` pointed known_moduli at a template of the shipped synthetic
    # files, so the first run on one's own curves FAILed
    case = tmp_path / "mine"
    written = new_case(get_kind("afm_fit_files"), case)
    assert [p.name for p in written] == ["case.toml", "example_cone_1.55kPa.csv"]
    text = (case / "case.toml").read_text()
    assert "\nknown_moduli =" not in text and '\ncurves = "curves"' in text
    shutil.rmtree(case / "curves")  # one's own curves in place of the example
    shutil.copytree(CASE / "curves", case / "curves")
    result, out = _run(case, tmp_path / "out")
    assert result.status == "PASS", result.reason
    [done] = json.loads((out / "metrics.json").read_text())["checks"]
    assert done["name"] == "done: 12 fitted, 0 poor, 1 refused" and done["computed"] == 12
    assert "done: 12 fitted, 0 poor, 1 refused" in (out / "report.md").read_text()


def test_calibration_inputs_read_files_without_spring_constant(tmp_path):
    # item 2: AFM-Workshop CSVs carry no spring constant (and the volts one no sensitivity);
    # the case gives them globally and per file pattern, and the table says which k was used
    case = tmp_path / "workshop"
    (case / "curves" / "volts").mkdir(parents=True)
    (case / "curves" / "force").mkdir()
    shutil.copy(INSTRUMENT / WORKSHOP_VOLTS, case / "curves" / "volts")
    shutil.copy(INSTRUMENT / WORKSHOP_FORCE, case / "curves" / "force")
    _case(
        case,
        "geometry = { half_angle_deg = 30.0 }\nspring_constant_N_per_m = 20.0\n"
        'calibration = { "curves/volts/*" = { spring_constant_N_per_m = 0.5, '
        "sensitivity_nm_per_V = 10.0 } }\n",
    )
    result, out = _run(case, tmp_path / "out")
    rows = {r["group"]: r for r in _rows(out)}
    assert not rows["volts"]["error"] and not rows["force"]["error"], rows
    for group, name, k, s in (
        ("volts", WORKSHOP_VOLTS, 0.5, 10.0),
        ("force", WORKSHOP_FORCE, 20.0, None),
    ):
        curve = read_curve(INSTRUMENT / name, spring_constant_N_per_m=k, sensitivity_nm_per_V=s)
        expected = fit_indentation(curve, "sneddon_cone", {"half_angle_deg": 30.0}).E_kPa
        assert float(rows[group]["E_kPa"]) == pytest.approx(expected, rel=1e-5)  # CSV: 6 digits
        assert float(rows[group]["spring_constant_N_per_m"]) == pytest.approx(k, rel=1e-6)


def test_poor_fits_stay_out_of_statistics_and_material_files(tmp_path):
    # item 3: a group of poor fits made a material file; one curve showed SD 0.000
    case = tmp_path / "poor"
    for i, e in enumerate((4.0, 6.0)):
        _curve_file(case / "curves" / "mixed", f"g{i}.csv", e, seed=i)
    # paraboloid curves fitted with a cone: E(delta) changes with depth -> rated poor
    sphere = {"model": "hertz_paraboloid", "geometry": {"radius_um": 5.0}}
    _curve_file(case / "curves" / "mixed", "p0.csv", 5.0, seed=7, **sphere)
    _curve_file(case / "curves" / "bad", "p1.csv", 5.0, seed=8, **sphere)
    _curve_file(case / "curves" / "single", "s.csv", 3.0, seed=9)
    _case(case, "")
    result, out = _run(case, tmp_path / "out")
    rows = _rows(out)
    quality = {Path(r["file"]).stem: r["quality"] for r in rows}
    assert quality == {"g0": "good", "g1": "good", "p0": "poor", "p1": "poor", "s": "good"}
    good_e = [float(r["E_kPa"]) for r in rows if Path(r["file"]).stem in ("g0", "g1")]
    mixed = read_material(out / "material_mixed.toml")
    assert mixed.E_kPa == pytest.approx(np.mean(good_e), rel=1e-5)  # p0 left out; CSV 6 digits
    assert not (out / "material_bad.toml").exists()
    report = (out / "report.md").read_text()
    assert "| bad | 0 | 1 | - |" in report
    assert "| mixed | 2 | 1 |" in report
    assert "| single | 1 | 0 | " in report and "+- n/a |" in report
    # include_poor = true keeps them
    _case(case, "include_poor = true\n")
    _, out = _run(case, tmp_path / "out2")
    all_e = [float(r["E_kPa"]) for r in _rows(out) if r["group"] == "mixed"]
    assert read_material(out / "material_mixed.toml").E_kPa == pytest.approx(
        np.mean(all_e), rel=1e-5
    )
    assert (out / "material_bad.toml").exists()


def test_nanite_fits_of_curves_without_contact_make_no_material_file(tmp_path):
    # item 3: in nanite mode a group of no-contact curves (R^2 0.2-0.3) made a material file
    case = tmp_path / "qi"
    (case / "curves" / "map").mkdir(parents=True)
    shutil.copy(
        INSTRUMENT / "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data", case / "curves" / "map"
    )
    _case(case, 'geometry = { half_angle_deg = 30.0 }\nanalysis = "nanite"\n')
    _, out = _run(case, tmp_path / "out")
    rows = _rows(out)
    assert len(rows) == 4 and {r["quality"] for r in rows} == {"poor"}
    assert all(float(r["r_squared"]) < 0.5 for r in rows)
    assert not (out / "material_map.toml").exists()
    assert "| map | 0 | 4 | - |" in (out / "report.md").read_text()


def test_fits_csv_names_model_tip_calibration_and_contact_from_start(tmp_path):
    # item 4: fits.csv lacked model, tip, nu, k, contact points, depth, analysis; the contact
    # point was an absolute instrument height
    case = tmp_path / "columns"
    path = _curve_file(case / "curves" / "zp", "a.csv", 5.0, k_nN_per_um=70.0)
    _case(case, "geometry = { half_angle_deg = 10.0 }\nnu = 0.45\nmax_indentation_um = 1.5\n")
    fit = fit_indentation(read_curve(path), nu=0.45, fit_range=FitRange(1.5))
    _, out = _run(case, tmp_path / "out")
    [row] = _rows(out)
    assert row["model"] == "sneddon_cone" and row["tip"] == "half_angle_deg=10"
    assert float(row["nu"]) == 0.45 and float(row["spring_constant_N_per_m"]) == 0.07
    assert row["analysis"] == "default" and row["fit_range"] == "to 1.5 um past contact"
    # the curve's contact is 3 um of piezo travel after its first point
    assert float(row["contact_from_start_um"]) == pytest.approx(3.0, abs=0.03)
    # the window ends 1.5 um past the deviation estimate of contact, which lags the fitted one
    assert float(row["max_indentation_um"]) == pytest.approx(fit.max_indentation_um, rel=1e-5)
    assert int(row["n_contact_points"]) == fit.n_contact_points > 100
    assert row["rating"].startswith("good (R^2")
    report = (out / "report.md").read_text()
    assert "contact_from_start_um" in report and "weights the residuals" in report


def _paraboloid_creep(tmp_path: Path, truth: RelaxationProny, radius: float, nu: float) -> Path:
    # Lee-Radok for a paraboloid under a force step: delta^(3/2) = 3 (1 - nu) F0 J / (8 sqrt R)
    t = np.linspace(0.0, 6.0, 1201)
    j = creep_from_relaxation(truth)(t)
    delta = (3.0 * (1.0 - nu) * 5.0 * j / (8.0 * math.sqrt(radius))) ** (2.0 / 3.0)
    path = tmp_path / "creep.csv"
    with path.open("w") as fh:
        fh.write("time_s,force_nN,indentation_um\n")
        np.savetxt(fh, np.column_stack([t, np.full(t.size, 5.0), delta]), delimiter=",")
    return path


def test_creep_fit_uses_the_curves_tip(tmp_path):
    # item 8: the creep fit took a 10 deg cone whatever the tip (a paraboloid's record read
    # as a cone); now it takes the case's model and geometry
    truth = RelaxationProny(2.0, (0.3, 0.2), (0.2, 1.5))
    nu = 0.5
    case = tmp_path / "creep_case"
    _curve_file(
        case / "curves" / "zp", "a.csv", 6.0, model="hertz_paraboloid", geometry={"radius_um": 5.0}
    )
    (case / "creep").mkdir()
    shutil.copy(_paraboloid_creep(tmp_path, truth, 5.0, nu), case / "creep" / "zp.csv")
    _case(
        case,
        'model = "hertz_paraboloid"\ngeometry = { radius_um = 5.0 }\n'
        'creep = { zp = "creep/zp.csv" }\n',
    )
    result, out = _run(case, tmp_path / "out")
    material = read_material(out / "material_zp.toml")
    E0 = 2.0 * (1.0 + nu) * truth.G0_kPa
    assert material.E_kPa == pytest.approx(E0, rel=0.01)
    report = (out / "report.md").read_text()
    E_inf = 2.0 * (1.0 + nu) * truth.G_inf_kPa
    assert f"| zp | {material.E_kPa:.4g} | {E_inf:.4g} |" in report  # E_inf reported
    assert "(creep_zp.png)" in report and (out / "creep_zp.png").is_file()  # linked
    # a cone half angle with a paraboloid model is refused, naming the input
    _case(
        case,
        'model = "hertz_paraboloid"\ncreep = { zp = "creep/zp.csv" }\n'
        "half_angle_deg_creep = 30.0\n",
    )
    result, _ = _run(case, tmp_path / "out2")
    assert result.status == "ERROR" and "half_angle_deg_creep" in result.reason


def test_creep_fit_takes_the_cone_half_angle_of_the_curves(tmp_path):
    # item 8: a 30 deg cone's record read with the old default of 10 deg gave 3.3x E0
    truth = RelaxationProny(2.0, (0.3, 0.2), (0.2, 1.5))
    t = np.linspace(0.0, 6.0, 1201)
    j = creep_from_relaxation(truth)(t)
    delta = np.sqrt(math.pi * 0.5 * 5.0 * j / (4.0 * math.tan(math.radians(30.0))))
    case = tmp_path / "cone30"
    _curve_file(case / "curves" / "zp", "a.csv", 6.0, geometry={"half_angle_deg": 30.0})
    write_creep(case / "zp_creep.csv", t, np.full(t.size, 5.0), delta, 0.0, 1e6)
    _case(case, 'geometry = { half_angle_deg = 30.0 }\ncreep = { zp = "zp_creep.csv" }\n')
    _, out = _run(case, tmp_path / "out")
    E0 = 3.0 * truth.G0_kPa
    assert read_material(out / "material_zp.toml").E_kPa == pytest.approx(E0, rel=0.01)


def test_undetermined_prony_terms_are_flagged_in_every_material_file(tmp_path):
    # item 8: a term longer than the record was flagged in the report only
    truth = RelaxationProny(2.0, (0.3, 0.3), (0.2, 40.0))  # 40 s in a 6 s record
    t = np.linspace(0.0, 6.0, 1201)
    j = creep_from_relaxation(truth)(t)
    delta = np.sqrt(math.pi * 0.5 * 5.0 * j / (4.0 * math.tan(math.radians(10.0))))
    fit = fit_creep_tip(CreepData(t, np.full(t.size, 5.0), delta), "sneddon_cone")
    assert fit.undetermined, fit.creep
    case = tmp_path / "flag"
    _curve_file(case / "curves" / "zp", "a.csv", 6.0)
    write_creep(case / "zp_creep.csv", t, np.full(t.size, 5.0), delta, 0.0, 1e6)
    _case(case, 'creep = { zp = "zp_creep.csv" }\n')
    _, out = _run(case, tmp_path / "out")
    for name in ("material_zp.toml", "material_zp_ansys.inp", "material_zp_febio.xml"):
        assert "not determined" in (out / name).read_text(), name
    assert "not determined" in read_material(out / "material_zp.toml").source
