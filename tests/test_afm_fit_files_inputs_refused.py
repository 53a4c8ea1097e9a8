"""``afm_fit_files`` inputs that ``validate`` said ok and ``run`` failed on later (or accepted
silently): each is now one line at ``validate`` naming the file, the input and what was
expected, and ``run`` reports the case as ERROR with the same line.

Each bad case is a copy of ``cases/afm_fit_files`` with one change (``tests.case_copies``).
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_fit_files_report import fit_range_text
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases
from tests.case_copies import edited_case

CASE = "afm_fit_files"
SUFFIXES = (
    ".csv, .h5, .ibw, .jpk-force, .jpk-force-map, .jpk-qi-data, .jpk-qi-series, .tab, .tsv, "
    ".txt, .zip"
)
CREEP = "{data}/creep/zp_creep.csv (from case.toml: inputs.creep)"
KNOWN = "{data}/known_moduli.csv (from case.toml: inputs.known_moduli)"
TOML = "{case}/case.toml"


def _edit_file(relative: str, edit: Callable[[list[str]], list[str]]) -> Callable[[Path], None]:
    """A mutation that rewrites the lines of one data file of the case copy."""

    def mutate(folder: Path) -> None:
        path = folder / relative
        lines = path.read_text().splitlines()
        path.write_text("".join(f"{line}\n" for line in edit(lines)))

    return mutate


def _cell(line: int, column: int, value: str) -> Callable[[list[str]], list[str]]:
    """Replace one comma-separated cell of ``line`` (1 = the first line of the file)."""

    def edit(lines: list[str]) -> list[str]:
        cells = lines[line - 1].split(",")
        cells[column] = value
        return [*lines[: line - 1], ",".join(cells), *lines[line:]]

    return edit


def _empty_curves(folder: Path, keep: str | None = None) -> None:
    shutil.rmtree(folder / "curves")
    (folder / "curves").mkdir()
    if keep is not None:
        (folder / "curves" / "readme.txt").write_text(keep)


# The shipped creep record: 3 comment lines, the header on line 4, data rows from line 5.
# The shipped known_moduli.csv: a comment on line 1, the header on line 2, rows 3-14
# (line 5: curves/zp/zp_03.csv).
REFUSED = {
    # 1. validate said ok, run failed later
    "curves_missing": (
        {"curves": "curvez"},
        None,
        TOML + ": inputs.curves: expected an existing folder of curve files (or a glob of them) "
        "in the case folder; not found, got 'curvez'",
    ),
    "curves_absolute": (
        {"curves": "/etc"},
        None,
        TOML + ": inputs.curves: expected a folder or glob relative to the case folder, without "
        "'..', got '/etc'",
    ),
    "curves_dotdot": (
        {"curves": "../afm_fit_files/curves"},
        None,
        TOML + ": inputs.curves: expected a folder or glob relative to the case folder, without "
        "'..', got '../afm_fit_files/curves'",
    ),
    "curves_empty_folder": (
        {},
        _empty_curves,
        TOML + f": inputs.curves: expected a folder holding curve files ({SUFFIXES}); it has "
        "none, got 'curves'",
    ),
    "curves_only_a_note": (
        {},
        lambda folder: _empty_curves(folder, keep="notes\n"),
        TOML + ": inputs.curves: expected curve files the reader can read; none of the 1 found "
        "can (first: curves/readme.txt: header: expected at least two columns (piezo and "
        "force), got 'notes')",
    ),
    "creep_empty": (
        {},
        _edit_file("creep/zp_creep.csv", lambda lines: []),
        CREEP + ": a header row and data rows (the file is empty)",
    ),
    "creep_nan": (
        {},
        _edit_file("creep/zp_creep.csv", _cell(11, 1, "nan")),
        CREEP + ": force_nN: expected finite numbers (data row 7 holds nan)",
    ),
    "creep_two_rows": (
        {},
        _edit_file("creep/zp_creep.csv", lambda lines: lines[:6]),
        CREEP + ": time_s: expected at least 10 samples, got 2",
    ),
    "known_moduli_other_header": (
        {},
        _edit_file("known_moduli.csv", lambda lines: [lines[0], "name,E", *lines[2:]]),
        KNOWN + ": header (line 2): expected columns 'file,E_kPa' (the curve file relative to "
        "the case folder, its modulus in kPa), got 'name, E'",
    ),
    "creep_group_unknown": (
        {"creep": {"zq": "creep/zp_creep.csv"}},
        None,
        TOML + ": inputs.creep.zq: expected a group of the curve files (one of cytoplasm, zp: "
        "their subfolders, '# group' metadata or inputs.groups)",
    ),
    "zona_thicker_than_cell_radius": (
        {
            "max_indentation_um": 1.0,
            "correction": {
                "type": "shelled_oocyte",
                "zona_thickness_um": 100.0,
                "cytoplasm_modulus_kPa": 1.0,
                "cell_radius_um": 50.0,
            },
        },
        None,
        TOML + ": inputs.correction.zona_thickness_um: expected a ZP thinner than the cell's "
        "radius (zona_thickness_um < cell_radius_um = 50 um), got 100.0",
    ),
    # 2. a bad tip geometry (the shipped creep line kept: no misleading creep-group message)
    "geometry_typo": (
        {"geometry": {"half_angle_dg": 10.0}},
        None,
        TOML + ": inputs.geometry.half_angle_dg: expected a geometry key of sneddon_cone: "
        "['half_angle_deg']",
    ),
    "geometry_angle_95": (
        {"geometry": {"half_angle_deg": 95.0}},
        None,
        TOML + ": inputs.geometry.half_angle_deg: expected a value in (0.001, 90) deg, got 95.0",
    ),
    "geometry_radius_on_cone": (
        {"geometry": {"radius_um": 5.0}},
        None,
        TOML + ": inputs.geometry.radius_um: expected a geometry key of sneddon_cone: "
        "['half_angle_deg']",
    ),
    # 3. accepted silently
    "groups_glob_matches_nothing": (
        {"groups": {"zp": "nothing/*.csv"}},
        None,
        TOML + ": inputs.groups.zp: expected a glob matching at least one curve file of "
        "inputs.curves (its path relative to the case folder, e.g. 'curves/zp/*.csv'; a file "
        "goes to the first pattern matching it), got 'nothing/*.csv'",
    ),
    "known_modulus_negative": (
        {},
        _edit_file("known_moduli.csv", _cell(5, 1, "-1.5")),
        KNOWN + ": E_kPa (line 5): expected a positive modulus in kPa, within [1e-06, 1e+09], "
        "got -1.5",
    ),
    "known_modulus_of_no_file": (
        {},
        _edit_file("known_moduli.csv", lambda lines: [*lines, "curves/zp/zp_99.csv,5.0"]),
        TOML + ": inputs.known_moduli: expected an existing curve file (path relative to the "
        "case folder) on every row (known_moduli.csv line 15 names a file that does not "
        "exist), got 'curves/zp/zp_99.csv'",
    ),
}


def _bad_case(tmp_path: Path, name: str) -> tuple[Path, str]:
    """The case copy of mutation ``name`` and the one line ``validate`` must print for it."""
    inputs, mutate, message = REFUSED[name]
    folder = edited_case(tmp_path, CASE, **inputs)
    if mutate is not None:
        mutate(folder)
    return folder, message.format(case=folder, data=folder.resolve())


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_validation_refuses_with_one_line_naming_file_and_field(tmp_path: Path, name: str) -> None:
    folder, message = _bad_case(tmp_path, name)
    with pytest.raises(InputError) as err:
        load_case(folder)
    assert str(err.value) == message


@pytest.mark.parametrize(
    "name", ["curves_dotdot", "creep_two_rows", "geometry_typo", "known_modulus_of_no_file"]
)
def test_validate_command_exits_2_with_that_line(tmp_path: Path, name: str) -> None:
    folder, message = _bad_case(tmp_path, name)
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [f"invalid {message}"]


def test_run_reports_the_case_as_error_with_the_same_line(tmp_path: Path) -> None:
    """The bad geometry with the shipped creep line: the run used to refuse every curve and
    FAIL with 'inputs.creep.zp: expected a group of the fitted curves (one of none)'."""
    folder, message = _bad_case(tmp_path, "geometry_angle_95")
    [result] = run_cases(plan([folder]), tmp_path / "results")
    assert (result.status, result.reason) == ("ERROR", f"invalid case: {message}")


def test_shipped_case_still_validates() -> None:
    case = load_case(Path(__file__).resolve().parents[1] / "cases" / CASE)
    assert case.kind.name == CASE


def test_both_fit_ranges_are_the_documented_window_whichever_ends_first(tmp_path: Path) -> None:
    """max_indentation_um with max_force_fraction is kept: afm.fit and docs/afm.md define the
    window as ending where the first of the two ends, and the report and fits.csv say so."""
    folder = edited_case(tmp_path, CASE, max_indentation_um=1.0, max_force_fraction=0.5)
    inputs = load_case(folder).inputs
    expected = "to 1 um past contact or to 0.5 of the peak force, whichever ends first"
    assert fit_range_text(inputs) == expected  # type: ignore[arg-type]
