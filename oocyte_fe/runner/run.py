"""Running cases: plan them, run each (one process per case with ``jobs > 1``), keep the
summary current.

Each case runs in a temporary folder renamed into place at the end (whole or nothing,
:mod:`oocyte_fe.runner.execute`); a failing case never stops the others. With ``jobs > 1``
each case runs in its own process (:mod:`oocyte_fe.runner.workers`): a process that dies costs
only its own case. ``summary.md`` and ``index.html`` are rebuilt, atomically, from the case
folders present after every finished case. Cases with a ``[sweep]`` table go to the
registry's batch runner (the sweep builds on case execution; this module never imports it).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import CASE_FILE, Case, discover, load_case
from oocyte_fe.runner.execute import (
    check_writable,
    clean_stale,
    execute_case,
    failure_folder,
    partial_folder,
    place_result,
)
from oocyte_fe.runner.progress import EventSink, Guarded, ProgressEvent, ignore
from oocyte_fe.runner.registry import batch_runner
from oocyte_fe.runner.report import write_summary
from oocyte_fe.runner.result import CaseResult, read_result
from oocyte_fe.runner.workers import run_in_processes

__all__ = [  # execute_case and partial_folder: kept importable from here for older callers
    "CaseResult",
    "RunPlan",
    "execute_case",
    "partial_folder",
    "plan",
    "run_cases",
    "run_one",
]


def run_one(
    case: Case,
    out_root: Path,
    quick: bool = False,
    events: EventSink = ignore,
    verbose: bool = False,
    scheduler: str | None = None,
) -> CaseResult:
    """Run one validated case into ``out_root/<case name>/``; never raises for a case failure.
    ``scheduler`` (the CLI's ``--scheduler``) reaches the kind as ``ctx.scheduler``."""
    events(ProgressEvent(case.name, "start", case.started(quick)))
    tmp = partial_folder(out_root, case.name)
    result = execute_case(case, tmp, quick, events, verbose, scheduler)
    result = place_result(tmp, out_root / case.name, result)
    events(ProgressEvent(case.name, "end", result.status, result=result))
    return result


@dataclass(frozen=True)
class RunPlan:
    """Cases found under the given paths: the valid ones, and those that failed to load."""

    cases: list[Case]
    invalid: list[tuple[str, str]]  # (case name, one-line error)
    skipped: list[str] = field(default_factory=list)  # heavy cases left out (no --full)
    declared: dict[str, str] = field(default_factory=dict)  # an invalid case's kind, if named


def declared_kind(folder: Path) -> str:
    """The ``kind`` a case file names, as written (``?`` where the file does not say, or
    cannot be read: the file's fault is the case's error, reported by :func:`load_case`)."""
    try:
        kind = checks.read_toml(folder / CASE_FILE).get("kind")
    except InputError:
        return "?"
    return kind if isinstance(kind, str) and kind else "?"


def plan(
    paths: list[Path], only: list[str] | None = None, quick: bool = False, full: bool = False
) -> RunPlan:
    """Discover and validate cases. A malformed case is listed as invalid, not fatal.

    ``full`` loads every case with its ``[full]`` overrides and includes the cases marked
    ``heavy = true``; without it those are skipped unless named in ``only`` or given as a case
    folder of their own.
    """
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
    named = {p.resolve() for p in paths if (p / CASE_FILE).is_file()}
    cases, invalid, skipped = [], [], []
    declared: dict[str, str] = {}
    for folder in folders:
        try:
            case = load_case(folder, quick=quick, full=full)
        except InputError as exc:
            invalid.append((folder.name, str(exc)))
            declared[folder.name] = declared_kind(folder)
            continue
        if case.spec.heavy and not (full or only or folder.resolve() in named):
            skipped.append(case.name)
        else:
            cases.append(case)
    return RunPlan(cases, invalid, skipped, declared)


def default_jobs() -> int:
    """Cases run at once by default: one per core the process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def longest_first(cases: list[Case], out_root: Path) -> list[Case]:
    """Cases ordered by their last run time in ``out_root``, or their ``cost_s`` when they have
    not run there (longest first, so parallel runs end together, as CTest's COST property);
    cases with neither go first, in their given order."""

    def last_seconds(case: Case) -> float:
        found = read_result(out_root / case.name)
        if found is not None:
            return found.seconds
        return case.spec.cost_s if case.spec.cost_s is not None else math.inf

    return sorted(cases, key=last_seconds, reverse=True)


def run_cases(
    run_plan: RunPlan,
    out_root: Path,
    *,
    jobs: int = 1,
    quick: bool = False,
    events: EventSink = ignore,
    scheduler: str | None = None,
    workers: int | None = None,
    verbose: bool = False,
) -> list[CaseResult]:
    """Run every case of the plan, ``jobs`` at a time; write ``summary.md``; return results.

    Cases with a ``[sweep]`` table run after the others, through the registry's batch runner
    (:func:`oocyte_fe.sweep.run.run_sweeps`), their samples on Dask: a local cluster of
    ``workers`` processes (one per core by default) or the ``scheduler`` address. The other
    cases get ``scheduler`` as ``ctx.scheduler`` (the VOF kind sends its OpenFOAM runs there).
    """
    check_writable(out_root)
    clean_stale(out_root)
    results = [
        failure_folder(out_root, n, run_plan.declared.get(n, "?"), f"invalid case: {e}")
        for n, e in run_plan.invalid
    ]

    show = Guarded(events)

    def finished(event: ProgressEvent) -> None:
        show(event)
        if event.what == "end" and event.result is not None:
            results.append(event.result)
            write_summary(results, out_root)

    write_summary(results, out_root)
    plain = longest_first([c for c in run_plan.cases if c.spec.sweep is None], out_root)
    sweeps = [c for c in run_plan.cases if c.spec.sweep is not None]
    if jobs <= 1 or len(plain) <= 1:
        for case in plain:
            run_one(case, out_root, quick, finished, verbose, scheduler)
    else:
        run_in_processes(plain, out_root, jobs, quick, finished, verbose, scheduler)
    if sweeps:
        batch_runner("sweep")(sweeps, out_root, finished, scheduler, workers)
    write_summary(results, out_root)
    order = {c.name: i for i, c in enumerate(run_plan.cases)}
    return sorted(results, key=lambda r: (order.get(r.name, -1), r.name))
