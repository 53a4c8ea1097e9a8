"""The CLI's ``--scheduler`` reaches the cases that are not sweeps (``ctx.scheduler``): in the
runner's own process and in its case processes, and the VOF kind sends its OpenFOAM runs there,
ahead of the case file's ``scheduler`` input. No OpenFOAM and no Dask scheduler are needed: the
VOF runs are intercepted where they would be submitted."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

import oocyte_fe.kinds.microchannel_vof as vof_kind
import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
from oocyte_fe.cli import app
from oocyte_fe.microchannel.vof.runner import OpenFoam
from oocyte_fe.runner.run import plan, run_cases
from tests.test_runner import GOOD, make_case

CASES = Path(__file__).resolve().parents[1] / "cases"
ADDRESS = "tcp://scheduler.example:8786"


@pytest.mark.parametrize("jobs", [1, 2])  # 2: each case in its own process
def test_cli_scheduler_reaches_every_plain_case(tmp_path: Path, jobs: int) -> None:
    make_case(tmp_path / "cases", "first", GOOD)
    make_case(tmp_path / "cases", "second", GOOD)
    out = tmp_path / "out"
    run_cases(plan([tmp_path / "cases"]), out, jobs=jobs, scheduler=ADDRESS)
    for name in ("first", "second"):
        assert (out / name / "scheduler.txt").read_text() == ADDRESS
    run_cases(plan([tmp_path / "cases"]), tmp_path / "none", jobs=jobs)
    assert (tmp_path / "none" / "first" / "scheduler.txt").read_text() == "None"


class _Submitted(Exception):
    """Raised where the VOF runs would be submitted: the test has what it wanted."""


def test_cli_scheduler_reaches_the_vof_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    seen: list[object] = []

    def submit(_fn, jobs, concurrent, scheduler, progress=None):  # run_concurrently's place
        seen.append(scheduler)
        raise _Submitted

    monkeypatch.setattr(vof_kind, "find_openfoam", lambda _path=None: OpenFoam(tmp_path))
    monkeypatch.setattr(vof_kind, "run_concurrently", submit)
    case = str(CASES / "microchannel_vof_quick")
    args = ["run", case, "--out", str(tmp_path / "out"), "-q"]
    CliRunner().invoke(app, [*args, "--scheduler", ADDRESS])
    CliRunner().invoke(app, args)
    assert seen == [ADDRESS, None]  # the quick case sets no scheduler: a local cluster


@pytest.mark.parametrize(
    ("cli", "case", "used"),
    [
        (ADDRESS, None, ADDRESS),
        (ADDRESS, "tcp://other:1", ADDRESS),
        (None, "tcp://other:1", "tcp://other:1"),
        (None, None, None),
    ],
)
def test_the_cli_scheduler_wins_over_the_case_input(cli, case, used) -> None:
    ctx = SimpleNamespace(scheduler=cli)
    inp = SimpleNamespace(scheduler=case)
    assert vof_kind.run_scheduler(ctx, inp) == used  # type: ignore[arg-type]
