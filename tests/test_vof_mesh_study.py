"""The mesh study of the VOF cases: a power law through three meshes refined by unequal
ratios (against closed forms and Richardson's constant-ratio limit), the inputs that list the
finer meshes (one number or a list; refused when not each finer, not on the geometry's
lattice, or with a corrector count per mesh that does not match), the runs they add and the
report's mesh section (no OpenFOAM needed)."""

from __future__ import annotations

import math
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

import oocyte_fe.kinds.microchannel_vof as vof_kind
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.microchannel_vof_inputs import VofInputs
from oocyte_fe.kinds.microchannel_vof_studies import mesh_study, sensitivity_notes
from oocyte_fe.microchannel.vof.extrapolation import power_law, richardson
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.microchannel.vof.runner import OpenFoam
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases

CASES = Path(__file__).resolve().parents[1] / "cases"
THIRD = 12.5 / 3.0  # 4.17 um, the lattice's third of 12.5


@pytest.mark.parametrize(
    ("steps", "order"),
    [((12.5, 6.25, THIRD), 1.7), ((6.25, THIRD, 3.125), 1.0), ((10.0, 7.0, 2.0), 2.5)],
)
def test_power_law_recovers_order_and_limit_on_unequal_refinements(steps, order) -> None:
    f = [0.008 + 3e-4 * h**order for h in steps]  # e0 = 0.008 exactly
    fit = power_law(steps, f)
    assert fit.monotone
    assert fit.order == pytest.approx(order, rel=1e-8)
    assert fit.limit == pytest.approx(0.008, rel=1e-9)
    assert fit.finest == f[2]


@pytest.mark.parametrize("ratio", [2.0, 3.0])
def test_power_law_is_richardson_at_a_constant_ratio(ratio: float) -> None:
    steps = [9.0, 9.0 / ratio, 9.0 / ratio**2]
    f = [0.0148, 0.0101, 0.0089]
    a, b = power_law(steps, f), richardson(f, ratio)
    assert a.order == pytest.approx(b.order, rel=1e-9)
    assert a.limit == pytest.approx(b.limit, rel=1e-9)
    assert a.factor == pytest.approx(b.factor, rel=1e-12)


def test_power_law_without_an_order() -> None:
    alternating = power_law([6.25, THIRD, 3.125], [0.0101, 0.0091, 0.0092])
    assert not alternating.monotone and math.isnan(alternating.order)
    assert math.isnan(alternating.limit)
    # the differences grow: no positive order, no limit
    slow = power_law([12.5, 6.25, 3.125], [0.03, 0.02, 0.008])
    assert math.isnan(slow.order) and math.isnan(slow.limit)


@pytest.mark.parametrize(
    ("steps", "values", "field"),
    [
        ([12.5, 6.25], [0.01, 0.02], "values"),
        ([12.5, 6.25, 3.125], [0.01, math.nan, 0.02], "values"),
        ([6.25, 12.5, 3.125], [0.03, 0.02, 0.01], "steps"),
        ([12.5, 6.25, 0.0], [0.03, 0.02, 0.01], "steps"),
    ],
)
def test_power_law_refuses_bad_input(steps, values, field: str) -> None:
    with pytest.raises(InputError, match=f"power_law: {field}: expected"):
        power_law(steps, values)


def _inputs(**change: object) -> VofInputs:
    case = CASES / "microchannel_vof_table4"
    data = tomllib.loads((case / "case.toml").read_text())["inputs"]
    return VofInputs.model_validate({**data, **change}, context={"case_dir": case})


def test_finer_meshes_as_one_number_or_a_list() -> None:
    assert load_case(CASES / "microchannel_vof_table4").inputs.mesh_checks == [(6.25, 48)]
    three = _inputs(mesh_check_dx_um=[6.25, THIRD, 3.125], mesh_check_correctors=[48, 64, 96])
    assert three.mesh_checks == [(6.25, 48), (THIRD, 64), (3.125, 96)]
    one_count = _inputs(mesh_check_dx_um=[6.25, 3.125], mesh_check_correctors=40)
    assert one_count.mesh_checks == [(6.25, 40), (3.125, 40)]
    assert _inputs(mesh_check_dx_um=[6.25], mesh_check_correctors=[]).mesh_checks == [(6.25, 24)]
    assert _inputs(mesh_check_dx_um=[]).mesh_checks == []


@pytest.mark.parametrize(
    ("line", "says"),
    [
        ("mesh_check_dx_um = [3.125, 6.25]", "mesh_check_dx_um: expected strictly decreasing"),
        ("mesh_check_dx_um = 25.0", "mesh_check_dx_um: expected max(mesh_check_dx_um) < dx_um"),
        ("mesh_check_dx_um = [6.25, 4.17]", "mesh_check_dx_um: expected a length that is a mult"),
        ("mesh_check_dx_um = [6.25, -1.0]", "mesh_check_dx_um"),
        (
            "mesh_check_dx_um = [6.25, 3.125]\nmesh_check_correctors = [48, 64, 96]",
            "mesh_check_correctors: expected one count, or one per mesh of mesh_check_dx_um (2)",
        ),
    ],
)
def test_finer_meshes_that_cannot_run_are_refused(tmp_path: Path, line: str, says: str) -> None:
    case = tmp_path / "table4"
    shutil.copytree(CASES / "microchannel_vof_table4", case)
    toml = case / "case.toml"
    kept = [row for row in toml.read_text().splitlines() if not row.startswith("mesh_check_")]
    at = kept.index("[inputs]") + 1
    toml.write_text("\n".join([*kept[:at], line, *kept[at:]]) + "\n")
    with pytest.raises(InputError) as err:
        load_case(case)
    assert f"{toml}: inputs.{says}" in str(err.value).replace("\n", " ")


