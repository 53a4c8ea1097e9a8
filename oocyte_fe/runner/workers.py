"""Cases in parallel, one process each: a process that dies costs only its own case.

The parent starts up to ``jobs`` processes, each loading and running one case into a temporary
folder the parent chose, and sending its progress events and its result through
one queue. The parent moves finished folders into place. A process that ends without a result
(killed, out of memory, a crash in compiled code) or overruns its case's ``timeout_s`` by
:data:`GRACE_S` is reported ``ERROR`` with the cause; its temporary folder is removed and the
other cases run on.

The processes are forked from a ``forkserver`` that imported the runner and the kinds of the
cases once (:func:`_start_method`): a fresh interpreter per case (``spawn``) spent 1.5-4 CPU s
importing numpy, scipy, matplotlib, pydantic and the FE stack again, 61 of the main job's 427
CPU s. The server is a clean single-threaded process (no display thread, nothing run), so each
case still starts from freshly imported modules. Where ``forkserver`` does not exist
(Windows), ``spawn``.
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.forkserver
import queue as queue_mod
import shutil
import signal
import time
from dataclasses import dataclass
from multiprocessing.process import BaseProcess
from pathlib import Path

from oocyte_fe.runner.casefile import Case, load_case
from oocyte_fe.runner.execute import execute_case, failure_folder, partial_folder, place_result
from oocyte_fe.runner.progress import EventSink, ProgressEvent
from oocyte_fe.runner.result import CaseResult

GRACE_S = 30.0
"""How long past its ``timeout_s`` a case process may take before it is killed."""


def _child(
    directory: Path,
    tmp: Path,
    quick: bool,
    kind_module: str,
    verbose: bool,
    q: object,
    scheduler: str | None = None,
    full: bool = False,
) -> None:
    """Process entry point: reload the case (with the ``[quick]`` / ``[full]`` overrides it
    was planned with) and run it into ``tmp``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    put = q.put  # type: ignore[attr-defined]
    case = load_case(directory, quick=quick, kind_module=kind_module, full=full)
    result = execute_case(case, tmp, quick, lambda ev: put(("event", ev)), verbose, scheduler)
    put(("result", result))


@dataclass
class _Running:
    case: Case
    process: BaseProcess
    tmp: Path
    started: float


def _death(process: BaseProcess) -> str:
    code = process.exitcode
    if code is not None and code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"its worker process was killed ({name}); no result"
    return f"its worker process ended (exit code {code}) without a result"


def _start_method(cases: list[Case]) -> multiprocessing.context.BaseContext:
    """A ``forkserver`` context preloading the runner and the cases' kind modules (``spawn``
    where there is none). A server left from an earlier run keeps its own preloads (a missing
    module is then imported by the case process: slower, same result)."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(sorted({__name__, *(case.kind.module for case in cases)}))
    return context


def _stop_server(context: multiprocessing.context.BaseContext) -> None:
    """Stop the forkserver and wait for it, so its CPU time and that of the case processes it
    reaped count as this process's children (``getrusage``), and the next run preloads its own
    kinds (the standard library has no public call for this; without it the server ends with
    this process)."""
    server = getattr(multiprocessing.forkserver, "_forkserver", None)
    if context.get_start_method() == "forkserver" and hasattr(server, "_stop"):
        server._stop()


def run_in_processes(
    cases: list[Case],
    out_root: Path,
    jobs: int,
    quick: bool,
    events: EventSink,
    verbose: bool,
    scheduler: str | None = None,
) -> list[CaseResult]:
    """Run ``cases``, ``jobs`` at a time, each in its own process; never raises for a case.
    ``scheduler`` (the CLI's ``--scheduler``) reaches each case as ``ctx.scheduler``."""
    mp = _start_method(cases)
    q = mp.Queue()
    todo = list(cases)
    running: dict[str, _Running] = {}
    got: dict[str, CaseResult] = {}
    results: list[CaseResult] = []

    def drain(wait: float) -> None:
        try:
            while True:
                what, payload = q.get(timeout=wait)
                wait = 0.0
                if what == "event":
                    events(payload)
                else:
                    got[payload.name] = payload
        except queue_mod.Empty:
            return

    def end(name: str, result: CaseResult) -> None:
        results.append(result)
        events(ProgressEvent(name, "end", result.status, result=result))

    try:
        while todo or running:
            while todo and len(running) < jobs:
                case = todo.pop(0)
                tmp = partial_folder(out_root, case.name)
                module = case.kind.module
                args = (case.directory, tmp, quick, module, verbose, q, scheduler, case.full)
                process = mp.Process(target=_child, args=args, name=f"case-{case.name}")
                process.start()
                running[case.name] = _Running(case, process, tmp, time.monotonic())
                events(ProgressEvent(case.name, "start", case.started(quick)))
            drain(0.2)
            for name, run in list(running.items()):
                limit = (run.case.spec.timeout_s or float("inf")) + GRACE_S
                if run.process.is_alive() and time.monotonic() - run.started > limit:
                    run.process.kill()
                    run.process.join()
                    got.pop(name, None)
                    shutil.rmtree(run.tmp, ignore_errors=True)
                    del running[name]
                    reason = f"killed after {limit:g} s (timeout_s {run.case.spec.timeout_s:g} s)"
                    end(name, failure_folder(out_root, name, run.case.kind.name, reason))
                    continue
                if run.process.is_alive():
                    continue
                run.process.join()
                drain(0.0)  # a result sent just before the exit
                del running[name]
                if name in got:
                    end(name, place_result(run.tmp, out_root / name, got.pop(name)))
                else:
                    shutil.rmtree(run.tmp, ignore_errors=True)
                    reason = _death(run.process)
                    end(name, failure_folder(out_root, name, run.case.kind.name, reason))
    finally:  # interrupted (Ctrl-C): stop the workers, leave no temporary folders
        for run in running.values():
            run.process.kill()
            run.process.join()
            shutil.rmtree(run.tmp, ignore_errors=True)
        q.close()
        _stop_server(mp)
    return results
