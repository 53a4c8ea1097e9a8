"""Inputs of the NMSD kinds that ``validate`` once let through (outside tester, items 2, 10,
11, 16, 17, 20, 22).

Each passed ``validate`` and then either ran a silently wrong number (Table II points beyond
the press's travel fitted to its end force, an approach done in one step) or failed ``run``
with a message naming no input. Now each is one line naming the file, the field and what was
expected, and the value just inside each bound is accepted: every rule from both sides.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest
from typer.testing import CliRunner

from nmsd.calibration import calibrate
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters
from nmsd.press import press_setup
from nmsd.spindle import predict_spindle_offset
from nmsd.tableII import read_force_displacement
from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from tests.case_copies import CASES, edited_case, refused_message

TABLE = "nmsd_force_displacement_tableII.csv"
APPROACH_UM = 33.2203  # the default approach: mouth clear of the lattice to the spindle


def _refused(folder: Path) -> str:
    return refused_message(folder)


def _with_rows(folder: Path, *rows: str) -> Path:
    """``folder``'s Table II with ``rows`` appended."""
    table = folder / TABLE
    table.write_text(table.read_text().rstrip("\n") + "\n" + "\n".join(rows) + "\n")
    return folder


def _edited_rows(folder: Path, edit: Callable[[list[str]], None]) -> Path:
    table = folder / TABLE
    lines = table.read_text().splitlines()
    edit(lines)
    table.write_text("\n".join(lines) + "\n")
    return folder


# --- item 2: the press reaches every Table II point it is fitted to ---------------------------

PRESS_REFUSED = [
    (
        "nmsd_calibration_tableII",
        {"travel_um": 62.3, "snapshot_um": [10.0, 20.0]},
        "inputs.travel_um: expected travel_um >= the largest displacement_um of data (the press "
        "must reach every point it is fitted to) = 62.375, got 62.3",
    ),
    (
        "nmsd_spindle_offset",
        {"travel_um": 62.3},
        "inputs.travel_um: expected travel_um >= the largest displacement_um of data",
    ),
]
PRESS_KEPT = [
    ("nmsd_calibration_tableII", {"travel_um": 62.375, "snapshot_um": [10.0, 20.0]}),
    ("nmsd_spindle_offset", {"travel_um": 62.375}),
]


@pytest.mark.parametrize(("case", "inputs", "message"), PRESS_REFUSED)
def test_travel_shorter_than_the_data_is_refused(
    tmp_path: Path, case: str, inputs: dict, message: str
) -> None:
    assert message in _refused(edited_case(tmp_path, case, **inputs))


@pytest.mark.parametrize(("case", "inputs"), PRESS_KEPT)
def test_travel_reaching_the_data_is_accepted(tmp_path: Path, case: str, inputs: dict) -> None:
    load_case(edited_case(tmp_path, case, **inputs))


def test_a_table_beyond_the_cell_names_the_data(tmp_path: Path) -> None:
    folder = _with_rows(edited_case(tmp_path, "nmsd_calibration_tableII"), "115.625,60.0,60.0")
    assert (
        "inputs.data: expected displacement_um below cell_diameter_um - gap_um = 115.625 um in "
        "every row (a press cannot go through the cell), got 115.625"
    ) in _refused(folder)


def test_a_table_inside_the_travel_is_accepted(tmp_path: Path) -> None:
    folder = _with_rows(edited_case(tmp_path, "nmsd_calibration_tableII"), "65.0,60.0,60.0")
    load_case(folder)
    beyond = _with_rows(edited_case(tmp_path / "b", "nmsd_calibration_tableII"), "65.1,60,60")
    assert "= 65.1, got 65.0" in _refused(beyond)  # past the travel: the travel is named


def test_validate_exits_2_on_a_short_travel(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "nmsd_spindle_offset", travel_um=30.0)
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    assert "inputs.travel_um: expected travel_um >= the largest displacement_um" in result.output
    assert "Traceback" not in result.output


