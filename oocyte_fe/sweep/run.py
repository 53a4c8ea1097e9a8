"""Running a sweep case: every sample of the design on Dask, then the aggregated report.

Each sample is the case's own kind run with the sampled values put at their input paths
(``[reference]``/``[tolerances]`` apply to the aggregated statistics, not to the samples).
A sample that raises is recorded with its reason (``ERROR``); a sample whose worker died
is ``LOST``; both are excluded from the statistics and counted, and the others run on.
Finished samples are never recomputed (see :mod:`oocyte_fe.sweep.store`).
"""

from __future__ import annotations

import shutil
import time
import traceback
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from pydantic import ValidationError

from oocyte_fe.runner.casefile import Case
from oocyte_fe.runner.execute import execute_case, partial_folder
from oocyte_fe.runner.progress import EventSink, ProgressEvent
from oocyte_fe.runner.report import (
    evaluate_checks,
    misses,
    write_case_report,
    write_failure_report,
)
from oocyte_fe.runner.result import CaseResult
from oocyte_fe.sweep.paths import PathError
from oocyte_fe.sweep.report import SampleRow, aggregate
from oocyte_fe.sweep.sampling import design
from oocyte_fe.sweep.spec import apply_values, error_field, resolved_inputs
from oocyte_fe.sweep.store import (
    SAMPLES,
    SampleRecord,
    read_sample,
    recover_samples,
    sample_key,
    write_status,
)

if TYPE_CHECKING:
    from distributed import Client


@dataclass(frozen=True)
class PlannedSample:
    """A row of the design: its key, values, unit point, and the case to run (or why not)."""

    key: str
    values: dict
    unit: np.ndarray
    case: Case | None
    error: str = ""


def plan_samples(case: Case) -> list[PlannedSample]:
    """The design of ``case``'s sweep with each row's inputs validated by the kind's model."""
    sweep = case.spec.sweep
    if sweep is None:
        raise ValueError(f"case {case.name} has no [sweep] table")
    d = design(sweep, case.quick)
    raw = case.raw_inputs
    base = resolved_inputs(case.inputs)
    spec = case.spec.model_copy(update={"reference": {}, "tolerances": {}, "sweep": None})
    planned = []
    for values, unit in zip(d.values, d.unit, strict=True):
        key = sample_key(case.kind.name, raw, values)
        try:
            inputs = case.kind.inputs.model_validate(
                apply_values(base, values), context={"case_dir": case.directory}
            )
        except ValidationError as exc:
            first = exc.errors()[0]
            loc, msg = error_field(first, "")
            where = f"inputs.{loc}" if loc else "inputs"
            planned.append(PlannedSample(key, values, unit, None, f"{where}: {msg}"))
            continue
        except PathError as exc:
            planned.append(PlannedSample(key, values, unit, None, str(exc).splitlines()[0]))
            continue
        sample = Case(key, case.directory, spec, case.kind, inputs, case.quick, case.full)
        planned.append(PlannedSample(key, values, unit, sample))
    return planned


def run_sample(case: Case, samples_dir: Path) -> SampleRecord:
    """Dask task: run one sample into ``samples_dir/<key>/`` (whole or not at all)."""
    tmp = partial_folder(samples_dir, case.name)
    result = execute_case(case, tmp, case.quick)
    write_status(tmp, case.name, result.status, result.seconds, result.reason)
    final = samples_dir / case.name
    if final.exists():  # the same values came twice (a list parameter): keep the first
        shutil.rmtree(tmp)
    else:
        tmp.rename(final)
    record = read_sample(final)
    assert record is not None
    return record


def run_samples(
    planned: list[PlannedSample],
    samples_dir: Path,
    client: Client,
    say: Callable[[str], None] = lambda _msg: None,
    count: Callable[[int, int], None] = lambda _done, _total: None,
) -> dict[str, SampleRecord]:
    """Records of every sample key: finished ones read back, the others run on ``client``."""
    from distributed import as_completed

    records: dict[str, SampleRecord] = {}
    todo: dict[str, Case] = {}
    for p in planned:
        if p.case is None:
            records[p.key] = SampleRecord(p.key, "ERROR", 0.0, f"invalid inputs: {p.error}")
            continue
        done = read_sample(samples_dir / p.key)
        if done is not None:
            records[p.key] = done
        else:
            todo[p.key] = p.case
    reused = len(records)
    say(f"{reused} samples reused, {len(todo)} to run")
    futures = {client.submit(run_sample, c, samples_dir, pure=False): k for k, c in todo.items()}
    finished = failed = 0
    for future in as_completed(futures):
        key = futures[future]
        try:
            records[key] = future.result()
        except Exception as exc:  # the worker died or the task could not run
            reason = f"lost: {type(exc).__name__}: {exc}".splitlines()[0]
            records[key] = SampleRecord(key, "LOST", 0.0, reason)
        finished += 1
        failed += not records[key].ok
        say(f"{finished}/{len(todo)} samples run ({failed} failed), {reused} reused")
        count(finished, len(todo))
    return records


