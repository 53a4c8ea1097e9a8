"""The user route: case kind ``afm_fit_files`` on the shipped files and on a copied case."""

from __future__ import annotations

import csv
import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from afm.batch import curve_files
from afm.fit_files import CreepRecord, fit_files, read_known_moduli
from afm.material_file import read_material
from oocyte_fe.errors import InputError
from oocyte_fe.runner.run import plan, run_cases

CASE = Path(__file__).parents[1] / "cases" / "afm_fit_files"


def _rows(folder: Path) -> list[dict[str, str]]:
    with (folder / "fits.csv").open() as fh:
        return list(csv.DictReader(fh))


def test_shipped_case_fits_every_curve_and_skips_the_bad_one(tmp_path):
    [result] = run_cases(plan([CASE], quick=True), tmp_path, quick=True)
    assert result.status == "PASS", result.reason
    out = tmp_path / "afm_fit_files"
    rows = _rows(out)
    assert len(rows) == 13
    bad = [r for r in rows if r["error"]]
    assert [r["file"] for r in bad] == ["curves/zp/zp_bad_no_contact.csv"]
    assert "reaches contact" in bad[0]["error"] and bad[0]["quality"] == "error"
    known = {}
    with (CASE / "known_moduli.csv").open() as fh:
        for row in csv.DictReader(line for line in fh if not line.startswith("#")):
            known[row["file"]] = float(row["E_kPa"])
    for row in rows:
        if row["file"] in known:
            assert float(row["E_kPa"]) == pytest.approx(known[row["file"]], rel=0.05)
            assert (out / row["plot"]).is_file()
            assert {"height_channel", "map_x_um", "map_y_um", "curve_index"} <= set(row)
    assert {r["group"] for r in rows} == {"zp", "cytoplasm"}
    zp = read_material(out / "material_zp.toml")
    assert zp.g and zp.E_kPa == pytest.approx(7.01, rel=0.03)  # from the creep record
    cyto = read_material(out / "material_cytoplasm.toml")
    fitted = [float(r["E_kPa"]) for r in rows if r["group"] == "cytoplasm"]
    assert cyto.E_kPa == pytest.approx(sum(fitted) / len(fitted), rel=1e-5) and not cyto.g
    ET.parse(out / "material_zp_febio.xml")
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["metrics"]["n_failed"] == 1 and metrics["metrics"]["n_fitted"] == 12
    report = (out / "report.md").read_text()
    assert "(curve_plots/zp_01.png)" in report and "zp_bad_no_contact.csv" in report


def _copy(tmp_path: Path, edit: dict[str, str]) -> Path:
    case = tmp_path / "mine"
    shutil.copytree(CASE, case)
    text = (case / "case.toml").read_text()
    for old, new in edit.items():
        assert old in text
        text = text.replace(old, new)
    (case / "case.toml").write_text(text)
    return case


def test_glob_and_group_patterns(tmp_path):
    case = _copy(
        tmp_path,
        {
            'curves = "curves"': 'curves = "curves/*/*_0[1-3].csv"\n'
            'groups = { soft = "curves/cytoplasm/*", stiff = "curves/zp/*" }',
            'creep = { zp = "creep/zp_creep.csv" }\n': "",
            "[tolerances.n_failed]\nmax = 1": "[tolerances.n_failed]\nmax = 0",
            "[tolerances.n_fitted]\nmin = 12": "[tolerances.n_fitted]\nmin = 6",
        },
    )
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    out = tmp_path / "out" / "mine"
    rows = _rows(out)
    assert len(rows) == 6 and {r["group"] for r in rows} == {"soft", "stiff"}
    assert (out / "material_soft.toml").is_file() and (out / "material_stiff.toml").is_file()
    # the known-moduli check lists 12 files but only 6 were fitted: it must fail, not pass
    assert result.status == "FAIL"


@pytest.mark.parametrize("pattern", ["../afm_zp_cytoplasm", "/etc", "nothing_here/*.csv"])
def test_curves_outside_the_case_folder_or_missing_are_refused(tmp_path, pattern):
    case = _copy(tmp_path, {'curves = "curves"': f'curves = "{pattern}"'})
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "ERROR"
    assert "inputs.curves" in result.reason


INSTRUMENT = Path(__file__).parent / "data" / "instrument"