def test_calibrate_refuses_points_beyond_the_travel() -> None:
    data = read_force_displacement(CASES / "nmsd_calibration_tableII" / TABLE)
    setup = press_setup(circular_lattice(115.625, 17), travel_um=62.0, n_steps=4)
    with pytest.raises(InputError, match=r"displacements within the press travel \(62 um\)"):
        calibrate(setup, data, "linear_msd", n_starts=1, max_evaluations=4)


# --- item 17: the spindle approach's step and the PID's resolution ---------------------------


def test_an_approach_step_longer_than_the_approach_is_refused(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "nmsd_spindle_offset", approach_step_um=33.23)
    assert (
        "inputs.approach_step_um: expected approach_step_um <= the approach's travel (mouth "
        "clear of the lattice to spindle_initial_um) = 33.2203, got 33.23"
    ) in _refused(folder)
    load_case(edited_case(tmp_path / "kept", "nmsd_spindle_offset", approach_step_um=33.22))


def test_predict_spindle_offset_refuses_a_step_beyond_the_travel() -> None:
    lattice = circular_lattice(115.625, 17)
    with pytest.raises(InputError, match="step_um"):
        predict_spindle_offset(lattice, NmsdParameters(), step_um=APPROACH_UM + 0.01)


def test_a_resolution_coarser_than_the_bore_is_refused(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "nmsd_spindle_offset", resolution_um=10.0)
    assert (
        "inputs.resolution_um: expected resolution_um < removal_pipette_um / 2 (a coarser step "
        "can leave the spindle outside the bore) = 10, got 10.0"
    ) in _refused(folder)
    load_case(edited_case(tmp_path / "kept", "nmsd_spindle_offset", resolution_um=9.99))


# --- items 10, 22: enucleation_loop ----------------------------------------------------------


def test_enucleation_table_is_read_at_validation(tmp_path: Path) -> None:
    def bad_cell(lines: list[str]) -> None:
        lines[8] = lines[8].split(",")[0] + ",x," + lines[8].split(",")[2]

    def swapped(lines: list[str]) -> None:
        lines[6], lines[7] = lines[7], lines[6]

    folder = _edited_rows(edited_case(tmp_path / "a", "enucleation_loop"), bad_cell)
    message = _refused(folder)
    assert message.endswith(
        f"{TABLE} (from case.toml: inputs.data): force_experiment_uN: expected numbers in every "
        "row (line 9), got 'x'"
    ), message
    folder = _edited_rows(edited_case(tmp_path / "b", "enucleation_loop"), swapped)
    assert (
        "displacement_um: expected non-negative, strictly increasing, at most 1e6 um (line 8 "
        "is not above line 7)"
    ) in _refused(folder)


def test_enucleation_table_within_the_press(tmp_path: Path) -> None:
    folder = _with_rows(edited_case(tmp_path, "enucleation_loop"), "65.5,60.0,60.0")
    assert (
        "inputs.data: expected displacement_um at most the calibration press's travel 65 um, "
        "got 65.5"
    ) in _refused(folder)
    load_case(_with_rows(edited_case(tmp_path / "kept", "enucleation_loop"), "65.0,60.0,60.0"))


ENUCLEATION = [
    (
        "click_error_um",
        10.0,
        9.99,
        "inputs.click_error_um: expected click_error_um < the spindle's length in the video (a "
        "first box that still overlaps the spindle) = 10, got 10.0",
    ),
    (
        "param_spread",
        2.31,
        2.3,
        "inputs.param_spread: expected a value less than or equal to 2.3, got 2.31",
    ),
    ("n_cells", 1001, 1000, "inputs.n_cells: expected a value less than or equal to 1000"),
]


@pytest.mark.parametrize(("field", "refused", "kept", "message"), ENUCLEATION)
def test_enucleation_bounds(
    tmp_path: Path, field: str, refused: float, kept: float, message: str
) -> None:
    assert message in _refused(edited_case(tmp_path / "a", "enucleation_loop", **{field: refused}))
    load_case(edited_case(tmp_path / "b", "enucleation_loop", **{field: kept}))


