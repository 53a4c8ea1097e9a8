"""Relations between an FE experiment's parts that ``validate`` once let through.

Each input below passed ``validate`` and then either failed ``run`` with a pydantic
``ValidationError`` naming neither file nor field, or ran a wrong experiment silently (plates
closing through each other, a probe that never touches the cell, a pressure on no surface, a
material file with a modulus of 1e30 kPa). Now each is one line naming ``case.toml`` (and the
material file), the field and what was expected; the values just inside each bound are
accepted, so every rule is tested from both sides.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import tomli_w
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.runner.casefile import load_case
from tests.case_copies import CASES, edited_case, refused_message, set_inputs


def _path(*value: float, end: float = 1.0) -> dict:
    """A displacement path from 0 through ``value`` at equal times up to ``end`` s."""
    n = len(value)
    return {"time_s": [end * i / (n - 1) for i in range(n)], "value": list(value)}


def _neck_case(tmp_path: Path, **inputs: object) -> Path:
    """cases/fe_neck_aspiration with its material case beside it (``../afm_creep_prony``)."""
    shutil.copytree(CASES / "afm_creep_prony", tmp_path / "afm_creep_prony")
    return edited_case(tmp_path, "fe_neck_aspiration", **inputs)


def _template_case(tmp_path: Path, template: str, **inputs: object) -> Path:
    """A case written by ``oocyte-fe new fe_experiment --template``, with ``inputs`` set
    (dotted keys reach nested tables, as in :func:`tests.case_copies.edited_case`)."""
    folder = tmp_path / template
    result = CliRunner().invoke(app, ["new", "fe_experiment", str(folder), "--template", template])
    assert result.exit_code == 0, result.output
    return set_inputs(folder, **inputs)


def _refused(folder: Path) -> str:
    return refused_message(folder)


# --- 4: fe_neck_aspiration's pipette against the cell (same rules as fe_experiment's) --------

NECK_REFUSED = [
    (  # passed validate; run: "ValidationError: 1 validation error for Experiment"
        {"bore_diameter_um": 170.0, "neck_diameter_um": 160.0},
        "inputs.bore_diameter_um: expected a bore wider than the cell's diameter + 2 "
        "clearance_um = 180.2 um (the cell starts in the bore), got 170.0",
    ),
    (  # a neck wider than the 180 um cell: the cell passes untouched
        {"neck_diameter_um": 190.0},
        "inputs.neck_diameter_um: expected a neck narrower than the cell's diameter 180 um",
    ),
    (  # the rear cap carries the cell 5 mm: far beyond the modelled 500 um of neck
        {"advance_um": 5000.0},
        "inputs.advance_um: expected an advance of at most 539.2 um",
    ),
    (  # 0.05 um never closes the 0.1 um clearance: no seal, no passage
        {"advance_um": 0.05},
        "inputs.advance_um: expected an advance beyond clearance_um = 0.1 um",
    ),
    (  # an element of 100 um on the 90 um cell: the five points 47.1 um apart share elements
        {"size_um": 100.0},
        "inputs.size_um: expected size_um <= (cytoplasm_radius_um + zona_thickness_um) pi / 6 "
        "= 47.1239, got 100.0",
    ),
    (
        {"mesh_study_sizes_um": [48.0, 10.0]},
        "inputs.mesh_study_sizes_um: expected max(mesh_study_sizes_um) <= ",
    ),
    ({"sensitivity_size_um": 48.0}, "inputs.sensitivity_size_um: expected sensitivity_size_um <= "),
]


@pytest.mark.parametrize(("inputs", "says"), NECK_REFUSED)
def test_neck_aspiration_pipette_against_the_cell_is_refused(
    tmp_path: Path, inputs: dict, says: str
) -> None:
    message = _refused(_neck_case(tmp_path, **inputs))
    assert "fe_neck_aspiration/case.toml: " + says in message, message


@pytest.mark.parametrize(
    "inputs",
    [
        {"bore_diameter_um": 180.5, "neck_diameter_um": 150.0},
        {"neck_diameter_um": 179.0},
        {"advance_um": 539.0},
        {"size_um": 47.0, "mesh_study_sizes_um": [47.0, 10.0], "sensitivity_size_um": 47.0},
    ],
)
def test_neck_aspiration_pipette_just_inside_the_bounds_is_accepted(
    tmp_path: Path, inputs: dict
) -> None:
    case = load_case(_neck_case(tmp_path, **inputs))
    for key, value in inputs.items():
        assert getattr(case.inputs, key) == value


def test_neck_aspiration_bore_is_refused_by_validate_in_one_line(tmp_path: Path) -> None:
    folder = _neck_case(tmp_path, bore_diameter_um=170.0, neck_diameter_um=160.0)
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "inputs.bore_diameter_um: expected " in lines[0], result.output


# --- 4, 5: fe_experiment's necked pipette and its rear cap ------------------------------------

NECKED_REFUSED = [
    (
        {"tools.pipette.neck_diameter_um": 190.0},
        "inputs.tools.pipette.neck_diameter_um: expected a neck narrower than the cell's "
        "diameter 180 um",
    ),
    (
        {"tools.pipette.bore_diameter_um": 170.0, "tools.pipette.neck_diameter_um": 160.0},
        "inputs.tools.pipette.bore_diameter_um: expected a bore wider than the cell's diameter",
    ),
    (
        {"tools.cap.displacement_um": _path(0.0, 1000.0)},
        "inputs.tools.cap.displacement_um: expected an advance of at most 539.2 um",
    ),
]


@pytest.mark.parametrize(("inputs", "says"), NECKED_REFUSED)
def test_necked_pipette_against_the_cell_is_refused(
    tmp_path: Path, inputs: dict, says: str
) -> None:
    message = _refused(_template_case(tmp_path, "neck", **inputs))
    assert "neck/case.toml: " + says in message, message


# --- 5, 6: tools that travel through the cell, or never touch it ------------------------------

PLATES = "fe_plate_compression"
SPHERE = "fe_afm_sphere"
TRAVEL_REFUSED = [
    (  # 200 um of plates on a 140 um cell: each 100 um passed the one-tool check
        PLATES,
        {
            "tools.top.displacement_um": _path(0.0, 0.35, 100.0),
            "tools.bottom.displacement_um": _path(0.0, 0.35, 100.0),
        },
        "inputs.tools.top.displacement_um: expected travels of opposed tools, "
        "tools.top.displacement_um and tools.bottom.displacement_um (advance less gap), "
        "summing below the cell's diameter 140 um: at t = 1 s they sum to 200 um",
    ),
    (  # the dish (a holding pipette) driven 300 um into the probe
        SPHERE,
        {"tools.dish.displacement_um": _path(0.0, 300.0)},
        "inputs.tools.dish.displacement_um: expected travels of opposed tools, "
        "tools.dish.displacement_um and tools.probe.displacement_um",
    ),
    (  # plates moving away: they never press the cell
        PLATES,
        {
            "tools.top.displacement_um": _path(0.0, -0.35, -21.0),
            "tools.bottom.displacement_um": _path(0.0, -0.35, -21.0),
        },
        "inputs.tools.top.displacement_um: expected a path that presses the tool into the "
        "cell (an advance beyond gap_um = 0 um): its largest advance is 0 um, so it only "
        "reaches the cell's surface, never presses it",
    ),
    (  # a probe 5 mm away moved 0.5 um
        SPHERE,
        {"tools.probe.gap_um": 5000.0},
        "inputs.tools.probe.displacement_um: expected a path that presses the tool into the "
        "cell (an advance beyond gap_um = 5000 um): its largest advance is 0.5 um, so it "
        "stops 4999.5 um short of the cell",
    ),
    (  # one plate pressing, then backing off: the cell loses its support at 1 s
        PLATES,
        {"tools.top.displacement_um": _path(0.0, 5.0, -1.0)},
        "the cell needs support (a free cell under loads only: support = 'inertia_relief'; "
        "tools.top.displacement_um is 1 um clear of the cell at t = 1 s)",
    ),
    (
        PLATES,
        {"tools.top.displacement_um": _path(0.0, 150.0)},
        "inputs.tools.top.displacement_um: expected a travel into the cell (advance less "
        "gap_um) below its diameter 140 um, got 150.0",
    ),
]


@pytest.mark.parametrize(("case", "inputs", "says"), TRAVEL_REFUSED)
def test_tool_travels_against_the_cell_are_refused(
    tmp_path: Path, case: str, inputs: dict, says: str
) -> None:
    message = _refused(edited_case(tmp_path, case, **inputs))
    assert f"{case}/case.toml: inputs" in message and says in message, message


@pytest.mark.parametrize(
    ("case", "inputs"),
    [
        (  # 69.9 + 69.9 um: the plates stop 0.2 um apart
            PLATES,
            {
                "tools.top.displacement_um": _path(0.0, 0.35, 69.9),
                "tools.bottom.displacement_um": _path(0.0, 0.35, 69.9),
            },
        ),
        (  # the largest travels at different times never sum to the diameter
            PLATES,
            {
                "tools.top.displacement_um": _path(0.0, 100.0, 20.0),
                "tools.bottom.displacement_um": _path(0.0, 20.0, 100.0),
            },
        ),
        (SPHERE, {"tools.dish.displacement_um": _path(0.0, 139.0)}),
        (SPHERE, {"tools.probe.gap_um": 0.4}),
    ],
)
def test_tool_travels_within_the_cell_are_accepted(tmp_path: Path, case: str, inputs: dict) -> None:
    load_case(edited_case(tmp_path, case, **inputs))


# --- 7: a pressure window outside the axisymmetric section ------------------------------------


def _pressure(window: list[float]) -> dict:
    ramp = _path(0.0, 10.0)
    return {"p": {"type": "pressure", "pressure_Pa": ramp, "window_deg": window}}


@pytest.mark.parametrize("window", [[-170.0, -100.0], [-30.0, 0.0]])
def test_pressure_window_outside_the_axisymmetric_section_is_refused(
    tmp_path: Path, window: list[float]
) -> None:
    """theta = atan2(x, y) runs over 0-180 deg with x >= 0: the window selected nothing."""
    message = _refused(edited_case(tmp_path, PLATES, loads=_pressure(window)))
    says = (
        f"{PLATES}/case.toml: inputs.loads.p.window_deg: expected a window that meets the "
        "polar angles of the axisymmetric section, 0 to 180 deg"
    )
    assert says in message, message


@pytest.mark.parametrize(
    ("symmetry", "window"),
    [("axisymmetric", [-30.0, 10.0]), ("plane_strain", [-170.0, -100.0])],
)
def test_pressure_window_on_the_surface_is_accepted(
    tmp_path: Path, symmetry: str, window: list[float]
) -> None:
    inputs = {"loads": _pressure(window), "cell.symmetry": symmetry}
    if symmetry == "plane_strain":  # plates alone do not hold a plane-strain cell: loads only
        inputs |= {"tools": {}, "support": "inertia_relief"}
    case = load_case(edited_case(tmp_path, PLATES, **inputs))
    assert case.inputs.loads["p"].window_deg == window


# --- 8: a material file's constants get the bounds of inline ones ----------------------------

MATERIAL_REFUSED = [
    (
        {"E_kPa": 1e-30},
        "material.E_kPa",
        "E_kPa",
        "a value in [1e-06, 1e+09] kPa (Young's modulus)",
    ),
    ({"E_kPa": 1e30}, "material.E_kPa", "E_kPa", "a value in [1e-06, 1e+09] kPa (Young's modulus)"),
    ({"nu": -0.9}, "material.nu", "nu", "a value in [0, 0.5] (Poisson's ratio)"),
    (
        {"prony": {"g": [0.5], "tau_s": [1e-300]}},
        "prony.tau_s",
        "prony.tau_s",
        "relaxation times in [1e-09, 1e+09] s",
    ),
]


def _file_material_case(tmp_path: Path, changes: dict) -> Path:
    """The plates case with its cytoplasm in a material file ``mat.toml`` of ``changes``."""
    material = _material(**changes)
    prony = material.pop("prony", None)
    record = {"material": {"name": "cyto", "source": "test"} | material}
    if prony:
        record["prony"] = prony
    folder = edited_case(tmp_path / "file", PLATES, **{"cell.materials.cytoplasm": "mat.toml"})
    (folder / "mat.toml").write_text(tomli_w.dumps(record))
    return folder


def _material(**changes: object) -> dict:
    table: dict = {"E_kPa": 1.0, "nu": 0.5} | changes
    return table


@pytest.mark.parametrize(("changes", "file_field", "inline_field", "says"), MATERIAL_REFUSED)
def test_material_file_and_inline_constants_have_the_same_bounds(
    tmp_path: Path, changes: dict, file_field: str, inline_field: str, says: str
) -> None:
    inline = _refused(
        edited_case(
            tmp_path / "inline", PLATES, **{"cell.materials.cytoplasm": _material(**changes)}
        )
    )
    assert f"inputs.cell.materials.cytoplasm.{inline_field}: expected {says}" in inline

    folder = _file_material_case(tmp_path, changes)
    message = _refused(folder)
    head = f"{PLATES}/case.toml: inputs.cell.materials.cytoplasm: expected a material file ("
    assert head in message, message
    assert f"{folder / 'mat.toml'}: {file_field}: expected {says}" in message, message


@pytest.mark.parametrize(
    "changes",
    [
        {"E_kPa": 1e-6},
        {"E_kPa": 1e9},
        {"nu": 0.0},
        {"prony": {"g": [0.5], "tau_s": [1e-9]}},
    ],
)
def test_material_constants_at_the_bounds_are_accepted_in_both_forms(
    tmp_path: Path, changes: dict
) -> None:
    load_case(
        edited_case(
            tmp_path / "inline", PLATES, **{"cell.materials.cytoplasm": _material(**changes)}
        )
    )
    folder = _file_material_case(tmp_path, changes)
    load_case(folder)


# --- 9: the refined zone's depth within the cell ----------------------------------------------


def test_refine_depth_beyond_the_cell_radius_is_refused(tmp_path: Path) -> None:
    message = _refused(edited_case(tmp_path, PLATES, **{"cell.refine_depth_um": 500.0}))
    assert (
        f"{PLATES}/case.toml: inputs.cell.refine_depth_um: expected refine_depth_um < the "
        "cell's radius = 70, got 500.0" in message
    ), message


def test_refine_depth_within_the_cell_radius_is_accepted(tmp_path: Path) -> None:
    case = load_case(edited_case(tmp_path, PLATES, **{"cell.refine_depth_um": 69.0}))
    assert case.inputs.cell.refine_depth_um == 69.0


@pytest.mark.parametrize(
    ("window", "refused"),
    [
        ([1000.0, 2000.0, 3000.0, 4000.0], True),  # passed validate: an empty figure
        ([-20.0, 20.0, 50.0, 60.0], True),  # above the 50 um cell; the pipette does not move
        ([-20.0, 20.0, 30.0, 60.0], False),  # the shipped window over the apex
        ([49.0, 60.0, -60.0, -49.0], False),  # a corner of the cell's extent
    ],
)
def test_section_window_must_show_part_of_the_cell(
    tmp_path: Path, window: list[float], refused: bool
) -> None:
    """The figures' window against the cell's extent (R = 50 um about the origin; a tool's
    travel widens it along the axis, here none: the pipette sucks, it does not move)."""
    folder = edited_case(tmp_path, "fe_aspiration_theret", **{"record.section_window_um": window})
    if not refused:
        assert load_case(folder).inputs.record.section_window_um == window
        return
    assert _refused(folder) == (
        "fe_aspiration_theret/case.toml: inputs.record.section_window_um: expected a window that "
        "shows part of the cell: x within (-50, 50) um and y within (-50, 50) um (the cell about "
        f"the origin, and as far as the tools move), got {window}"
    ).replace("fe_aspiration_theret/", f"{folder}/")
