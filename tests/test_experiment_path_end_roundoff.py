"""A tool's path written to end with the experiment (``time_s[-1] == time.duration_s``) keeps
validating when either is off by round-off; a path that really runs past the duration is
refused, naming the field (``oocyte_fe.experiment.description.TIME_SLACK``)."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

import pytest
import tomli_w

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case

CASE = Path(__file__).parents[1] / "cases" / "fe_afm_sphere"


def _case_with(tmp_path: Path, end_s: float, duration_s: float) -> Path:
    case = tmp_path / "sphere"
    shutil.copytree(CASE, case)
    raw = tomllib.loads((case / "case.toml").read_text())
    path = raw["inputs"]["tools"]["probe"]["displacement_um"]
    assert path["time_s"][-1] == raw["inputs"]["time"]["duration_s"] == 1.0  # as shipped
    path["time_s"][-1] = end_s
    raw["inputs"]["time"]["duration_s"] = duration_s
    (case / "case.toml").write_text(tomli_w.dumps(raw))
    return case


@pytest.mark.parametrize(
    ("end_s", "duration_s"),
    [(1.0 + 1e-9, 1.0), (1.0, 1.0 - 1e-9), (1.0 + 1e-9, 1.0 - 1e-9)],
    ids=["path_end_up", "duration_down", "both"],
)
def test_a_path_ending_with_the_run_off_by_round_off_validates(tmp_path, end_s, duration_s):
    case = load_case(_case_with(tmp_path, end_s, duration_s))
    assert case.inputs.time.duration_s == duration_s  # read as written, not rounded


def test_a_path_running_past_the_run_is_refused_naming_the_field(tmp_path):
    with pytest.raises(InputError, match=r"tools\.probe\.displacement_um\.time_s within time"):
        load_case(_case_with(tmp_path, 1.001, 1.0))
