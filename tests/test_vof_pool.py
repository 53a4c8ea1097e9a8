"""Running VOF runs concurrently on Dask (vof.pool) and the numerics options the convergence
study added (no OpenFOAM needed)."""

from __future__ import annotations

import threading
import time

import pytest

from oocyte_fe.microchannel.vof.casewriter import Numerics, schemes, solution
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.microchannel.vof.runner import OpenFoam, run_utility

_lock = threading.Lock()
_running = {"now": 0, "most": 0}


def _square_slowly(x: float, delay: float, progress=None) -> float:
    with _lock:
        _running["now"] += 1
        _running["most"] = max(_running["most"], _running["now"])
    if progress is not None:
        progress(f"squaring {x:g}")
    time.sleep(delay)
    with _lock:
        _running["now"] -= 1
    return x * x


def test_runs_come_back_in_job_order_two_at_a_time() -> None:
    _running.update(now=0, most=0)
    jobs = [(3.0, 0.3), (1.0, 0.05), (2.0, 0.15), (4.0, 0.05)]
    said: list[str] = []
    guard = threading.Lock()  # the callback holds a lock: it cannot be pickled

    def say(msg: str) -> None:
        with guard:
            said.append(msg)

    lines = [say, None, say, say]
    result = run_concurrently(_square_slowly, jobs, concurrent=2, progress=lines)
    assert result == [9.0, 1.0, 4.0, 16.0]
    assert _running["most"] == 2
    assert sorted(said) == ["squaring 2", "squaring 3", "squaring 4"]


def _fail_on_two(x: float, progress=None) -> float:
    if x == 2:
        raise RuntimeError("run 2 diverged")
    return x


def test_a_failed_run_raises_its_own_error() -> None:
    with pytest.raises(RuntimeError, match="run 2 diverged"):
        run_concurrently(_fail_on_two, [(1.0,), (2.0,), (3.0,)], concurrent=2)


def test_a_single_run_stays_in_this_process() -> None:
    guard = threading.Lock()  # unpicklable: fine, nothing is pickled without Dask
    said: list[str] = []
    threads: list[str] = []

    def square(x: float, progress=None) -> float:
        threads.append(threading.current_thread().name)
        progress(f"squaring {x:g}")
        with guard:
            return x * x

    assert run_concurrently(square, [(3.0,)], concurrent=2, progress=[said.append]) == [9.0]
    assert said == ["squaring 3"]
    assert threads == [threading.current_thread().name]  # no Dask worker thread


def test_a_single_failed_run_raises_its_own_error() -> None:
    with pytest.raises(RuntimeError, match="run 2 diverged"):
        run_concurrently(_fail_on_two, [(2.0,)], concurrent=1)


def test_corrector_tolerance_and_time_scheme_reach_the_dictionaries() -> None:
    num = Numerics(correctors=24, pressure_rel_tol=0.05, ddt="CrankNicolson 0.9")
    sol = solution(num)
    assert sol["PIMPLE"]["nCorrectors"] == 24
    assert sol["solvers"]["p_rgh"]["relTol"] == 0.05  # the correctors before the last
    assert sol["solvers"]["p_rghFinal"]["relTol"] == 0  # the last one: to 1e-8
    assert schemes(num.ddt)["ddtSchemes"]["default"] == "CrankNicolson 0.9"


def _fail_at_once(x: float, tool: object, progress=None) -> float:
    raise RuntimeError("the first pressure's flow diverged")


def _start_a_program_later(x: float, tool: object, progress=None) -> float:
    foam, case = tool  # type: ignore[misc]
    time.sleep(1.0)  # busy (an FE cell, say) while the other task fails
    run_utility(foam, case, ["fakeUtility"])
    return x


def test_a_task_still_running_after_a_stop_starts_no_further_program(tmp_path) -> None:
    """A task in a worker thread cannot be interrupted; once the run is stopped it must not
    start an OpenFOAM program (a flow of the next pass, say). The program here writes a file
    when it starts; the file is never written (it was, before the stop reached tasks)."""
    marker = tmp_path / "started"
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    program = bin_dir / "fakeUtility"
    program.write_text(f"#!/bin/sh\ntouch {marker}\n")
    program.chmod(0o755)
    foam = OpenFoam(tmp_path, bin_dir)
    run_utility(foam, tmp_path, ["fakeUtility"])  # outside a stopped task it runs
    assert marker.exists()
    marker.unlink()
    jobs = [(1.0, (foam, tmp_path)), (2.0, (foam, tmp_path))]
    tasks = {1.0: _fail_at_once, 2.0: _start_a_program_later}

    def task(x: float, tool: object, progress=None) -> float:
        return tasks[x](x, tool, progress)

    with pytest.raises(RuntimeError, match="diverged"):
        run_concurrently(task, jobs, concurrent=2)
    time.sleep(2.0)  # the second task wakes, tries to start its program
    assert not marker.exists()
