"""Constants calibrated once, a spindle offset predicted from them (``nmsd_calibration`` ->
``nmsd_constants.toml`` -> ``nmsd_spindle_offset``'s ``constants_file``).

The quick spindle case calibrates on Table II with the quick Table II case's settings, so the
constants it finds are the ones that case writes: read from the file they must give the same
offset (to round-off), without the calibration.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from nmsd.constants_file import constants_toml, read_constants
from nmsd.parameters import NmsdParameters
from oocyte_fe.errors import InputError
from oocyte_fe.runner import run_case
from tests.case_copies import edited_case, refused_message, set_inputs

OFFSET = ("offset_x_um", "offset_y_um", "spindle_displacement_um", "loss_model_pct")


def test_the_file_gives_back_every_constant_exactly(tmp_path: Path) -> None:
    params = NmsdParameters(k1=0.1 / 3, k2=837.5, dl_c=0.8, d0=0.97, d1=1.25, node_mass=3.5e-9)
    path = tmp_path / "c.toml"
    path.write_text(constants_toml(params, 115.625, 17, "table.csv", 6.6))
    back = read_constants(path)
    assert back.params == NmsdParameters(**{**vars(params), "source": back.params.source})
    assert (back.cell_diameter_um, back.spacings_across, back.data) == (115.625, 17, "table.csv")
    assert "k1_nN = 0.03333333333333333" in path.read_text()  # full precision


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("[nmsd]\nk2_nN = 1.0\n", "nmsd.k1_nN"),
        ("[lattice]\ncell_diameter_um = 100.0\nspacings_across = 17\n", "[nmsd]"),
        (
            "[nmsd]\nk1_nN = 1.0\nk2_nN = 100.0\ndl_c = 0.8\nd0_nN_s_per_um = 1.0\n"
            "d1_nN_s_per_um2 = 1.0\nnode_mass_nN_s2_per_um = 1e-9\nk3 = 1\n",
            "nmsd.k3",
        ),
        (
            "[nmsd]\nk1_nN = 1.0\nk2_nN = 100.0\ndl_c = 0.8\nd0_nN_s_per_um = 1.0\n"
            "d1_nN_s_per_um2 = 1.0\nnode_mass_nN_s2_per_um = 1e-9\n[lattice]\n"
            "cell_diameter_um = 100.0\nspacings_across = 2.5\n",
            "lattice.spacings_across",
        ),
        (
            "[nmsd]\nk1_nN = -1.0\nk2_nN = 100.0\ndl_c = 0.8\nd0_nN_s_per_um = 1.0\n"
            "d1_nN_s_per_um2 = 1.0\nnode_mass_nN_s2_per_um = 1e-9\n",
            "k1",
        ),
    ],
)
def test_a_bad_file_names_itself_and_the_field(tmp_path: Path, text: str, field: str) -> None:
    path = tmp_path / "c.toml"
    path.write_text(text)
    with pytest.raises(InputError) as err:
        read_constants(path)
    assert err.value.field == field and str(path) in str(err.value)


@pytest.mark.slow
def test_the_spindle_offset_from_the_file_is_the_calibrated_one(tmp_path: Path, quick_run):
    constants = quick_run("nmsd_calibration_tableII") / "nmsd_constants.toml"  # shared run
    calibrated = run_case(edited_case(tmp_path / "a", "nmsd_spindle_offset"), tmp_path / "o1", True)
    folder = edited_case(tmp_path / "b", "nmsd_spindle_offset")
    shutil.copy(constants, folder / "nmsd_constants.toml")
    from_file = run_case(
        set_inputs(folder, constants_file="nmsd_constants.toml"), tmp_path / "o2", True
    )
    for key in OFFSET:
        assert from_file.metrics[key] == pytest.approx(calibrated.metrics[key], rel=1e-9), key
    report = (from_file.folder / "report.md").read_text()
    assert "Constants used (constants read from" in report and "not fitted" in report
    log = (from_file.folder / "log.txt").read_text()
    assert (
        "calibrating nmsd" not in log
        and "calibrating nmsd" in (calibrated.folder / "log.txt").read_text()
    )
    rmse = json.loads((quick_run("nmsd_calibration_tableII") / "metrics.json").read_text())
    assert read_constants(constants).rmse_uN == pytest.approx(rmse["metrics"]["rmse_uN"], rel=1e-12)


@pytest.mark.parametrize(
    ("inputs", "says"),
    [
        ({"spacings_across": 15}, "inputs.spacings_across: expected 17, as in constants_file"),
        ({"cell_diameter_um": 110.0}, "inputs.cell_diameter_um: expected 115.625, as in"),
        ({"damping": "link"}, "inputs.damping: expected 'nodal', as in constants_file"),
    ],
)
def test_constants_of_another_lattice_are_refused(tmp_path: Path, inputs: dict, says: str):
    folder = edited_case(tmp_path, "nmsd_spindle_offset", constants_file="c.toml")
    params = NmsdParameters(k1=0.27, k2=837.5, dl_c=0.8, d0=0.97, d1=1.25, node_mass=3.5e-9)
    (folder / "c.toml").write_text(constants_toml(params, 115.625, 17, "t.csv", 6.6))
    assert says in refused_message(set_inputs(folder, **inputs))
