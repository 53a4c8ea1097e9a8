"""FE experiment inputs an outside tester found refused without the value, or not at all
(its defects 10, 13 and 16), each now one line naming ``case.toml``, the field, what was
expected and what the file has:

1. a tool's ``type`` misspelt (``shpere``): the value and the closest type;
2. a straight pipette wider than the cell: the width it has;
3. a suction controller naming a tool that is not a holding pipette with a path: the name
   given and the holding pipettes there are;
4. an input written above the first ``[inputs...]`` header (a top-level key): where it goes;
5. a zona material on a cell with no ZP (``zona_thickness_um = 0``): it was ignored; and
   ``oocyte-fe new fe_experiment`` no longer writes one active (its default cell has no ZP).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.runner.casefile import load_case
from tests.case_copies import edited_case, refused_message, set_inputs

SPHERE = "fe_afm_sphere"
PIPETTE = "fe_aspiration_theret"


def _neck(tmp_path: Path, **inputs: object) -> Path:
    folder = tmp_path / "neck"
    result = CliRunner().invoke(app, ["new", "fe_experiment", str(folder), "--template", "neck"])
    assert result.exit_code == 0, result.output
    return set_inputs(folder, **inputs)


def test_a_misspelt_tool_type_names_the_value_and_the_closest_type(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, SPHERE, **{"tools.probe.type": "shpere"})
    message = refused_message(folder)
    assert message.endswith(
        "case.toml: inputs.tools.probe.type: expected a table with type = one of plate, "
        "sphere, cone, straight_pipette, necked_pipette, wedge_pipette, holding_pipette "
        "(did you mean 'sphere'?), got 'shpere'"
    ), message


def test_a_pipette_wider_than_the_cell_says_how_wide(tmp_path: Path) -> None:
    radius = tomllib.loads((Path("cases") / PIPETTE / "case.toml").read_text())["inputs"]
    cell_r = radius["cell"]["outer_diameter_um"] / 2
    folder = edited_case(tmp_path, PIPETTE, **{"tools.pipette.inner_radius_um": cell_r + 10})
    fillet = radius["tools"]["pipette"].get("mouth_fillet_um", 0.0)
    assert refused_message(folder).endswith(
        "inputs.tools.pipette.inner_radius_um: expected inner_radius_um + mouth_fillet_um "
        f"below the cell's radius {cell_r:g} um, got {cell_r + 10 + fillet!r}"
    )


def test_a_suction_controller_naming_no_holding_pipette(tmp_path: Path) -> None:
    folder = _neck(tmp_path, **{"tools.pipette.suction_control.tool": "holder"})
    assert refused_message(folder).endswith(
        "inputs.tools.pipette.suction_control.tool: expected the name of a holding pipette "
        "with displacement_um in tools ('cap'), got 'holder'"
    )


def test_a_suction_controller_naming_another_kind_of_tool(tmp_path: Path) -> None:
    folder = _neck(tmp_path, **{"tools.pipette.suction_control.tool": "pipette"})
    assert refused_message(folder).endswith(
        "in tools ('cap'); 'pipette' is a necked_pipette, got 'pipette'"
    )


def test_an_input_above_the_inputs_table_says_where_it_goes(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, SPHERE)
    text = (folder / "case.toml").read_text()
    text = text.replace("[inputs", 'kinematics = "small_strain"\n\n[inputs', 1)
    (folder / "case.toml").write_text(text)
    assert refused_message(folder).endswith(
        "case.toml: kinematics: expected no such key at the top level: 'kinematics' is an "
        "input, write it in the [inputs] table (inputs.kinematics: a bare key belongs to the "
        "table whose header is above it)"
    )


def test_an_unknown_top_level_key_that_is_no_input_keeps_the_plain_message(
    tmp_path: Path,
) -> None:
    folder = edited_case(tmp_path, SPHERE)
    text = (folder / "case.toml").read_text()
    (folder / "case.toml").write_text(text.replace("[inputs", "colour = 3\n\n[inputs", 1))
    assert refused_message(folder).endswith("case.toml: colour: expected no such key (unknown key)")


def test_a_zona_material_without_a_zona_is_refused(tmp_path: Path) -> None:
    zona = {"E_kPa": 7.0, "nu": 0.5}
    folder = edited_case(tmp_path, SPHERE, **{"cell.materials.zona": zona})
    assert refused_message(folder).endswith(
        "inputs.cell.zona_thickness_um: expected a ZP thickness > 0 with materials.zona (at 0 "
        "the cell is all cytoplasm and the zona material would be ignored; remove it for a "
        "homogeneous cell), got 0.0"
    )
    # just inside: a 1 um ZP takes it
    set_inputs(folder, **{"cell.zona_thickness_um": 1.0})
    assert load_case(folder).inputs.cell.materials.zona.E_kPa == pytest.approx(7.0)


def test_new_writes_the_optional_zona_file_as_a_comment(tmp_path: Path) -> None:
    folder = tmp_path / "mine"
    result = CliRunner().invoke(app, ["new", "fe_experiment", str(folder)])
    assert result.exit_code == 0, result.output
    lines = (folder / "case.toml").read_text().splitlines()
    assert '# zona = "zona.toml"   # optional: uncomment to use (template beside)' in lines
    assert not any(line.startswith("zona =") for line in lines)
    assert (folder / "zona.toml").is_file()  # the template stays, ready to be used


def test_the_report_inputs_block_leaves_out_an_unset_text(tmp_path: Path) -> None:
    """The case's own description heads the report; the experiment's empty one (the
    default) is not listed in the Inputs block as ``description = ""``."""
    from oocyte_fe.runner.registry import CaseOutcome
    from oocyte_fe.runner.report import write_case_report

    case = load_case(edited_case(tmp_path / "in", SPHERE, description=""))
    write_case_report(case, CaseOutcome(metrics={}), [], tmp_path, 1.0)
    inputs = (tmp_path / "report.md").read_text().split("## Inputs", 1)[1]
    assert "description" not in inputs
    assert "[cell]" in inputs and "outer_diameter_um = 140.0" in inputs


def test_a_holding_pipette_path_starts_at_zero(tmp_path: Path) -> None:
    """A holding pipette holds the cell where it is at t = 0: a path starting at 2 um moved
    the held patch by 2 um in the first step."""
    folder = _neck(tmp_path, **{"tools.cap.displacement_um.value": [2.0, 150.0]})
    assert refused_message(folder).endswith(
        "inputs.tools.cap.displacement_um: expected a path that is 0 at t = 0 (a holding "
        "pipette holds the cell where it is at t = 0; its path is the displacement from "
        "there), got [2.0, 150.0]"
    )
    set_inputs(folder, **{"tools.cap.displacement_um.value": [0.0, 150.0]})
    assert load_case(folder).inputs.tools["cap"].displacement_um.value == [0.0, 150.0]


def test_a_suction_that_stays_zero_loads_nothing(tmp_path: Path) -> None:
    zero = {"time_s": [0.0, 1.0], "value": [0.0, 0.0]}
    folder = edited_case(tmp_path, PIPETTE, **{"tools.pipette.suction_Pa": zero})
    assert refused_message(folder).endswith(
        "inputs.tools: expected at least one tool with a path (displacement_um) or a suction "
        "(suction_Pa, suction_control) that is not 0 throughout, or a surface load (loads): "
        "nothing here loads the cell, got ['pipette']"
    )
    set_inputs(folder, **{"tools.pipette.suction_Pa.value": [0.0, 1e-3]})  # 1 mPa: loads
    assert load_case(folder).inputs.tools["pipette"].suction_Pa.value[-1] == 1e-3
