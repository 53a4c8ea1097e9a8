"""Running cases: each in a temporary folder renamed into place at the end (whole or nothing).

A case that raises, diverges or times out is reported ``ERROR`` with its reason; its result
folder then holds only ``report.md`` (the reason) and ``error.log`` (log and traceback), none of
the partial outputs. The other cases run on and keep their results.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
import shutil
import signal
import threading
import time
import traceback
import uuid
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import Case, discover, load_case
from oocyte_fe.runner.registry import CaseContext
from oocyte_fe.runner.report import (
    evaluate_checks,
    write_case_report,
    write_failure_report,
    write_summary,
)

Notify = Callable[[str, str], None]
"""Progress callback: ``notify(case_name, message)``."""


@dataclass(frozen=True)
class CaseResult:
    """The outcome of one case as the summary shows it."""

    name: str
    kind: str
    status: str  # PASS, FAIL or ERROR
    passed: int
    total: int
    seconds: float
    reason: str = ""

    @property
    def ok(self) -> bool:
        return self.status == "PASS"


class CaseTimeout(Exception):
    """Raised inside a case that ran past its ``timeout_s``."""


@contextlib.contextmanager
def _time_limit(seconds: float | None, log: logging.Logger) -> Iterator[None]:
    if not seconds:
        yield
        return
    if threading.current_thread() is not threading.main_thread():
        # SIGALRM reaches the main thread only (a Dask worker runs tasks in a thread)
        log.warning("timeout_s = %g s not enforced outside the main thread", seconds)
        yield
        return

    def _alarm(_signum: int, _frame: object) -> None:
        raise CaseTimeout(f"timed out after {seconds:g} s (timeout_s in case.toml)")

    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def check_writable(out_root: Path) -> None:
    """Fail early, with the folder named, when results cannot be written."""
    try:
        out_root.mkdir(parents=True, exist_ok=True)
        probe = out_root / f".write-test-{uuid.uuid4().hex}"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise InputError(out_root, "--out", "a writable output folder", got=exc.strerror) from None


def swap_into_place(tmp: Path, final: Path) -> None:
    """Replace ``final`` by ``tmp`` (two renames; the old folder is removed after)."""
    old = final.with_name(f".{final.name}.old-{uuid.uuid4().hex[:8]}")
    if final.exists():
        final.rename(old)
    tmp.rename(final)
    shutil.rmtree(old, ignore_errors=True)


def _case_logger(name: str, log_file: Path) -> tuple[logging.Logger, logging.Handler]:
    logger = logging.getLogger(f"oocyte_fe.case.{name}.{uuid.uuid4().hex[:6]}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handler = logging.FileHandler(log_file)
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    logger.addHandler(handler)
    return logger, handler


def execute_case(
    case: Case, tmp: Path, quick: bool = False, notify: Notify | None = None
) -> CaseResult:
    """Run one validated case with ``tmp`` as its result folder; never raises for a case failure.

    On failure ``tmp`` is emptied and holds only ``report.md`` (the reason) and ``error.log``.
    """
    logger, handler = _case_logger(case.name, tmp / "log.txt")
    ctx = CaseContext(
        name=case.name,
        case_dir=case.directory,
        out_dir=tmp,
        inputs=case.inputs,
        quick=quick,
        log=logger,
        notify=(lambda msg: notify(case.name, msg)) if notify else (lambda _msg: None),
    )
    start = time.perf_counter()
    try:
        ctx.step("started" + (" (quick)" if quick else ""))
        with _time_limit(case.spec.timeout_s, logger):
            outcome = case.kind.run(ctx)
        checks = evaluate_checks(case, outcome)
        seconds = time.perf_counter() - start
        logger.info("finished in %.2f s", seconds)
        handler.close()
        status = write_case_report(case, outcome, checks, tmp, seconds)
        result = CaseResult(
            case.name,
            case.kind.name,
            status,
            sum(c.passed for c in checks),
            len(checks),
            seconds,
            ""
            if status == "PASS"
            else "failed: " + ", ".join(c.name for c in checks if not c.passed),
        )
    except Exception as exc:  # a case failure must never stop the other cases
        seconds = time.perf_counter() - start
        reason = f"{type(exc).__name__}: {exc}".splitlines()[0]
        logger.error("case failed: %s", reason)
        handler.close()
        log_text = (tmp / "log.txt").read_text() if (tmp / "log.txt").exists() else ""
        shutil.rmtree(tmp)
        tmp.mkdir()
        (tmp / "error.log").write_text(log_text + "\n" + traceback.format_exc())
        write_failure_report(case.name, case.kind.name, reason, tmp)
        result = CaseResult(case.name, case.kind.name, "ERROR", 0, 0, seconds, reason)
    finally:
        logger.removeHandler(handler)
    return result


def partial_folder(out_root: Path, name: str) -> Path:
    """A fresh temporary result folder for ``out_root/<name>`` (renamed into place later)."""
    tmp = out_root / f".{name}.partial-{uuid.uuid4().hex[:8]}"
    tmp.mkdir(parents=True)
    return tmp


def run_case(
    case: Case, out_root: Path, quick: bool = False, notify: Notify | None = None
) -> CaseResult:
    """Run one validated case into ``out_root/<case name>/``; never raises for a case failure."""
    tmp = partial_folder(out_root, case.name)
    result = execute_case(case, tmp, quick, notify)
    swap_into_place(tmp, out_root / case.name)
    return result


def _run_in_worker(
    directory: Path, out_root: Path, quick: bool, kind_module: str, queue: object
) -> CaseResult:
    """Process-pool entry point: reload the case in the worker and run it."""
    case = load_case(directory, quick=quick, kind_module=kind_module)
    return run_case(case, out_root, quick, lambda name, msg: queue.put((name, msg)))  # type: ignore[attr-defined]


@dataclass(frozen=True)
class RunPlan:
    """Cases found under the given paths: the valid ones, and those that failed to load."""

    cases: list[Case]
    invalid: list[tuple[str, str]]  # (case name, one-line error)


def plan(paths: list[Path], only: list[str] | None = None, quick: bool = False) -> RunPlan:
    """Discover and validate cases. A malformed case is listed as invalid, not fatal."""
    folders = discover(paths)
    if only:
        unknown = sorted(set(only) - {f.name for f in folders})
        if unknown:
            raise InputError(
                "--only",
                unknown[0],
                f"one of the cases found: {', '.join(f.name for f in folders)}",
            )
        folders = [f for f in folders if f.name in only]
    cases, invalid = [], []
    for folder in folders:
        try:
            cases.append(load_case(folder, quick=quick))
        except InputError as exc:
            invalid.append((folder.name, str(exc)))
    return RunPlan(cases, invalid)


def run_cases(
    run_plan: RunPlan,
    out_root: Path,
    *,
    jobs: int = 1,
    quick: bool = False,
    notify: Notify | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
) -> list[CaseResult]:
    """Run every case of the plan, ``jobs`` at a time; write ``summary.md``; return results.

    Cases with a ``[sweep]`` table run after the others, their samples on Dask: a local
    cluster of ``workers`` processes (one per core by default) or the ``scheduler`` address.
    """
    check_writable(out_root)
    results = [CaseResult(name, "?", "ERROR", 0, 0, 0.0, err) for name, err in run_plan.invalid]
    plain = [c for c in run_plan.cases if c.spec.sweep is None]
    sweeps = [c for c in run_plan.cases if c.spec.sweep is not None]
    if jobs <= 1 or len(plain) <= 1:
        for case in plain:
            results.append(run_case(case, out_root, quick, notify))
    else:
        results.extend(_run_parallel(plain, out_root, jobs, quick, notify))
    if sweeps:
        results.extend(_run_sweeps(sweeps, out_root, notify, scheduler, workers))
    order = {c.name: i for i, c in enumerate(run_plan.cases)}
    results.sort(key=lambda r: (order.get(r.name, -1), r.name))
    write_summary(results, out_root)
    return results


def _run_sweeps(
    cases: list[Case],
    out_root: Path,
    notify: Notify | None,
    scheduler: str | None,
    workers: int | None,
) -> list[CaseResult]:
    from oocyte_fe.sweep.cluster import dask_client
    from oocyte_fe.sweep.run import run_sweep

    with dask_client(scheduler, workers) as client:
        return [run_sweep(case, out_root, client, notify) for case in cases]


def _run_parallel(
    cases: list[Case], out_root: Path, jobs: int, quick: bool, notify: Notify | None
) -> list[CaseResult]:
    ctx = multiprocessing.get_context("spawn")
    results = []
    with ctx.Manager() as manager:
        queue = manager.Queue()
        with ProcessPoolExecutor(
            max_workers=min(jobs, os.cpu_count() or 1), mp_context=ctx
        ) as pool:
            futures = {
                pool.submit(_run_in_worker, c.directory, out_root, quick, c.kind.module, queue): c
                for c in cases
            }
            pending = set(futures)
            while pending:
                done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
                while not queue.empty():
                    name, msg = queue.get()
                    if notify:
                        notify(name, msg)
                for fut in done:
                    case = futures[fut]
                    try:
                        results.append(fut.result())
                    except Exception as exc:  # the worker itself died
                        reason = f"{type(exc).__name__}: {exc}".splitlines()[0]
                        results.append(
                            CaseResult(case.name, case.kind.name, "ERROR", 0, 0, 0.0, reason)
                        )
    return results