def test_instrument_files_and_force_map_through_the_user_route(tmp_path):
    # real files (afmformats' test data, MIT): a JPK curve and a JPK QI map of 4 curves
    case = tmp_path / "jpk"
    (case / "curves" / "single").mkdir(parents=True)
    (case / "curves" / "map").mkdir()
    shutil.copy(INSTRUMENT / "fmt-jpk-fd_spot3-0192.jpk-force", case / "curves" / "single")
    shutil.copy(
        INSTRUMENT / "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data", case / "curves" / "map"
    )
    (case / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "real JPK files"\n[inputs]\ncurves = "curves"\n'
        "geometry = { half_angle_deg = 30.0 }\n"
    )
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    out = tmp_path / "out" / "jpk"
    rows = _rows(out)
    single = [r for r in rows if r["group"] == "single"]
    assert len(single) == 1 and single[0]["height_channel"]
    # JPK data processing gives 348.6 kPa for this curve (cone 30 deg, nu 0.5)
    assert float(single[0]["E_kPa"]) == pytest.approx(348.6, rel=0.03)
    maps = [r for r in rows if r["group"] == "map"]
    assert len(maps) == 4 and all(r["map_x_um"] and r["curve_index"] for r in maps)
    assert result.status in {"PASS", "FAIL"}, result.reason
    assert (out / "modulus_map_fmt-jpk-fd_2020.02.07-16.29.05.036.png").is_file()


def test_height_channel_override_reaches_the_table(tmp_path):
    case = tmp_path / "piezo"
    (case / "curves").mkdir(parents=True)
    shutil.copy(INSTRUMENT / "fmt-jpk-fd_spot3-0192.jpk-force", case / "curves")
    (case / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "override"\n[inputs]\ncurves = "curves"\n'
        'geometry = { half_angle_deg = 30.0 }\nheight_channel = "height (piezo)"\n'
    )
    run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    [row] = _rows(tmp_path / "out" / "piezo")
    assert row["height_channel"] == "height (piezo)"
    assert float(row["E_kPa"]) > 3000  # the piezo channel's wrong 10 245 kPa (issue 17 item 1)
    # peer: the library's fit of the same file read through the piezo channel (the case's
    # defaults: cone 30 deg, nu 0.5), to the CSV's 6 digits (1e-5)
    from afm.curve_io import read_curve
    from afm.fit import fit_indentation

    path = case / "curves" / "fmt-jpk-fd_spot3-0192.jpk-force"
    piezo = read_curve(path, height_channel="height (piezo)")
    expected = fit_indentation(piezo, "sneddon_cone", {"half_angle_deg": 30.0}, 0.5).E_kPa
    assert float(row["E_kPa"]) == pytest.approx(expected, rel=1e-5)


def test_group_names_cannot_leave_the_result_folder(tmp_path):
    case = _copy(
        tmp_path,
        {
            'curves = "curves"': 'curves = "curves"\ngroups = { "../../evil" = "curves/zp/*" }',
            'creep = { zp = "creep/zp_creep.csv" }\n': "",
        },
    )
    run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    out = tmp_path / "out" / "mine"
    assert (out / "material_______evil.toml").is_file()
    assert not list(tmp_path.glob("**/evil*"))
    assert read_material(out / "material_______evil.toml").name == "../../evil"


def test_creep_file_for_a_group_without_curves_is_refused(tmp_path):
    case = _copy(
        tmp_path, {'creep = { zp = "creep/zp_creep.csv" }': 'creep = { ZP = "creep/zp_creep.csv" }'}
    )
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "ERROR" and "inputs.creep.ZP" in result.reason
    assert "cytoplasm, zp" in result.reason


