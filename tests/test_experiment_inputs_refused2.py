"""FE experiment inputs that ``validate`` once let through (an outside tester's defects 3, 4, 5
and 16), each now refused in one line naming ``case.toml``, the field and what was expected,
and accepted just inside its bound:

1. a tool length or a path's advance typed in metres (``radius_um = 3e-6``, an advance of
   3e-7 um): they ran to a force of 0; now at least the cell's finest element / 10 (a
   length) or / 100 (an advance);
2. a tool that starts inside the cell (advance at t = 0 beyond its gap): ``run`` stopped with
   an obstacle error naming neither file nor field;
3. a mesh far too fine (0.05 um on a 400 um cell: meshing hung); now at most 2 million
   triangles, estimated;
4. a case where nothing loads the cell (no path, no suction, no load): it reported PASS after
   0 Newton iterations.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
import tomli_w
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.experiment.description import MAX_TRIANGLES
from oocyte_fe.runner.casefile import load_case
from tests.case_copies import edited_case, refused_message, set_inputs

SPHERE = "fe_afm_sphere"  # refine_size_um = 0.25: the floor is 0.025 um
PIPETTE = "fe_aspiration_theret"  # refine_size_um = 0.5: the floor is 0.05 um
PLATES = "fe_plate_compression"


def _path(*value: float) -> dict:
    n = len(value)
    return {"time_s": [i / (n - 1) for i in range(n)], "value": list(value)}


UNSET = "<unset>"
"""An input value that removes the key from the copied case."""


def _case(tmp_path: Path, case: str, **inputs: object) -> Path:
    """``cases/<case>`` copied with ``inputs`` set, those set to :data:`UNSET` removed."""
    folder = edited_case(tmp_path, case, **inputs)
    raw = tomllib.loads((folder / "case.toml").read_text())
    for key, value in inputs.items():
        if value == UNSET:
            *parents, last = key.split(".")
            table = raw["inputs"]
            for part in parents:
                table = table[part]
            del table[last]
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    return folder


def _template(tmp_path: Path, template: str, **inputs: object) -> Path:
    folder = tmp_path / template
    result = CliRunner().invoke(app, ["new", "fe_experiment", str(folder), "--template", template])
    assert result.exit_code == 0, result.output
    return set_inputs(folder, **inputs)


DISH = {"type": "holding_pipette", "side": "bottom", "half_width_um": 60.0}
# a 140 um cell, no refinement, elements of h um: 2.31 pi 70^2 / 2 / h^2 triangles, 2.0e6 at
# h = 0.0943 um; the case's [full] run (mesh_scale = 0.5) meets it at mesh_size_um = 0.1886
TINY_MESH = 0.1886

REFUSED = [
    (  # 1: a probe radius in metres
        SPHERE,
        {"tools.probe.radius_um": 3e-6},
        "inputs.tools.probe.radius_um: expected at least 0.025 um (the cell's finest element, "
        "refine_size_um = 0.25 um, / 10: a smaller tool falls within one element); 3e-06 um "
        "looks like metres (3 um?), got 3e-06",
    ),
    (  # 1: a holding pipette's width in metres
        SPHERE,
        {"tools.dish.half_width_um": 6e-5},
        "inputs.tools.dish.half_width_um: expected at least 0.025 um",
    ),
    (  # 1: a pipette's radius in metres
        PIPETTE,
        {"tools.pipette.inner_radius_um": 5e-6},
        "inputs.tools.pipette.inner_radius_um: expected at least 0.05 um",
    ),
    (  # 1: an indentation depth in metres
        SPHERE,
        {"tools.probe.displacement_um": _path(0.0, 5e-7)},
        "inputs.tools.probe.displacement_um: expected a largest advance into the cell (beyond "
        "gap_um = 0 um) of at least 0.0025 um (the cell's finest element, refine_size_um = "
        "0.25 um, / 100: a smaller advance gives no force): it presses only 5e-07 um; 5e-07 um "
        "looks like metres (0.5 um?)",
    ),
    (  # 1: no refined size: the floor is the element's / 100
        SPHERE,
        {"cell.refine_size_um": UNSET, "tools.probe.displacement_um": _path(0.0, 0.05)},
        "inputs.tools.probe.displacement_um: expected a largest advance into the cell (beyond "
        "gap_um = 0 um) of at least 0.08 um (the cell's finest element, refine_size_um unset: "
        "mesh_size_um = 8 um, / 100",
    ),
    (  # 2: the probe starts 2 um deep
        SPHERE,
        {"tools.probe.displacement_um": _path(2.0, 2.5)},
        "inputs.tools.probe.displacement_um: expected an advance at t = 0 of at most gap_um = "
        "0 um (the tool starts clear of the cell or touching it): it starts 2 um inside the "
        "cell, got [2.0, 2.5]",
    ),
    (  # 2: within a gap, but beyond it
        SPHERE,
        {"tools.probe.gap_um": 1.0, "tools.probe.displacement_um": _path(1.5, 2.0)},
        "inputs.tools.probe.displacement_um: expected an advance at t = 0 of at most gap_um = "
        "1 um (the tool starts clear of the cell or touching it): it starts 0.5 um inside",
    ),
    (  # 2: a plate
        PLATES,
        {"tools.top.displacement_um": _path(1.0, 5.0)},
        "inputs.tools.top.displacement_um: expected an advance at t = 0 of at most gap_um = 0 um",
    ),
    (  # 3: 0.05 um elements on a 140 um cell: 7 million triangles
        SPHERE,
        {"cell.mesh_size_um": 0.05, "cell.refine_size_um": 0.05},
        "inputs.cell.mesh_size_um: expected a mesh of at most 2,000,000 triangles",
    ),
    (  # 3: just over the bound
        SPHERE,
        {"cell.mesh_size_um": TINY_MESH - 0.001, "cell.refine_size_um": TINY_MESH - 0.001},
        "inputs.cell.mesh_size_um: expected a mesh of at most 2,000,000 triangles (estimated "
        "from the section's area / mesh_size_um^2 and the refined band's area / "
        "refine_size_um^2, sizes times mesh_scale = 0.5): these sizes give about 2.02e+06",
    ),
    (  # 3: a refined band too fine (0.005 um elements 4 um deep under 6 deg)
        SPHERE,
        {"cell.refine_size_um": 0.005},
        "inputs.cell.refine_size_um: expected a mesh of at most 2,000,000 triangles",
    ),
    (  # 4: only a dish that holds the cell: nothing loads it
        SPHERE,
        {"tools": {"dish": DISH}},
        "inputs.tools: expected at least one tool with a path (displacement_um) or a suction "
        "(suction_Pa, suction_control) that is not 0 throughout, or a surface load (loads): "
        "nothing here loads the cell",
    ),
]


@pytest.mark.parametrize(("case", "inputs", "says"), REFUSED)
def test_inputs_are_refused_in_one_line(tmp_path: Path, case: str, inputs: dict, says: str) -> None:
    message = refused_message(_case(tmp_path, case, **inputs))
    assert f"{case}/case.toml: " + says in message, message


@pytest.mark.parametrize(("case", "inputs", "says"), REFUSED[::2])
def test_validate_refuses_them_with_exit_2(
    tmp_path: Path, case: str, inputs: dict, says: str
) -> None:
    result = CliRunner().invoke(app, ["validate", str(_case(tmp_path, case, **inputs))])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and says in lines[0], result.output
    assert "Traceback" not in result.output


ACCEPTED = [
    (SPHERE, {"tools.probe.radius_um": 0.03, "tools.dish.half_width_um": 0.03}),
    (PIPETTE, {"tools.pipette.inner_radius_um": 0.06, "tools.pipette.wall_um": 0.06}),
    (SPHERE, {"tools.probe.displacement_um": _path(0.0, 0.003)}),
    (SPHERE, {"tools.probe.gap_um": 2.0, "tools.probe.displacement_um": _path(2.0, 2.5)}),
    (SPHERE, {"tools.probe.gap_um": 1.0, "tools.probe.displacement_um": _path(0.0, 1.5)}),
    (PLATES, {"tools.top.gap_um": 1.0, "tools.top.displacement_um": _path(1.0, 5.0)}),
    (SPHERE, {"cell.mesh_size_um": TINY_MESH + 0.001, "cell.refine_size_um": TINY_MESH + 0.001}),
    (SPHERE, {"cell.refine_size_um": 0.02}),
    (SPHERE, {"tools": {"dish": DISH | {"displacement_um": _path(0.0, 0.5)}}}),
    (
        SPHERE,
        {
            "tools": {"dish": DISH},
            "loads": {"push": {"type": "pressure", "pressure_Pa": _path(0.0, 10.0)}},
        },
    ),
]


@pytest.mark.parametrize(("case", "inputs"), ACCEPTED)
def test_inputs_just_inside_the_bounds_load(tmp_path: Path, case: str, inputs: dict) -> None:
    exp = load_case(_case(tmp_path, case, **inputs)).inputs
    assert exp.estimated_triangles() <= MAX_TRIANGLES


def test_tiny_mesh_estimate_brackets_the_bound(tmp_path: Path) -> None:
    over = load_case(
        edited_case(tmp_path, SPHERE, **{"cell.mesh_size_um": 0.2, "cell.refine_size_um": 0.2})
    ).inputs
    # 2.31 pi 70^2 / 2 / 0.2^2 triangles, no refined band
    assert over.estimated_triangles() == pytest.approx(2.31 * 3.14159265 * 70**2 / 2 / 0.04)


def test_necked_pipette_starting_past_its_clearance_is_refused(tmp_path: Path) -> None:
    folder = _template(tmp_path, "neck", **{"tools.pipette.displacement_um": _path(0.5, 0.5)})
    message = refused_message(folder)
    assert (
        "neck/case.toml: inputs.tools.pipette.displacement_um: expected an advance at t = 0 of "
        "at most clearance_um = 0.1 um" in message
    ), message


@pytest.mark.parametrize("template", ["afm_indentation", "plates", "aspiration", "neck", "press"])
def test_templates_estimate_far_below_the_mesh_bound(tmp_path: Path, template: str) -> None:
    exp = load_case(_template(tmp_path, template)).inputs
    assert exp.estimated_triangles() < MAX_TRIANGLES / 100


def test_the_estimate_grades_as_the_mesher_does() -> None:
    """description.GRADING is a copy (the description must not import gmsh): the same value."""
    from oocyte_fe.experiment import description
    from oocyte_fe.mesh import gmsh_session

    assert description.GRADING == gmsh_session.GRADING


def test_a_plate_that_never_moves_points_to_the_holding_pipette(tmp_path: Path) -> None:
    """A user's dish as a plate standing still (the tester's `dish_plate`): refused, and the
    message names the tool that models a dish."""
    still = _case(tmp_path / "still", PLATES, **{"tools.bottom.displacement_um": _path(0.0, 0.0)})
    assert "a dish the cell rests on: a holding_pipette" in refused_message(still)
    unset = _case(tmp_path / "unset", PLATES, **{"tools.bottom.displacement_um": UNSET})
    assert "holding_pipette" in refused_message(unset)