# --- items 11, 16, 20: nmsd_vs_fe ------------------------------------------------------------

FINEST = "cell_diameter_um / 1000 (at most ~1e6 elements or grid points) = 0.115625"
CROSSCHECK = [  # (inputs refused, inputs kept, message); --quick presses 62.5 um
    (
        {"hold_half_width_um": 57.8125},
        {"hold_half_width_um": 57.8},
        "inputs.hold_half_width_um: expected hold_half_width_um < cell_diameter_um / 2 = 57.8125",
    ),
    (
        {"grid_margin_um": 57.8125},
        {"grid_margin_um": 57.8},
        "inputs.grid_margin_um: expected grid_margin_um < cell_diameter_um / 2 (a grid inside the "
        "cell) = 57.8125",
    ),
    (
        {"arrow_advances_um": [20.0, 65.0]},  # a frame of the full press, past the quick one
        {"arrow_advances_um": [20.0, 62.5]},
        "inputs.arrow_advances_um: expected max(arrow_advances_um) <= travel_um = 62.5",
    ),
    (  # an advance between two output frames was left out of the arrow plots without a word
        {"arrow_advances_um": [20.0, 41.0]},
        {"arrow_advances_um": [20.0, 42.5]},
        "inputs.arrow_advances_um: expected advances on the FE's output frames (travel_um / 26 = "
        "2.5 um apart, fe_step_um rounded to fit the travel), got [41.0]",
    ),
    (
        {"fe_step_um": 62.6, "arrow_advances_um": [32.5]},
        {"fe_step_um": 62.5, "fe_max_step_um": 1.25, "arrow_advances_um": []},
        "inputs.fe_step_um: expected fe_step_um <= travel_um = 62.5, got 62.6",
    ),
    (
        {"fe_size_um": 0.115, "fe_refine_size_um": 0.115},
        {"fe_size_um": 0.116, "fe_refine_size_um": 0.116},
        f"inputs.fe_size_um: expected fe_size_um >= {FINEST}, got 0.115",
    ),
    (
        {"fe_refine_size_um": 0.115},
        {"fe_refine_size_um": 0.116},
        f"inputs.fe_refine_size_um: expected fe_refine_size_um >= {FINEST}, got 0.115",
    ),
    (
        {"grid_spacing_um": 0.115},
        {"grid_spacing_um": 0.116},
        f"inputs.grid_spacing_um: expected grid_spacing_um >= {FINEST}, got 0.115",
    ),
    (
        {"check_speed_um_s": 0.0},
        {"check_speed_um_s": 0.0, "calibrate_both_speeds": False},
        "inputs.check_speed_um_s: expected a second speed > 0 with calibrate_both_speeds = true "
        "(0 turns the check off), got 0.0",
    ),
    (
        {"nmsd_zona_stiffness_ratio": "AFM_relaxed"},
        {"nmsd_zona_stiffness_ratio": "afm_instantaneous"},
        "inputs.nmsd_zona_stiffness_ratio: expected a number > 0 or one of 'afm_relaxed', "
        "'afm_instantaneous', got 'AFM_relaxed'",
    ),
    (
        {"nmsd_zona_stiffness_ratio": 0.0},
        {"nmsd_zona_stiffness_ratio": 1e-6},
        "inputs.nmsd_zona_stiffness_ratio: expected a number > 0 or one of 'afm_relaxed', "
        "'afm_instantaneous', got 0.0",
    ),
]


@pytest.mark.parametrize(("refused", "kept", "message"), CROSSCHECK)
def test_crosscheck_relations(tmp_path: Path, refused: dict, kept: dict, message: str) -> None:
    assert message in _refused(edited_case(tmp_path / "a", "nmsd_vs_fe", **refused))
    load_case(edited_case(tmp_path / "b", "nmsd_vs_fe", **kept))
