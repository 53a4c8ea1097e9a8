"""Inputs of the microchannel kinds that ``validate`` once let through (outside tester, items 4,
7, 12, 13, 14, 18).

Each passed ``validate`` and then ran a wrong study silently (meshes in the wrong order, a cell
wider than its channel, a Carreau curve whose plateau lies above its zero-shear viscosity), failed
only at ``run`` (a flow curve too short to fit), or would have run for days or not at all (a VOF
time step longer than the run, a mesh of 1e11 cells, a cell that never reaches the junction, an
OpenFOAM folder that does not exist). Now each is one line naming the file, the field and what
was expected; the values just inside each bound are accepted, so every rule is tested from both
sides. Only ``validate`` is exercised (no FE, no OpenFOAM).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
import tomli_w
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.runner.casefile import load_case
from tests.case_copies import edited_case, refused_message

VOF = "microchannel_vof_quick"
FLOW_CURVE_HEADER = "strain_rate_1_s,stress_as_printed,viscosity_Pa_s\n"


def _refused(folder: Path) -> str:
    return refused_message(folder)


def _without_quick(folder: Path) -> Path:
    raw = tomllib.loads((folder / "case.toml").read_text())
    raw.pop("quick", None)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    return folder


def _flow_curve(folder: Path, name: str, rows: list[tuple[float, float]]) -> Path:
    body = "".join(f"{rate},0,{eta}\n" for rate, eta in rows)
    (folder / name).write_text(FLOW_CURVE_HEADER + body)
    return folder


CURVE4 = [(0.001, 900.0), (0.005, 400.0), (0.01, 200.0), (0.05, 45.0)]


# --- 4: microchannel_flow's meshes refine one after the other -------------------------------

FLOW_REFUSED = [
    ({"radial_cells": [8, 8]}, "inputs.radial_cells: expected strictly increasing cell counts"),
    (
        {"radial_cells": [64, 32, 16, 8, 4]},
        "inputs.radial_cells: expected strictly increasing cell counts",
    ),
    ({"rectangle_cells": [4, 2]}, "inputs.rectangle_cells: expected strictly increasing cell"),
    (  # 18: the infinite-shear plateau above the zero-shear viscosity (eta0 = 1434 Pa s)
        {"carreau.eta_inf_Pa_s": 1434.001},
        "inputs.carreau.eta_inf_Pa_s: expected eta_inf_Pa_s <= eta0_Pa_s (the infinite-shear "
        "plateau lies at or below the zero-shear one) = 1434, got 1434.001",
    ),
]


@pytest.mark.parametrize(("inputs", "says"), FLOW_REFUSED)
def test_microchannel_flow_refuses(tmp_path: Path, inputs: dict, says: str) -> None:
    folder = _without_quick(edited_case(tmp_path, "microchannel_flow", **inputs))
    message = _refused(folder)
    assert "microchannel_flow/case.toml: " + says in message, message


@pytest.mark.parametrize(
    "inputs",
    [
        {"radial_cells": [8, 9]},
        {"rectangle_cells": [2, 3]},
        {"radial_cells": [4]},
        {"carreau.eta_inf_Pa_s": 1434.0},
    ],
)
def test_microchannel_flow_accepts_just_inside(tmp_path: Path, inputs: dict) -> None:
    load_case(_without_quick(edited_case(tmp_path, "microchannel_flow", **inputs)))


# --- 7: microchannel_deformation: the cell in its channel, eta_inf below the flow curve ------


@pytest.mark.parametrize(
    ("inputs", "says"),
    [
        (
            {"cell_diameter_um": 250.0},
            "inputs.cell_diameter_um: expected cell_diameter_um < channel.diameter_um (the cell "
            "fits in the channel) = 250, got 250.0",
        ),
        (  # above every Table 2 viscosity: the fitted load factor went to 0
            {"eta_inf_Pa_s": 5000.0},
            "inputs.eta_inf_Pa_s: expected an infinite-shear viscosity below the lowest viscosity "
            "of table2_viscosity.csv (44.1 Pa s",
        ),
        ({"eta_inf_Pa_s": 44.1}, "inputs.eta_inf_Pa_s: expected an infinite-shear viscosity"),
    ],
)
def test_microchannel_deformation_refuses(tmp_path: Path, inputs: dict, says: str) -> None:
    message = _refused(edited_case(tmp_path, "microchannel_deformation", **inputs))
    assert "microchannel_deformation/case.toml: " + says in message, message


@pytest.mark.parametrize("inputs", [{"cell_diameter_um": 249.0}, {"eta_inf_Pa_s": 44.0}])
def test_microchannel_deformation_accepts_just_inside(tmp_path: Path, inputs: dict) -> None:
    load_case(edited_case(tmp_path, "microchannel_deformation", **inputs))


def test_a_pressure_twice_in_the_deformation_table_is_refused(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "microchannel_deformation")
    table = folder / "table4_deformation.csv"
    lines = table.read_text().splitlines()
    at_700 = next(i for i, line in enumerate(lines) if line.startswith("700,"))
    lines[at_700] = "900," + lines[at_700].split(",", 1)[1]
    table.write_text("\n".join(lines) + "\n")
    message = _refused(folder)
    assert (
        "table4_deformation.csv (from case.toml: inputs.deformation_data): pressure_hPa: "
        "expected each pressure on one row, got 900.0"
    ) in message, message
    lines[at_700] = "800," + lines[at_700].split(",", 1)[1]  # a new pressure: accepted
    table.write_text("\n".join(lines) + "\n")
    load_case(folder)


def test_the_deformation_flow_curve_needs_three_rates_for_carreau_with_eta_inf_fixed(
    tmp_path: Path,
) -> None:
    folder = edited_case(tmp_path, "microchannel_deformation")
    _flow_curve(folder, "table2_viscosity.csv", CURVE4[:2])
    message = _refused(folder)
    assert (
        "inputs.viscosity_data: expected a flow curve carreau can be fitted to "
        "(table2_viscosity.csv: shear_rate: "
        "at least 3 distinct shear rates"
    ) in message, message
    load_case(_flow_curve(folder, "table2_viscosity.csv", CURVE4[:3]))


# --- 12: microchannel_carreau_fit's flow curve is fittable at validate ----------------------


def _carreau_only(tmp_path: Path) -> Path:
    return _without_quick(edited_case(tmp_path, "microchannel_carreau_fit", models=["carreau"]))


def test_carreau_fit_refuses_too_few_rates_and_accepts_four(tmp_path: Path) -> None:
    folder = _carreau_only(tmp_path)
    _flow_curve(folder, "table2_viscosity.csv", [*CURVE4[:3], (0.01, 150.0)])  # 3 distinct
    message = _refused(folder)
    assert (
        "microchannel_carreau_fit/case.toml: inputs.data: expected a flow curve carreau can "
        "be fitted to (table2_viscosity.csv: shear_rate: at least 4 distinct shear rates to "
        "fit the 4 free parameters of carreau), got 3"
    ) in message, message
    load_case(_flow_curve(folder, "table2_viscosity.csv", CURVE4))


def test_carreau_fit_refuses_a_constant_viscosity(tmp_path: Path) -> None:
    folder = _carreau_only(tmp_path)
    _flow_curve(folder, "table2_viscosity.csv", [(r, 100.0) for r, _ in CURVE4])
    message = _refused(folder)
    assert (
        "inputs.data: expected a flow curve carreau can be fitted to (table2_viscosity.csv: "
        "viscosity: viscosities "
        "that vary"
    ) in message and "got '100 Pa s'" in message, message
    load_case(
        _flow_curve(
            folder, "table2_viscosity.csv", [(r, 100.0) for r, _ in CURVE4[:3]] + [(0.05, 100.001)]
        )
    )


def test_carreau_fit_asks_only_what_the_chosen_models_need(tmp_path: Path) -> None:
    """Two rates fit the power law (two parameters), not Carreau (four)."""
    folder = _without_quick(edited_case(tmp_path, "microchannel_carreau_fit", models=["power_law"]))
    load_case(_flow_curve(folder, "table2_viscosity.csv", CURVE4[:2]))
    message = _refused(_flow_curve(folder, "table2_viscosity.csv", CURVE4[:1]))
    assert "at least 2 distinct shear rates to fit the 2 free parameters of power_law" in message


# --- 13: rtdc_elastic_cell's flow mesh --------------------------------------------------------


def test_rtdc_flow_size_below_a_million_triangles_is_refused(tmp_path: Path) -> None:
    message = _refused(edited_case(tmp_path, "rtdc_elastic_cell", flow_size_um=0.0773))
    assert (
        "inputs.flow_size_um: expected flow_size_um >= the size of a flow mesh of 1 million "
        "triangles"
    ) in message and "= 0.0773575, got 0.0773" in message, message
    load_case(edited_case(tmp_path / "ok", "rtdc_elastic_cell", flow_size_um=0.0774))


# --- 14, 18: microchannel_vof (validate only) -------------------------------------------------

VOF_REFUSED = [
    (  # the run lasts travel_um / U(300 hPa) = 430 um / 0.7015 m/s = 6.129e-4 s
        {"time_step_s": 6.2e-4},
        "inputs.time_step_s: expected a time step shorter than the run at 300 hPa (travel_um / "
        "U = 0.000613 s",
    ),
    (  # 125/224 um: 2.007 million cells
        {"dx_um": 125 / 224},
        "inputs.dx_um: expected a cell size giving at most 2 million cells",
    ),
    (
        {"travel_um": 333.0},
        "inputs.travel_um: expected travel_um > geometry.cell_offset_um / 1.5 (below it the "
        "cell's centre does not reach the junction centre x = 0 even at the centreline speed "
        "1.5 U) = 333.333, got 333.0",
    ),
    (
        {"travel_um": 1695.5},
        "inputs.travel_um: expected travel_um <= geometry.cell_offset_um + downstream_length_um "
        "+ cell_diameter_um / 2",
    ),
    (
        {"pressures_hPa": [350.0]},
        "inputs.pressures_hPa: expected pressures among those of table4_deformation.csv, the "
        "table the case compares with (200, 300, 400, 500, 600, 700, 900 hPa), got 350.0",
    ),
    (
        {"kelvin_voigt_fit_hPa": [250.0, 500.0]},
        "inputs.kelvin_voigt_fit_hPa: expected pressures among those of table4_deformation.csv",
    ),
    (
        {"kelvin_voigt_fit_hPa": [200.0, 300.0, 500.0, 900.0]},
        "inputs.kelvin_voigt_fit_hPa: expected two or three pressures",
    ),
    (  # the ZP's eta_inf is 3.371 Pa s
        {"zero_shear_cap_Pa_s": 3.371},
        "inputs.zero_shear_cap_Pa_s: expected zero_shear_cap_Pa_s > the largest eta_inf_Pa_s "
        "of zp and cytoplasm",
    ),
    ({"cap_sensitivity_Pa_s": 3.0}, "inputs.cap_sensitivity_Pa_s: expected cap_sensitivity_Pa_s"),
    (
        {"zp.eta_inf_Pa_s": 4618.0},
        "inputs.zp.eta_inf_Pa_s: expected eta_inf_Pa_s <= eta0_Pa_s",
    ),
    (  # the Table 2 fit keeps the cytoplasm's eta_inf: below the lowest viscosity, 44.1 Pa s
        {"cytoplasm.eta_inf_Pa_s": 44.1},
        "inputs.cytoplasm.eta_inf_Pa_s: expected an infinite-shear viscosity below the lowest "
        "viscosity of table2_viscosity.csv (44.1 Pa s",
    ),
    (
        {"isoadvector.snap_tol": 0.5},
        "inputs.isoadvector.snap_tol: expected a tolerance below 0.5",
    ),
    (
        {"isoadvector.surf_cell_tol": 0.5},
        "inputs.isoadvector.surf_cell_tol: expected a tolerance below 0.5",
    ),
    (
        {"openfoam": "/nonexistent/OpenFOAM"},
        "inputs.openfoam: expected an existing OpenFOAM directory",
    ),
]


@pytest.mark.parametrize(("inputs", "says"), VOF_REFUSED)
def test_microchannel_vof_refuses(tmp_path: Path, inputs: dict, says: str) -> None:
    message = _refused(edited_case(tmp_path, VOF, **inputs))
    assert f"{VOF}/case.toml: " + says in message, message


@pytest.mark.parametrize(
    "inputs",
    [
        {"time_step_s": 6.0e-4},
        {"dx_um": 125 / 223},
        {"travel_um": 334.0},
        {"travel_um": 1695.0},
        {"pressures_hPa": [400.0]},
        {"kelvin_voigt_fit_hPa": [200.0, 500.0]},
        {"zero_shear_cap_Pa_s": 3.38},
        {"cap_sensitivity_Pa_s": 3.38},
        {"zp.eta_inf_Pa_s": 4617.93, "zero_shear_cap_Pa_s": 5000.0},
        {"cytoplasm.eta_inf_Pa_s": 44.0},
        {"isoadvector.snap_tol": 0.49, "isoadvector.surf_cell_tol": 0.49},
        {"isoadvector.snap_tol": 0.0},
    ],
)
def test_microchannel_vof_accepts_just_inside(tmp_path: Path, inputs: dict) -> None:
    load_case(edited_case(tmp_path, VOF, **inputs))


def test_an_existing_openfoam_folder_is_accepted(tmp_path: Path) -> None:
    (tmp_path / "foam").mkdir()
    load_case(edited_case(tmp_path, VOF, openfoam=str(tmp_path / "foam")))


@pytest.mark.parametrize(
    ("name", "text", "says"),
    [
        (
            "table4_deformation.csv",
            "",
            "table4_deformation.csv (from case.toml: inputs.deformation_data): a header row",
        ),
        (
            "table4_deformation.csv",
            "pressure_hPa,ratio_experiment,ratio_simulation\n300,1.9,0.9\n",
            "inputs.deformation_data): ratio_experiment: expected axis ratios in (0, 1], got 1.9",
        ),
        (
            "table2_viscosity.csv",
            FLOW_CURVE_HEADER + "0.001,0,abc\n",
            "table2_viscosity.csv (from case.toml: inputs.viscosity_data): viscosity_Pa_s "
            "(line 2): expected a number",
        ),
    ],
)
def test_microchannel_vof_reads_its_data_files_at_validate(
    tmp_path: Path, name: str, text: str, says: str
) -> None:
    folder = edited_case(tmp_path, VOF)
    (folder / name).write_text(text)
    message = _refused(folder)
    assert says in message, message


def test_validate_exits_2_with_one_line(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, VOF, travel_um=100.0)
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "inputs.travel_um: expected travel_um > " in lines[0], result.output


# --- 22: the beside model's settings and the model itself, each useless without the other ----


def _table4_without(tmp_path: Path, *keys: str) -> Path:
    """cases/microchannel_vof_table4 with ``keys`` removed from its inputs."""
    folder = edited_case(tmp_path, "microchannel_vof_table4")
    raw = tomllib.loads((folder / "case.toml").read_text())
    for key in keys:
        del raw["inputs"][key]
    raw.get("quick", {}).pop("beside_pressures_hPa", None)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    return folder


def test_beside_settings_without_a_beside_model_are_refused(tmp_path: Path) -> None:
    # the beside pressures, cell size, correctors and refinements were ignored without a word
    message = _refused(_table4_without(tmp_path, "beside_model"))
    assert (
        "inputs.beside_pressures_hPa: expected no beside_* input without a beside_model (it "
        "would be ignored): name the model or leave the input out, got [300.0, 200.0"
    ) in message, message


def test_a_beside_model_without_pressures_is_refused(tmp_path: Path) -> None:
    message = _refused(_table4_without(tmp_path, "beside_pressures_hPa"))
    assert (
        "inputs.beside_pressures_hPa: expected at least one pressure for beside_model = "
        "'three_phase_mules' (none: it never runs)"
    ) in message, message


def test_no_beside_model_and_no_beside_settings_is_accepted(tmp_path: Path) -> None:
    keys = ("beside_model", "beside_pressures_hPa", "beside_dx_um", "beside_correctors")
    inputs = load_case(_table4_without(tmp_path, *keys, "beside_dt_refinements")).inputs
    assert inputs.beside_model is None and inputs.beside_pressures_hPa == []