def test_nanite_analysis_is_a_choice_of_the_user_route(tmp_path):
    # analysis = "nanite" fits with afm.nanite_pipeline.fit_nanite_default: the JPK curve's E
    # is that function's, and the QI map's 4 noisy curves (no contact for the default
    # analysis) get nanite's moduli
    from afm.curve_io import read_curves
    from afm.nanite_pipeline import fit_nanite_default

    single = INSTRUMENT / "fmt-jpk-fd_spot3-0192.jpk-force"
    qi = INSTRUMENT / "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data"
    case = tmp_path / "nanite"
    (case / "curves").mkdir(parents=True)
    shutil.copy(single, case / "curves")
    shutil.copy(qi, case / "curves")
    inputs = 'curves = "curves"\ngeometry = { half_angle_deg = 30.0 }\nanalysis = "nanite"\n'
    (case / "case.toml").write_text(
        f'kind = "afm_fit_files"\ndescription = "nanite route"\n[inputs]\n{inputs}'
    )
    run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    rows = _rows(tmp_path / "out" / "nanite")
    assert len(rows) == 5 and all(r["E_kPa"] and not r["error"] for r in rows)
    assert {r["contact_method"] for r in rows} == {"nanite default"}
    [row] = [r for r in rows if r["file"].endswith(".jpk-force")]
    [curve] = read_curves(single)
    expected = fit_nanite_default(curve, "sneddon_cone", {"half_angle_deg": 30.0}).E_kPa
    assert float(row["E_kPa"]) == pytest.approx(expected, rel=1e-5)  # CSV: 6 digits
    # nanite's analysis fits the whole approach with x0 free: a fit range or the deviation
    # contact with it is refused
    for extra in ("max_force_fraction = 0.5", 'contact_method = "deviation"'):
        (case / "case.toml").write_text(
            f'kind = "afm_fit_files"\ndescription = "x"\n[inputs]\n{inputs}{extra}\n'
        )
        [result] = run_cases(plan([case], quick=True), tmp_path / "out2", quick=True)
        assert result.status == "ERROR" and "inputs.analysis" in result.reason


def test_fit_files_groups_and_materials_without_the_runner():
    # the library function behind the kind: shipped files, groups by subfolder, the ZP's
    # material from its creep record, the cytoplasm's elastic with its mean E
    files = curve_files(CASE / "curves")
    known = read_known_moduli(CASE / "known_moduli.csv")
    cone = {"half_angle_deg": 10.0}
    creep = {"zp": CreepRecord(CASE / "creep" / "zp_creep.csv", "sneddon_cone", cone)}
    result = fit_files(files, "sneddon_cone", cone, 0.5, CASE, creep=creep, known_moduli=known)
    assert result.summary == "done: 12 fitted, 0 poor, 1 refused"
    assert list(result.stats) == ["cytoplasm", "zp"] and result.stats["zp"].n == 6
    cyto, zp = result.materials
    assert cyto.creep is None and cyto.material.E_kPa == result.stats["cytoplasm"].mean_kPa
    assert zp.creep is not None and zp.material.g and zp.material.E_kPa == zp.creep.E0_kPa
    assert result.n_known == 12 and result.max_known_error_pct < 5
    assert result.known_within(5.0) and not result.known_within(1e-6)
    # a creep record of a group no curve belongs to names where it was given
    record = CreepRecord(CASE / "creep" / "zp_creep.csv", file="case.toml", field="creep.ZP")
    with pytest.raises(InputError, match="creep.ZP: .*one of cytoplasm, zp"):
        fit_files(files, "sneddon_cone", cone, 0.5, CASE, creep={"ZP": record})
    soft = fit_files(files, "sneddon_cone", cone, 0.5, CASE, groups={"soft": "curves/cyto*/*"})
    assert list(soft.stats) == ["soft", "zp"] and soft.known_errors is None


def test_new_case_writes_an_example_curve_that_fits_to_its_modulus(tmp_path):
    """`oocyte-fe new afm_fit_files` writes curves/ with one synthetic approach (10 deg cone
    into 1.55 kPa, cantilever deflection taken off the travel) and sets curves = "curves":
    the case runs as written and fits E = 1.55 kPa (within 0.5 %)."""
    from oocyte_fe.runner.registry import get_kind
    from oocyte_fe.runner.scaffold import new_case

    folder = tmp_path / "mine"
    written = new_case(get_kind("afm_fit_files"), folder)
    assert folder / "curves" / "example_cone_1.55kPa.csv" in written
    [result] = run_cases(plan([folder]), tmp_path / "out")
    assert result.status == "PASS", result.reason
    metrics = json.loads((tmp_path / "out" / "mine" / "metrics.json").read_text())["metrics"]
    assert metrics["n_fitted"] == 1
    with (tmp_path / "out" / "mine" / "fits.csv").open() as fh:
        [row] = list(csv.DictReader(fh))
    assert float(row["E_kPa"]) == pytest.approx(1.55, rel=5e-3)
