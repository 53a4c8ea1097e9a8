"""Closing the local Dask clusters: a slow worker is let stop, and nothing is left running.

distributed's own close gives a worker process 4 s to stop, then kills it (mid-message on a
loaded machine); a close that overruns raises and leaves the cluster half-closed until the
interpreter exits. The project's clusters give a worker :data:`CLOSE_TIMEOUT_S` instead.
"""

from __future__ import annotations

import contextlib
import threading
import time
from pathlib import Path

import psutil
import pytest
from distributed.diagnostics.plugin import WorkerPlugin

import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.progress import ProgressEvent
from oocyte_fe.sweep.cluster import CLOSE_TIMEOUT_S, dask_client
from oocyte_fe.sweep.run import run_sweeps

SLOW_S = 6.0  # longer than distributed's 4 s, well inside CLOSE_TIMEOUT_S

ECHO = """
kind = "test_echo"
description = "y = 2 x"
[inputs]
x_um = 1.0
[sweep]
samples = 4
seed = 1
[sweep.parameters.x_um]
distribution = "uniform"
low = 1.0
high = 3.0
"""


class SlowTeardown(WorkerPlugin):
    """Takes ``SLOW_S`` to tear down (a loaded machine), then leaves a file behind."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def teardown(self, worker: object) -> None:
        time.sleep(SLOW_S)
        self.marker.write_text("closed")


def _power(x: int, n: int, progress: object = None) -> int:
    return x**n


def _children() -> set[int]:
    """This process's child processes but multiprocessing's resource tracker (it stays)."""
    pids = set()
    for p in psutil.Process().children(recursive=True):
        with contextlib.suppress(psutil.Error):  # gone meanwhile
            if "resource_tracker" not in " ".join(p.cmdline()):
                pids.add(p.pid)
    return pids


def _live_dask() -> set[tuple[str, int | None]]:
    """The Dask clusters and clients not closed, and the IO loop threads still running."""
    from distributed import Client
    from distributed.deploy.spec import SpecCluster

    clusters = {("cluster", id(c)) for c in SpecCluster._instances if c.status.name != "closed"}
    clients = {("client", id(c)) for c in Client._instances if c.status != "closed"}
    loops = {("loop", t.ident) for t in threading.enumerate() if t.name == "IO loop"}
    return clusters | clients | loops


@pytest.mark.slow
def test_a_slow_worker_is_let_stop_not_killed(tmp_path: Path) -> None:
    assert SLOW_S < 0.8 * CLOSE_TIMEOUT_S
    marker = tmp_path / "closed.txt"
    start = time.monotonic()
    with dask_client(workers=1) as client:
        client.register_plugin(SlowTeardown(marker))
        assert client.submit(sum, [1, 2]).result() == 3
    assert marker.read_text() == "closed"  # killed at 4 s, the file would be missing
    assert time.monotonic() - start < CLOSE_TIMEOUT_S


def test_nothing_is_left_running_after_a_sweep(tmp_path: Path) -> None:
    before, before_dask = _children(), _live_dask()
    d = tmp_path / "echo"
    d.mkdir()
    (d / "case.toml").write_text(ECHO)
    events: list[ProgressEvent] = []
    run_sweeps([load_case(d)], tmp_path / "out", events.append, workers=2)
    assert [e.stage for e in events if e.what == "end"] == ["PASS"]
    assert run_concurrently(_power, [(2, 3), (3, 2)], concurrent=2) == [8, 9]
    assert _live_dask() == before_dask
    deadline = time.monotonic() + 10  # a killed process can take a moment to be reaped
    while _children() - before and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _children() - before
