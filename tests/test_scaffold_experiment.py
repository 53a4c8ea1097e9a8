"""What `oocyte-fe new fe_experiment` writes, as a new user edits it (an outside tester's
findings): a template's case has a `[quick]` table that `--quick` applies, and a case without a
template takes tool tables as docs/fe.md writes them."""

from __future__ import annotations

from pathlib import Path

import pytest

from oocyte_fe.experiment.templates import TEMPLATES
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import get_kind
from oocyte_fe.runner.scaffold import new_case


@pytest.mark.parametrize("name", sorted(TEMPLATES))
def test_a_template_case_is_coarser_with_quick(tmp_path: Path, name: str) -> None:
    new_case(get_kind("fe_experiment"), tmp_path / name, name)
    assert load_case(tmp_path / name).inputs.mesh_scale == 1.0
    assert load_case(tmp_path / name, quick=True).inputs.mesh_scale == 2.0
    assert load_case(tmp_path / name, full=True).inputs.mesh_scale == 1.0  # [full] is empty


def test_a_case_without_template_takes_tool_tables(tmp_path: Path) -> None:
    """The inputs' empty tables of tools and loads are comments, not `tools = {}`, so a
    `[inputs.tools.top]` table added below is that tool, not a TOML error ("declared twice")."""
    folder = tmp_path / "plain"
    new_case(get_kind("fe_experiment"), folder)
    text = (folder / "case.toml").read_text()
    assert "\ntools = " not in text and "\nloads = " not in text
    assert "[inputs.tools.NAME]" in text
    filled = {
        "# outer_diameter_um =    # REQUIRED: set a value": "outer_diameter_um = 100.0",
        "# mesh_size_um =    # REQUIRED: set a value": "mesh_size_um = 10.0",
        "# E_kPa =    # REQUIRED: set a value": "E_kPa = 1.0",
        "# duration_s =    # REQUIRED: set a value": "duration_s = 1.0",
        "# frames =    # REQUIRED: set a value": "frames = 4",
        "\n[quick]": '\n[inputs.tools.top]\ntype = "plate"\nside = "top"\n'
        "displacement_um = { time_s = [0.0, 1.0], value = [0.0, 5.0] }\n\n"
        '[inputs.tools.dish]\ntype = "holding_pipette"\nside = "bottom"\nhalf_width_um = 20.0\n'
        "\n[quick]",
    }
    for old, new in filled.items():
        assert old in text
        text = text.replace(old, new, 1)
    (folder / "case.toml").write_text(text)
    case = load_case(folder)
    assert list(case.inputs.tools) == ["top", "dish"] and case.inputs.tools["top"].side == "top"


def test_kinds_lists_the_fields_of_each_tool_and_load_type() -> None:
    """`oocyte-fe kinds fe_experiment` shows every tool's and load's fields with units (the
    tester found `tools: the rigid tools, by name` and nothing of radius_um, suction_Pa)."""
    from oocyte_fe.runner.scaffold import describe_kind

    text = "\n".join(describe_kind(get_kind("fe_experiment")))
    for kind_of in ("plate", "sphere", "cone", "straight_pipette", "holding_pipette"):
        assert f"tools.NAME with type = {kind_of!r}:" in text
    assert "loads.NAME with type = 'pressure':" in text
    assert "tools.NAME.radius_um [um]" in text and "tools.NAME.suction_Pa [Pa]" in text


def test_named_values_are_written_inline_where_the_comment_stands(tmp_path: Path) -> None:
    """An input mapping names to numbers or strings (afm_fit_files' `geometry`) says to write
    them inline on its line; the tester followed "add them as [inputs.geometry.NAME] tables"
    and got "expected a valid number". Names mapped to tables keep the table form."""
    import tomllib

    folder = tmp_path / "fits"
    new_case(get_kind("afm_fit_files"), folder)
    text = (folder / "case.toml").read_text()
    comment = "# none by default; write them here: geometry = { NAME = value, ... }"
    assert comment in text
    assert "# none by default; add them as [inputs.calibration.NAME] tables" in text
    edited = text.replace(comment, "geometry = { half_angle_deg = 10.0 }", 1)
    assert tomllib.loads(edited)["inputs"]["geometry"] == {"half_angle_deg": 10.0}