def test_the_finer_meshes_add_one_run_each(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    case = tmp_path / "microchannel_vof_quick"
    shutil.copytree(CASES / "microchannel_vof_quick", case)
    toml = case / "case.toml"
    text = toml.read_text()
    toml.write_text(
        text.replace(
            "\ncorrectors = 24",
            "\ncorrectors = 24\nmesh_check_dx_um = [6.25, 4.166666666666667]"
            "\nmesh_check_correctors = [48, 64]",
            1,
        )
    )
    seen: list[tuple[str, float, int]] = []

    def submit(_fn, jobs, concurrent, scheduler, progress=None):
        seen.extend((job[1].name, job[2].layout.dx, job[2].numerics.correctors) for job in jobs)
        raise RuntimeError("stop: the jobs are what the test wanted")

    monkeypatch.setattr(vof_kind, "find_openfoam", lambda _path=None: OpenFoam(tmp_path))
    monkeypatch.setattr(vof_kind, "run_concurrently", submit)
    run_cases(plan([case]), tmp_path / "out")
    assert seen == [
        ("p300hPa", 12.5, 24),
        ("p300hPa_dx6.25", 6.25, 48),
        ("p300hPa_dx4.16667", THIRD, 64),
    ]


def _run(ratio: float, n_cells: int, courant: float = 0.3) -> JunctionRun:
    history = type("History", (), {"ratio": np.array([ratio])})()
    return JunctionRun(Path("."), 1.0, 1.0, n_cells, 10, 1.0, history, ratio, 0.0, ratio, courant)


def test_the_mesh_section_gives_the_limit_of_three_meshes_or_more() -> None:
    e = {h: 0.008 + 3e-4 * h**1.7 for h in (12.5, 6.25, THIRD, 3.125)}
    meshes = [(h, _run(1 - e[h], 100)) for h in (6.25, THIRD, 3.125)]
    text, m = mesh_study(12.5, _run(1 - e[12.5], 25), meshes)
    assert m["mesh_dx_um"] == [12.5, 6.25, THIRD, 3.125]
    assert m["mesh_deformation"] == pytest.approx([e[h] for h in m["mesh_dx_um"]], rel=1e-12)
    assert m["mesh_order"] == pytest.approx(1.7, rel=1e-6)
    assert m["deformation_mesh_limit"] == pytest.approx(0.008, rel=1e-6)
    assert m["deformation_mesh_error_pct"] == pytest.approx(100 * (e[12.5] / 0.008 - 1), rel=1e-6)
    assert "p = 1.70" in text and "| 3.125 | 100 |" in text
    two, m2 = mesh_study(12.5, _run(1 - e[12.5], 25), meshes[:1])
    assert "mesh_order" not in m2 and "Power law" not in two
    # the 300 hPa liquid cell (docs): 6.25 / 4.17 / 3.125 um alternate, no order
    obs = [(6.25, _run(0.9899, 1)), (THIRD, _run(0.9909, 1)), (3.125, _run(0.9908, 1))]
    text, m3 = mesh_study(12.5, _run(0.9852, 1), obs)
    assert "no observed order" in text and "mesh_order" not in m3


def test_an_order_whose_differences_grow_with_unequal_ratios() -> None:
    """Steps 10, 9, 2 um: a power law of order 0.5 has a second difference ten times the first
    (factor 9.8, not "monotone" in Richardson's sense) and still an order and a limit, which
    the mesh section reports."""
    steps = (10.0, 9.0, 2.0)
    e = [0.008 + 3e-4 * h**0.5 for h in steps]
    fit = power_law(steps, e)
    assert fit.factor > 1
    assert fit.order == pytest.approx(0.5, rel=1e-8)
    assert fit.limit == pytest.approx(0.008, rel=1e-9)
    meshes = [(h, _run(1 - v, 1)) for h, v in zip(steps[1:], e[1:], strict=True)]
    text, m = mesh_study(steps[0], _run(1 - e[0], 1), meshes)
    assert m["mesh_order"] == pytest.approx(0.5, rel=1e-6) and "p = 0.50" in text


def test_each_mesh_is_listed_once_and_the_mesh_check_reads_the_first_finer_mesh() -> None:
    base = _run(0.9726, 25)
    extra = {
        "p600hPa_dx6.25": _run(0.9815, 100),
        "p600hPa_dx3.125": _run(0.9839, 400),
        "p600hPa_cap1000": _run(0.9730, 25),
    }
    notes, m = sensitivity_notes(extra, base, {})
    assert len(notes) == 1 and notes[0].startswith("- p600hPa_cap1000")
    assert m["mesh_change_pct"] == pytest.approx(100 * (0.9815 / 0.9726 - 1), rel=1e-12)
    assert m["mesh_deformation_change_pct"] == pytest.approx(100 * (0.0185 / 0.0274 - 1), rel=1e-9)
    text, _ = mesh_study(12.5, base, [(6.25, extra["p600hPa_dx6.25"])])
    assert "| 6.25 | 100 | 0.98150 | 0.01850 | -32.5 % |" in text