def _swap_keeping_samples(tmp: Path, final: Path) -> None:
    """Put the new aggregate ``tmp`` in place of ``final``, moving ``final/samples`` across."""
    old = final.with_name(f".{final.name}.old-{uuid.uuid4().hex[:8]}")
    final.rename(old)
    (old / SAMPLES).rename(tmp / SAMPLES)
    tmp.rename(final)
    shutil.rmtree(old, ignore_errors=True)


def run_sweep(
    case: Case,
    out_root: Path,
    client: Client,
    notify: Callable[[str, str], None] | None = None,
    count: Callable[[int, int], None] = lambda _done, _total: None,
) -> CaseResult:
    """Run the sweep of ``case`` into ``out_root/<case>/``; never raises for a case failure.

    ``notify(case, message)`` receives stage messages, ``count(done, total)`` the samples run.
    """
    start = time.perf_counter()
    kind = case.kind.name

    def say(msg: str) -> None:
        if notify:
            notify(case.name, msg)

    samples_dir = recover_samples(out_root, case.name)
    tmp = partial_folder(out_root, case.name)
    try:
        planned = plan_samples(case)
        records = run_samples(planned, samples_dir, client, say, count)
        rows = [SampleRow(i, p.values, p.unit, records[p.key]) for i, p in enumerate(planned)]
        if rows and not any(r.ok for r in rows):
            first = records[planned[0].key].reason
            raise RuntimeError(f"all {len(rows)} samples failed, the first: {first}")
        say("aggregating")
        names = list(case.spec.sweep.parameters)  # type: ignore[union-attr]
        outcome = aggregate(case, rows, names, tmp)
        checks = evaluate_checks(case, outcome)
        seconds = time.perf_counter() - start
        status = write_case_report(case, outcome, checks, tmp, seconds)
        n_failed = int(outcome.metrics["n_failed"])  # type: ignore[arg-type]
        reasons = [c.name for c in checks if c.status == "FAIL"]
        reason = ("failed: " + ", ".join(reasons) + "; ") if reasons else ""
        if n_failed:
            reason += f"{n_failed} of {len(rows)} samples failed"
        result = CaseResult(
            case.name,
            kind,
            status,
            sum(c.status == "PASS" for c in checks),
            len(checks),
            seconds,
            reason.removesuffix("; "),
            misses(checks),
        )
    except Exception as exc:  # a sweep failure must never stop the other cases
        seconds = time.perf_counter() - start
        reason = f"{type(exc).__name__}: {exc}".splitlines()[0]
        shutil.rmtree(tmp)
        tmp.mkdir()
        (tmp / "error.log").write_text(traceback.format_exc())
        write_failure_report(case.name, kind, reason, tmp)
        result = CaseResult(case.name, kind, "ERROR", 0, 0, seconds, reason)
    result.write(tmp)
    _swap_keeping_samples(tmp, out_root / case.name)
    return result


def run_sweeps(
    cases: list[Case],
    out_root: Path,
    events: EventSink,
    scheduler: str | None = None,
    workers: int | None = None,
) -> None:
    """The case runner's batch runner for ``[sweep]`` cases: one Dask client for all of them."""
    from oocyte_fe.sweep.cluster import dask_client

    with dask_client(scheduler, workers) as client:
        for case in cases:
            events(ProgressEvent(case.name, "start", "planning samples"))

            def say(_name: str, msg: str, name: str = case.name) -> None:
                events(ProgressEvent(name, "stage", msg))

            def count(done: int, total: int, name: str = case.name) -> None:
                events(ProgressEvent(name, "count", "samples", done, total))

            result = run_sweep(case, out_root, client, say, count)
            events(ProgressEvent(case.name, "end", result.status, result=result))
