"""Sweeps on a 2-worker local Dask cluster: closed-form statistics, failures, resume.

The cluster is started once for the module (about 3-5 s) and closed at the end.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.sweep.run import run_sweep
from oocyte_fe.sweep.store import SAMPLES, STATUS

ROOT = Path(__file__).resolve().parents[1]

LINEAR = """
kind = "analytic_linear"
description = "y = c + a.x over normal inputs"
[inputs]
x = [0.0, 0.0, 0.0]
a = [1.0, 1.0, 2.0]
c = 0.5
[sweep]
samples = 256
seed = 7
[sweep.parameters."x.0"]
distribution = "normal"
mean = 10.0
sd = 1.0
[sweep.parameters."x.1"]
distribution = "normal"
mean = 10.0
sd = 2.0
[sweep.parameters."x.2"]
distribution = "normal"
mean = 5.0
sd = 0.5
"""

ECHO = """
kind = "test_echo"
description = "y = 2 x; half the samples crash"
[inputs]
x_um = 1.0
sleep_s = SLEEP
[sweep]
samples = N
seed = 2
[sweep.parameters.x_um]
distribution = "uniform"
low = 1.0
high = 3.0
"""


@pytest.fixture(scope="module")
def client() -> Iterator[object]:
    from oocyte_fe.sweep.cluster import dask_client

    with dask_client(workers=2) as c:
        yield c


def write_case(root: Path, name: str, text: str) -> Path:
    d = root / name
    d.mkdir(parents=True)
    (d / "case.toml").write_text(text)
    return d


def echo_case(root: Path, n: int, sleep_s: float = 0.0, extra: str = "") -> Path:
    text = ECHO.replace("samples = N", f"samples = {n}").replace("SLEEP", str(sleep_s))
    return write_case(root, "echo", text + extra)


def metrics(out: Path, name: str) -> dict:
    return json.loads((out / name / "metrics.json").read_text())["metrics"]


def test_linear_statistics_match_closed_form(tmp_path: Path, client: object) -> None:
    case = load_case(write_case(tmp_path, "lin", LINEAR))
    res = run_sweep(case, tmp_path / "out", client)
    m = metrics(tmp_path / "out", "lin")
    a = np.array([1.0, 1.0, 2.0])
    mu, sigma = np.array([10.0, 10.0, 5.0]), np.array([1.0, 2.0, 0.5])
    mean = 0.5 + a @ mu  # 30.5
    var = np.sum(a**2 * sigma**2)  # 6
    n = 256
    assert res.status == "PASS" and m["n_ok"] == n and m["n_failed"] == 0
    # sampling error (plain Monte Carlo bounds; Latin hypercube is tighter): 3 standard errors
    sd = np.sqrt(var)
    assert m["y.mean"] == pytest.approx(mean, abs=3 * sd / np.sqrt(n))
    assert m["y.sd"] == pytest.approx(sd, rel=3 / np.sqrt(2 * n))
    q_se = np.sqrt(0.05 * 0.95 / n) / 0.10314 * sd  # SE of the 5 % quantile, phi(1.645)
    assert m["y.p05"] == pytest.approx(mean - 1.6449 * sd, abs=3 * q_se)
    assert m["y.p50"] == pytest.approx(mean, abs=3 * 1.2533 * sd / np.sqrt(n))
    assert m["y.p95"] == pytest.approx(mean + 1.6449 * sd, abs=3 * q_se)
    # first-order indices a_i^2 sigma_i^2 / var = 1/6, 4/6, 1/6 (RBD-FAST, 256 samples)
    report = (tmp_path / "out" / "lin" / "report.md").read_text()
    row = next(line for line in report.splitlines() if line.startswith("| y | ") and "+-" in line)
    s1 = [float(cell.split("+-")[0]) for cell in row.strip("| ").split(" | ")[1:]]
    np.testing.assert_allclose(s1, a**2 * sigma**2 / var, atol=0.1)
    assert (tmp_path / "out" / "lin" / "sensitivity.png").is_file()


def test_crashing_samples_are_reported_and_the_sweep_completes(
    tmp_path: Path, client: object
) -> None:
    extra = '[sweep.parameters.crash]\ndistribution = "list"\nvalues = [false, true]\n'
    case = load_case(echo_case(tmp_path, 8, extra=extra))
    res = run_sweep(case, tmp_path / "out", client)
    out = tmp_path / "out" / "echo"
    m = metrics(tmp_path / "out", "echo")
    assert m["n_ok"] == 4 and m["n_failed"] == 4  # Latin hypercube: half of each
    assert res.status == "PASS" and "4 of 8 samples failed" in res.reason
    with (out / "samples.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    crashed = [r for r in rows if r["status"] == "ERROR"]
    assert len(crashed) == 4 and all(r["input.crash"] == "True" for r in crashed)
    assert all("deliberate crash" in r["reason"] for r in crashed)
    ok_y = [float(r["y_um"]) for r in rows if r["status"] == "PASS"]
    assert m["y_um.mean"] == pytest.approx(np.mean(ok_y))
    assert "deliberate crash" in (out / "report.md").read_text()
    for r in crashed:  # the failed sample keeps its reason and log, no partial output
        assert sorted(p.name for p in (out / SAMPLES / r["key"]).iterdir()) == [
            "error.log",
            "report.html",
            "report.md",
            "result.json",
            "status.json",
        ]


def status_times(out: Path) -> dict[str, int]:
    return {p.parent.name: p.stat().st_mtime_ns for p in out.glob(f"echo/{SAMPLES}/*/{STATUS}")}


def test_resume_recomputes_only_missing_samples(tmp_path: Path, client: object) -> None:
    case = load_case(echo_case(tmp_path, 8))
    out = tmp_path / "out"
    run_sweep(case, out, client)
    first = status_times(out)
    assert len(first) == 8
    removed = sorted(first)[:3]
    for key in removed:
        for p in (out / "echo" / SAMPLES / key).iterdir():
            p.unlink()
        (out / "echo" / SAMPLES / key).rmdir()
    messages: list[str] = []
    run_sweep(case, out, client, notify=lambda _n, msg: messages.append(msg))
    second = status_times(out)
    assert "5 samples reused, 3 to run" in messages
    assert {k: second[k] for k in first if k not in removed} == {
        k: v for k, v in first.items() if k not in removed
    }
    assert set(second) == set(first)
    assert metrics(out, "echo")["n_ok"] == 8


@pytest.mark.slow
def test_resume_after_killed_run(tmp_path: Path, client: object) -> None:
    """Kill a sweep (and its cluster) mid-run; the rerun reuses every finished sample."""
    cases = tmp_path / "cases"
    echo_case(cases, 12, sleep_s=0.4)
    out = tmp_path / "out"
    script = (
        "import sys; sys.path.insert(0, sys.argv[1]); import tests.kinds_for_tests;"
        "from pathlib import Path; from oocyte_fe.runner.run import plan, run_cases;"
        "run_cases(plan([Path(sys.argv[2])]), Path(sys.argv[3]), workers=2)"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", script, str(ROOT), str(cases), str(out)],
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 120
    try:
        while len(status_times(out)) < 3:
            assert proc.poll() is None, "the sweep ended before it could be killed"
            assert time.monotonic() < deadline, "no sample finished within 120 s"
            time.sleep(0.1)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    finished = status_times(out)
    assert 3 <= len(finished) < 12
    messages: list[str] = []
    case = load_case(cases / "echo")
    res = run_sweep(case, out, client, notify=lambda _n, msg: messages.append(msg))
    assert f"{len(finished)} samples reused, {12 - len(finished)} to run" in messages
    after = status_times(out)
    assert {k: after[k] for k in finished} == finished and len(after) == 12
    assert res.status == "PASS" and metrics(out, "echo")["n_ok"] == 12
    assert not [p for p in out.iterdir() if p.name.startswith(".")]
    assert not [p for p in (out / "echo" / SAMPLES).iterdir() if p.name.startswith(".")]


@pytest.mark.slow
def test_spindle_offset_quick_sweep(tmp_path: Path, client: object) -> None:
    """cases/sweep_spindle_offset --quick: 4 resampled Table II curves, 4 recalibrations."""
    from oocyte_fe.sweep.resample import resample_relative

    case = load_case(ROOT / "cases" / "sweep_spindle_offset", quick=True)
    res = run_sweep(case, tmp_path, client)
    m = metrics(tmp_path, "sweep_spindle_offset")
    assert res.status == "PASS" and m["n_ok"] == 4 and m["n_failed"] == 0
    # the stated 2.5 % noise: the RMS change over 8 points lies well inside (0.5, 6) %
    assert 0.5 < m["force_change_rms_pct.p05"] <= m["force_change_rms_pct.p95"] < 6.0
    assert m["offset_x_um.sd"] > 0 and m["offset_y_um.sd"] > 0
    assert np.isfinite(m["offset_x_um.mean"]) and np.isfinite(m["offset_y_um.mean"])
    # each sample's resampled table is rebuilt from its seed alone
    with (tmp_path / "sweep_spindle_offset" / "samples.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    measured = np.loadtxt(case.inputs.data, delimiter=",", skiprows=1)[:, 1]
    for row in rows:
        table = tmp_path / "sweep_spindle_offset" / SAMPLES / row["key"] / "tableII_resampled.csv"
        got = np.loadtxt(table, delimiter=",", skiprows=1)[:, 1]
        want = resample_relative(measured, 0.025, int(row["input.noise_seed"]))
        np.testing.assert_allclose(got, want, rtol=1e-12)
    assert len({r["input.noise_seed"] for r in rows}) == 4
