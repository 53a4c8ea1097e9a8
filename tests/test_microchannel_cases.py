"""The three microchannel cases run end to end (quick settings) and pass their checks."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases

CASES = Path(__file__).parents[1] / "cases"
NAMES = ["microchannel_carreau_fit", "microchannel_flow", "microchannel_deformation"]


@pytest.mark.parametrize("name", NAMES)
def test_case_passes_quick(name: str, tmp_path: Path) -> None:
    [result] = run_cases(plan([CASES / name], quick=True), tmp_path, quick=True)
    assert result.status == "PASS", result.reason
    data = json.loads((tmp_path / name / "metrics.json").read_text())
    assert all(c["passed"] for c in data["checks"])
    assert list((tmp_path / name).glob("*.png"))


def test_pressure_beyond_laminar_range_is_a_clear_error(tmp_path: Path) -> None:
    text = (CASES / "microchannel_flow" / "case.toml").read_text()
    case = tmp_path / "flow"
    case.mkdir()
    (case / "case.toml").write_text(text.replace("700, 900]", "700, 9000]"))
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "ERROR"
    assert "inputs.pressures_hPa: expected pressures below" in result.reason


def test_unknown_viscosity_model_names_the_field(tmp_path: Path) -> None:
    case = tmp_path / "fit"
    case.mkdir()
    text = (CASES / "microchannel_carreau_fit" / "case.toml").read_text()
    (case / "case.toml").write_text(text.replace('"power_law"]\ntable3', '"bingham"]\ntable3'))
    (case / "table2_viscosity.csv").write_text(
        (CASES / "microchannel_carreau_fit" / "table2_viscosity.csv").read_text()
    )
    with pytest.raises(InputError, match="inputs.models: expected viscosity models among"):
        load_case(case)
