"""The dt -> 0 estimate of the VOF Table 4 case: Richardson's limit and observed order from
three solutions (against a closed-form sequence), the case's time-step study built from its
runs, and the extra runs the ``dt_refinements`` input adds (no OpenFOAM needed)."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest

import oocyte_fe.kinds.microchannel_vof as vof_kind
from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.extrapolation import common_reading, richardson, time_step_study
from oocyte_fe.microchannel.vof.runner import OpenFoam
from oocyte_fe.runner.run import plan, run_cases

CASES = Path(__file__).resolve().parents[1] / "cases"


@pytest.mark.parametrize(("order", "ratio"), [(1.0, 2.0), (1.5, 2.0), (2.0, 3.0), (0.5, 2.0)])
def test_richardson_recovers_order_and_limit_of_a_power_law(order: float, ratio: float) -> None:
    f = [3.0 - 0.25 * (1.0 / ratio**k) ** order for k in range(3)]  # f0 = 3 exactly
    ex = richardson(f, ratio)
    assert ex.monotone
    assert ex.order == pytest.approx(order, rel=1e-10)
    assert ex.limit == pytest.approx(3.0, rel=1e-12)
    assert ex.finest == f[2]


@pytest.mark.parametrize("q", [-0.5, -0.126, 0.3])
def test_limit_of_a_geometric_sequence_alternating_or_not(q: float) -> None:
    f = [1.5 - 0.2 * q**k for k in range(3)]  # f0 = 1.5, differences shrink by q
    ex = richardson(f)
    assert ex.factor == pytest.approx(q, rel=1e-12)
    assert ex.limit == pytest.approx(1.5, rel=1e-12)
    assert ex.monotone == (q > 0) and ex.converging
    assert math.isnan(ex.order) if q < 0 else ex.order == pytest.approx(-math.log2(q))
    if q < 0:  # alternating: the limit lies between the two finest solutions
        assert min(f[1:]) < ex.limit < max(f[1:])


def test_no_limit_when_the_differences_do_not_shrink() -> None:
    for values in ([1.0, 1.1, 1.3], [1.0, 1.2, 0.9], [1.0, 1.0, 1.1]):
        ex = richardson(values)
        assert not ex.converging and math.isnan(ex.limit) and math.isnan(ex.order)
    settled = richardson([1.0, 1.1, 1.1])  # the last two agree: the limit is the finest
    assert settled.limit == 1.1 and settled.order == math.inf


@pytest.mark.parametrize(
    ("values", "ratio", "field"),
    [([1.0, 2.0], 2.0, "values"), ([1.0, math.nan, 2.0], 2.0, "values"), ([3, 2, 1], 1.0, "ratio")],
)
def test_richardson_refuses_bad_input(values: list[float], ratio: float, field: str) -> None:
    with pytest.raises(InputError, match=f"richardson: {field}: expected"):
        richardson(values, ratio)


def test_time_step_study_gives_the_limit_next_to_the_case_dt() -> None:
    dt = 1e-6
    # 1 - b/a = 0.002 + 0.01 (dt / 1 us): first order, limit 0.002
    ratios = [1.0 - (0.002 + 0.01 * (dt / 2**k) / 1e-6) for k in range(3)]
    m = time_step_study(dt, ratios, [0.9] * 3).metrics()
    assert m["dt_change_pct"] == pytest.approx(100 * (1 - 0.007 / 0.012), rel=1e-12)  # 41.7 %
    assert m["dt_order"] == pytest.approx(1.0, rel=1e-9)
    assert m["deformation_dt_limit"] == pytest.approx(0.002, rel=1e-9)
    assert m["ratio_dt_limit"] == pytest.approx(0.998, rel=1e-12)
    assert m["ratio_dt_error_pct"] == pytest.approx(100 * (1 - 0.988 / 0.998), rel=1e-9)
    two = time_step_study(dt, ratios[:2], [0.9] * 2)
    assert two.extrapolation is None and set(two.metrics()) == {"dt_change_pct"}
    wobbly = time_step_study(dt, [0.990, 0.995, 0.994], [0.9] * 3).metrics()  # q = -0.2
    assert math.isnan(wobbly["dt_order"])
    assert wobbly["dt_factor"] == pytest.approx(-0.2, rel=1e-9)
    assert 0.994 < wobbly["ratio_dt_limit"] < 0.995
    away = time_step_study(dt, [0.990, 0.995, 0.985], [0.9] * 3)  # q = -2: no limit
    assert away.metrics()["dt_factor"] == pytest.approx(-2.0) and "ratio_dt_limit" not in (
        away.metrics()
    )
    # x = 0 not reached by a run (the short quick window): read at the end of the runs
    short = time_step_study(dt, [0.99, math.nan, 0.99], [0.97, 0.98, 0.985])
    assert short.where == "the end of the runs"
    assert short.metrics()["ratio_dt_limit"] == pytest.approx(0.99, rel=1e-12)


def test_runs_are_read_at_x0_only_when_every_run_reaches_it() -> None:
    # the one rule of the dt, mesh and sensitivity comparisons
    assert common_reading([0.91, 0.92], [0.95, 0.96]) == ("x = 0", (0.91, 0.92))
    assert common_reading([0.91, math.nan], [0.95, 0.96]) == ("the end of the runs", (0.95, 0.96))
    with pytest.raises(InputError, match="common_reading: at_end: expected 2 ratios, one per run"):
        common_reading([0.91, 0.92], [0.95])


def test_time_step_study_needs_two_runs() -> None:
    with pytest.raises(InputError, match="time_step_study: at_junction"):
        time_step_study(1e-6, [0.99], [0.99])


def test_dt_refinements_add_runs_at_halved_steps(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    case = tmp_path / "microchannel_vof_quick"
    shutil.copytree(CASES / "microchannel_vof_quick", case)
    toml = case / "case.toml"
    text = toml.read_text()
    assert "\ndt_refinements" not in text  # the quick case runs its one step (1e-6 s)
    toml.write_text(
        text.replace("\ntime_step_s = 1e-6", "\ntime_step_s = 1e-6\ndt_refinements = 2", 1)
    )
    seen: list[tuple[str, float]] = []

    def submit(_fn, jobs, concurrent, scheduler, progress=None):
        seen.extend((job[1].name, job[2].numerics.time_step) for job in jobs)
        raise RuntimeError("stop: the jobs are what the test wanted")

    monkeypatch.setattr(vof_kind, "find_openfoam", lambda _path=None: OpenFoam(tmp_path))
    monkeypatch.setattr(vof_kind, "run_concurrently", submit)
    run_cases(plan([case]), tmp_path / "out")
    assert seen == [
        ("p300hPa", 1e-6),
        ("p300hPa_dt5e-07", 5e-7),
        ("p300hPa_dt2.5e-07", 2.5e-7),
    ]
