"""Executing one case: a temporary result folder, the case's log, its time limit, the move
into place (whole or nothing), and the clean-up of folders left by killed runs.

A case that raises, diverges or times out is reported ``ERROR`` with its reason; its result
folder then holds only ``report.md`` (the reason), ``error.log`` (log and traceback) and
``result.json``, none of the partial outputs.
"""

from __future__ import annotations

import contextlib
import logging
import os
import resource
import shutil
import signal
import threading
import time
import traceback
import uuid
from collections.abc import Iterator
from dataclasses import replace
from pathlib import Path

from oocyte_fe.errors import InputError
from oocyte_fe.progress import reporting
from oocyte_fe.runner.casefile import Case
from oocyte_fe.runner.progress import EventSink, ProgressEvent, Throttle, ignore
from oocyte_fe.runner.registry import CaseContext
from oocyte_fe.runner.report import (
    evaluate_checks,
    misses,
    write_case_report,
    write_failure_report,
)
from oocyte_fe.runner.result import CaseResult


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
    if str(out_root) == "":
        raise InputError("--out", "", "a folder name (use --out . for the current folder)")
    try:
        out_root.mkdir(parents=True, exist_ok=True)
        probe = out_root / f".write-test-{uuid.uuid4().hex}"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise InputError(out_root, "--out", "a writable output folder", got=exc.strerror) from None


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's live process
        return True
    return True


def clean_stale(out_root: Path) -> list[Path]:
    """Remove ``.NAME.partial-PID-*`` / ``.NAME.old-PID-*`` folders of runs no longer alive."""
    removed = []
    for path in out_root.glob(".*.*-*-*"):
        tag = path.name.rsplit(".", 1)[-1]
        what, _, rest = tag.partition("-")
        pid = rest.partition("-")[0]
        if what in ("partial", "old") and pid.isdigit() and not _pid_alive(int(pid)):
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
    return removed


def partial_folder(out_root: Path, name: str) -> Path:
    """A fresh temporary result folder for ``out_root/<name>`` (renamed into place later).

    Its name carries this process's id, so a later run removes it once the process is gone.
    """
    tmp = out_root / f".{name}.partial-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    tmp.mkdir(parents=True)
    return tmp


def swap_into_place(tmp: Path, final: Path) -> None:
    """Replace ``final`` by ``tmp`` (two renames; the old folder is removed after)."""
    old = final.with_name(f".{final.name}.old-{os.getpid()}-{uuid.uuid4().hex[:8]}")
    if final.exists():
        final.rename(old)
    try:
        tmp.rename(final)
    except OSError:
        if old.exists():
            old.rename(final)  # put the previous result back
        raise
    shutil.rmtree(old, ignore_errors=True)


def place_result(tmp: Path, final: Path, result: CaseResult) -> CaseResult:
    """Move a finished case into place; a failure is that case's ERROR, never the run's."""
    try:
        swap_into_place(tmp, final)
    except OSError as exc:
        reason = (
            f"finished ({result.status}) but its folder could not be moved into place "
            f"({exc.strerror or exc}): the result is in {tmp} until the next run"
        )
        return replace(result, status="ERROR", reason=reason)
    return result


def _case_logger(name: str, log_file: Path) -> tuple[logging.Logger, logging.Handler]:
    logger = logging.getLogger(f"oocyte_fe.case.{name}.{uuid.uuid4().hex[:6]}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handler = logging.FileHandler(log_file)
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    logger.addHandler(handler)
    return logger, handler


def quiet_vtk(log_file: Path | None) -> None:
    """Keep VTK's warnings (``bad X server connection`` of off-screen rendering) off stderr;
    ``log_file`` (``--verbose``) receives them instead."""
    try:
        from vtkmodules.vtkCommonCore import vtkLogger
    except ImportError:  # pragma: no cover - vtk comes with pyvista
        return
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    if log_file is not None:
        vtkLogger.LogToFile(str(log_file), vtkLogger.APPEND, vtkLogger.VERBOSITY_WARNING)


def _context(
    case: Case,
    tmp: Path,
    quick: bool,
    logger: logging.Logger,
    events: EventSink,
    scheduler: str | None = None,
):
    stage = {"now": "started"}

    def on_step(message: str) -> None:
        stage["now"] = message
        events(ProgressEvent(case.name, "stage", message))

    def on_progress(done: int, total: int, what: str | None) -> None:
        events(ProgressEvent(case.name, "count", what or stage["now"], int(done), int(total)))

    return CaseContext(
        name=case.name,
        case_dir=case.directory,
        out_dir=tmp,
        inputs=case.inputs,
        quick=quick,
        log=logger,
        scheduler=scheduler,
        notify=on_step,
        on_progress=on_progress,
    )


def execute_case(
    case: Case,
    tmp: Path,
    quick: bool = False,
    events: EventSink = ignore,
    verbose: bool = False,
    scheduler: str | None = None,
) -> CaseResult:
    """Run one validated case with ``tmp`` as its result folder; never raises for a case failure.

    ``scheduler`` (the CLI's ``--scheduler``) reaches the kind as ``ctx.scheduler``.

    Writes ``result.json`` beside the report. On failure ``tmp`` is emptied and holds only
    ``report.md`` (the reason), ``error.log`` and ``result.json``.
    """
    logger, handler = _case_logger(case.name, tmp / "log.txt")
    quiet_vtk(tmp / "vtk.log" if verbose else None)
    ctx = _context(case, tmp, quick, logger, Throttle(events), scheduler)
    start, cpu_start = time.perf_counter(), cpu_seconds()
    try:
        logger.info(case.started(quick))
        with _time_limit(case.spec.timeout_s, logger), reporting(ctx.progress):
            outcome = case.kind.run(ctx)
        checks = [] if outcome.skipped else evaluate_checks(case, outcome)
        seconds, cpu = time.perf_counter() - start, cpu_seconds() - cpu_start
        logger.info("finished in %.2f s (%.2f CPU s)", seconds, cpu)
        handler.close()
        status = write_case_report(case, outcome, checks, tmp, seconds)
        failed = [c.name for c in checks if c.status == "FAIL"]
        missed = [c.name for c in checks if c.status == "MISS"]
        reason = outcome.skipped or "; ".join(
            part
            for part in (
                "failed: " + ", ".join(failed) if failed else "",
                "documented miss: " + ", ".join(missed) if missed else "",
            )
            if part
        )
        result = CaseResult(
            case.name,
            case.kind.name,
            status,
            sum(c.status == "PASS" for c in checks),
            len(checks),
            seconds,
            reason,
            misses(checks),
            cpu,
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
    result.write(tmp)
    return result


def cpu_seconds() -> float:
    """CPU time of this process (all threads) and of its children it waited for, s."""
    own, children = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def failure_folder(out_root: Path, name: str, kind: str, reason: str) -> CaseResult:
    """Put an ERROR folder for a case that could not run (invalid, or its process died)."""
    result = CaseResult(name, kind, "ERROR", 0, 0, 0.0, reason)
    tmp = partial_folder(out_root, name)
    write_failure_report(name, kind, reason, tmp)
    result.write(tmp)
    return place_result(tmp, out_root / name, result)
