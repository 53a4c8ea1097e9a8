"""Case runner: pass, fail by tolerance, crash, timeout, malformed input, parallel run."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases

GOOD = """
kind = "test_echo"
description = "echo"
[inputs]
x_um = 2.0
[reference.y_um]
value = 4.0
source = "analytic: y = 2 x"
unit = "um"
[tolerances.y_um]
rel = 0.01
"""


def make_case(root: Path, name: str, text: str) -> Path:
    d = root / name
    d.mkdir(parents=True)
    (d / "case.toml").write_text(text)
    return d


def run_dir(cases: Path, out: Path, jobs: int = 1) -> list:
    return run_cases(plan([cases]), out, jobs=jobs)


def test_pass_writes_report_metrics_and_summary(tmp_path: Path) -> None:
    make_case(tmp_path / "cases", "good", GOOD)
    out = tmp_path / "results"
    [res] = run_dir(tmp_path / "cases", out)
    assert res.status == "PASS" and res.passed == res.total == 1
    metrics = json.loads((out / "good" / "metrics.json").read_text())
    assert metrics["metrics"]["y_um"] == pytest.approx(4.0)
    report = (out / "good" / "report.md").read_text()
    assert "| y_um [1] | 4 | 4 | um | +0 (+0.00 %) | rel <= 0.01 | PASS |" in report
    assert "1. **y_um**: source: analytic: y = 2 x" in report
    assert "good" in (out / "summary.md").read_text()
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_fail_by_tolerance(tmp_path: Path) -> None:
    make_case(tmp_path / "cases", "bad", GOOD.replace("value = 4.0", "value = 4.1"))
    [res] = run_dir(tmp_path / "cases", tmp_path / "out")
    assert res.status == "FAIL" and res.passed == 0 and "y_um" in res.reason
    assert "FAIL" in (tmp_path / "out" / "bad" / "report.md").read_text()


def test_min_max_bounds(tmp_path: Path) -> None:
    text = GOOD.replace("rel = 0.01", "min = 3.0\nmax = 3.5")
    make_case(tmp_path / "cases", "bounds", text)
    [res] = run_dir(tmp_path / "cases", tmp_path / "out")
    assert res.status == "FAIL"


def test_crash_leaves_no_partial_results_and_others_run(tmp_path: Path) -> None:
    cases = tmp_path / "cases"
    make_case(cases, "a_crash", GOOD.replace("x_um = 2.0", "x_um = 2.0\ncrash = true"))
    make_case(cases, "b_good", GOOD)
    out = tmp_path / "out"
    # a previous good result of the crashing case must not survive as if current
    (out / "a_crash").mkdir(parents=True)
    (out / "a_crash" / "metrics.json").write_text("{}")
    results = {r.name: r for r in run_dir(cases, out)}
    assert results["a_crash"].status == "ERROR"
    assert "deliberate crash" in results["a_crash"].reason
    names = sorted(p.name for p in (out / "a_crash").iterdir())
    assert names == ["error.log", "report.html", "report.md", "result.json"]
    assert "deliberate crash" in (out / "a_crash" / "error.log").read_text()
    assert results["b_good"].status == "PASS"
    assert (out / "b_good" / "metrics.json").is_file()
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_timeout_is_reported(tmp_path: Path) -> None:
    text = GOOD.replace("x_um = 2.0", "x_um = 2.0\nsleep_s = 5.0").replace(
        'description = "echo"', 'description = "echo"\ntimeout_s = 0.3'
    )
    make_case(tmp_path / "cases", "slow", text)
    [res] = run_dir(tmp_path / "cases", tmp_path / "out")
    assert res.status == "ERROR" and "timed out after 0.3 s" in res.reason


def test_parallel_run_matches_serial(tmp_path: Path) -> None:
    cases = tmp_path / "cases"
    for i in range(3):
        make_case(cases, f"c{i}", GOOD.replace("x_um = 2.0", f"x_um = {i + 1}.0"))
    make_case(cases, "crash", GOOD.replace("x_um = 2.0", "x_um = 2.0\ncrash = true"))
    results = run_dir(cases, tmp_path / "out", jobs=2)
    status = {r.name: r.status for r in results}
    assert status == {"c0": "FAIL", "c1": "PASS", "c2": "FAIL", "crash": "ERROR"}
    y = json.loads((tmp_path / "out" / "c2" / "metrics.json").read_text())["metrics"]["y_um"]
    assert y == pytest.approx(6.0)


@pytest.mark.parametrize("jobs", [1, 2])
def test_full_overrides_reach_every_case_process(tmp_path: Path, jobs: int) -> None:
    """``--full``'s overrides apply whether the cases run here or in processes of their own
    (the worker processes reload the case: they once dropped ``[full]``)."""
    cases = tmp_path / "cases"
    for name in ("a", "b"):
        make_case(cases, name, GOOD.replace("x_um = 2.0", "x_um = 1.0") + "[full]\nx_um = 2.0\n")
    results = run_cases(plan([cases], full=True), tmp_path / "out", jobs=jobs)
    assert {r.name: r.status for r in results} == {"a": "PASS", "b": "PASS"}
    for name in ("a", "b"):
        y = json.loads((tmp_path / "out" / name / "metrics.json").read_text())["metrics"]["y_um"]
        assert y == pytest.approx(4.0, rel=1e-12)  # y = 2 x with the [full] x = 2.0


# --- malformed input: one line naming file, field and expectation -----------------------


@pytest.mark.parametrize(
    ("text", "field", "fragment"),
    [
        (GOOD.replace("x_um = 2.0", "x_um = "), "", "line 5"),
        (GOOD.replace('"test_echo"', '"nope"'), "kind", "test_echo"),
        (GOOD.replace("x_um = 2.0", ""), "inputs.x_um", "required"),
        (GOOD.replace("x_um = 2.0", "x_um = 2.0\ny = 1"), "inputs.y", "unknown key"),
        (
            GOOD.replace('description = "echo"', 'description = "e"\ncolour = 1'),
            "colour",
            "unknown",
        ),
        (GOOD.replace("x_um = 2.0", 'x_um = "two"'), "inputs.x_um", "valid number"),
        (GOOD.replace("x_um = 2.0", "x_um = -1.0"), "inputs.x_um", "greater than 0"),
        (GOOD.replace("x_um = 2.0", "x_um = 1.0\nnu = 0.5"), "inputs.nu", "less than 0.5"),
        (GOOD.replace("x_um = 2.0", 'x_um = 1.0\ndata = "no.csv"'), "inputs.data", "not found"),
        (GOOD.replace("[tolerances.y_um]", "[tolerances.z]"), "tolerances.z", "metric of kind"),
        (GOOD.replace("rel = 0.01", "rel = -1"), "tolerances.y_um.rel", "greater than or equal"),
        (GOOD.replace('source = "analytic: y = 2 x"', ""), "reference.y_um.source", "required"),
    ],
)
def test_malformed_case_messages(tmp_path: Path, text: str, field: str, fragment: str) -> None:
    d = make_case(tmp_path, "case", text)
    with pytest.raises(InputError) as info:
        load_case(d)
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith(str(d / "case.toml"))
    assert f": {field}:" in msg if field else True
    assert fragment in msg


def test_data_file_resolved_relative_to_case(tmp_path: Path) -> None:
    d = make_case(tmp_path, "case", GOOD.replace("x_um = 2.0", 'x_um = 2.0\ndata = "d.csv"'))
    (d / "d.csv").write_text("a\nb\nc\n")
    [res] = run_cases(plan([d]), tmp_path / "out")
    assert json.loads((tmp_path / "out" / "case" / "metrics.json").read_text())["metrics"][
        "n_rows"
    ] == pytest.approx(3.0)
    assert res.status == "PASS"


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_output_folder(tmp_path: Path) -> None:
    make_case(tmp_path / "cases", "good", GOOD)
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    with pytest.raises(InputError, match="writable output folder"):
        run_dir(tmp_path / "cases", ro / "out")


def test_output_path_that_is_a_file(tmp_path: Path) -> None:
    make_case(tmp_path / "cases", "good", GOOD)
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(InputError, match="--out: expected a writable output folder"):
        run_dir(tmp_path / "cases", blocker / "out")


# --- CLI ----------------------------------------------------------------------------------


def test_cli_run_exit_codes_and_one_line_errors(tmp_path: Path) -> None:
    cli = CliRunner()
    cases = tmp_path / "cases"
    make_case(cases, "good", GOOD)
    ok = cli.invoke(app, ["run", str(cases), "--out", str(tmp_path / "o1")])
    assert ok.exit_code == 0, ok.output
    make_case(cases, "broken", GOOD.replace("x_um = 2.0", "x_um = -2.0"))
    bad = cli.invoke(app, ["run", str(cases), "--out", str(tmp_path / "o2")])
    assert bad.exit_code == 1
    assert "greater than 0" in (tmp_path / "o2" / "summary.md").read_text()
    val = cli.invoke(app, ["validate", str(cases)])
    assert val.exit_code == 2 and "inputs.x_um" in val.output and "Traceback" not in val.output
    only = cli.invoke(app, ["run", str(cases), "--only", "good", "--out", str(tmp_path / "o3")])
    assert only.exit_code == 0 and not (tmp_path / "o3" / "broken").exists()
    missing = cli.invoke(app, ["run", str(tmp_path / "nowhere")])
    assert missing.exit_code == 2 and "a case folder" in missing.output
    listed = cli.invoke(app, ["run", str(cases), "--list"])
    assert "good" in listed.output and "INVALID" in listed.output
    long = make_case(cases, "long", GOOD.replace('"echo"', '"' + "a long description " * 12 + '"'))
    listed = cli.invoke(app, ["run", str(long), "--list"])  # not a terminal: one whole line
    assert listed.output.strip().splitlines() == [listed.output.strip()]
    assert listed.output.strip().endswith("a long description")
