"""Showing a run: a live rich display in a terminal, plain lines in a log, a summary table.

The displays are event sinks (:mod:`oocyte_fe.runner.progress`). A display that fails (a closed
terminal, a broken pipe) switches itself off: the run and its ``summary.md`` go on.
"""

from __future__ import annotations

import time

from rich.console import Console
from rich.markup import escape
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)
from rich.table import Table

from oocyte_fe.runner.progress import ProgressEvent
from oocyte_fe.runner.report import summary_markdown
from oocyte_fe.runner.result import CaseResult

COLOUR = {"PASS": "green", "MISS": "yellow", "SKIPPED": "cyan", "FAIL": "red", "ERROR": "bold red"}


def _end_line(r: CaseResult) -> str:
    text = f"{r.status} {r.passed}/{r.total} checks, {r.seconds:.1f} s"
    return text + (f" ({r.reason})" if r.reason else "")


class PlainDisplay:
    """One line per case start, stage and end, with the run's and the case's elapsed time.

    ``verbose`` adds the step counters (at most one line per case every ``every`` seconds).
    """

    def __init__(self, console: Console, verbose: bool = False, every: float = 10.0) -> None:
        self.console = console
        self.verbose = verbose
        self.every = every
        self.t0 = time.monotonic()
        self.started: dict[str, float] = {}
        self.last_count: dict[str, float] = {}
        self.off = False

    def line(self, case: str, text: str) -> None:
        now = time.monotonic()
        case_s = now - self.started.get(case, now)
        stamp = f"[{now - self.t0:7.1f} s] {case} ({case_s:.1f} s): {text}"
        self.console.print(stamp, markup=False, highlight=False, soft_wrap=True)

    def __call__(self, event: ProgressEvent) -> None:
        if self.off:
            return
        try:
            self._show(event)
        except Exception:  # a display must never stop the run
            self.off = True

    def _show(self, ev: ProgressEvent) -> None:
        if ev.what == "start":
            self.started[ev.case] = time.monotonic()
            self.line(ev.case, ev.stage)
        elif ev.what == "stage":
            self.line(ev.case, ev.stage)
        elif ev.what == "count" and self.verbose:
            now = time.monotonic()
            if now - self.last_count.get(ev.case, 0.0) >= self.every or ev.done >= ev.total:
                self.last_count[ev.case] = now
                self.line(ev.case, f"{ev.stage} {ev.done}/{ev.total}")
        elif ev.what == "end" and ev.result is not None:
            self.line(ev.case, _end_line(ev.result))


class LiveDisplay:
    """A rich progress display: one bar per running case (stage, counter, elapsed, ETA)."""

    def __init__(self, console: Console, n_cases: int) -> None:
        self.console = console
        self.progress = Progress(
            TextColumn("[bold]{task.fields[case]}"),
            TextColumn("{task.description}"),
            BarColumn(bar_width=24),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
            console=console,
            transient=True,
            refresh_per_second=4,
        )
        self.total = self.progress.add_task("cases done", case="all", total=n_cases)
        self.tasks: dict[str, TaskID] = {}
        self.off = False

    def __enter__(self) -> LiveDisplay:
        self.progress.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        try:
            self.progress.stop()
        except Exception:
            pass

    def __call__(self, event: ProgressEvent) -> None:
        if self.off:
            return
        try:
            self._show(event)
        except Exception:  # a display must never stop the run
            self.off = True
            self.__exit__()

    def _show(self, ev: ProgressEvent) -> None:
        p = self.progress
        task = self.tasks.get(ev.case)
        if ev.what == "start" or task is None:
            self.tasks[ev.case] = p.add_task(escape(ev.stage), case=escape(ev.case), total=None)
            return
        if ev.what == "stage":
            p.reset(task, total=None, description=escape(ev.stage))
        elif ev.what == "count":
            current = next(t for t in p.tasks if t.id == task)
            if current.description != escape(ev.stage) or current.total != ev.total:
                p.reset(task, total=ev.total, description=escape(ev.stage))
            p.update(task, completed=ev.done)
        elif ev.what == "end" and ev.result is not None:
            p.remove_task(task)
            del self.tasks[ev.case]
            p.advance(self.total)
            colour = COLOUR.get(ev.result.status, "white")
            p.console.print(
                f"[{colour}]{ev.result.status:5s}[/] {escape(ev.case)}: "
                + escape(_end_line(ev.result).split(" ", 1)[1]),
                highlight=False,
            )


def summary_table(results: list[CaseResult], console: Console) -> None:
    """Print the summary: a table in a wide terminal, one block per case in a narrow one,
    Markdown when the output is not a terminal. Case names are never cut."""
    if not console.is_terminal:
        console.print(summary_markdown(results), markup=False, highlight=False, soft_wrap=True)
        return
    name_w = max((len(r.name) for r in results), default=4)
    kind_w = max((len(r.kind) for r in results), default=4)
    if console.width >= name_w + kind_w + 50:
        table = Table(title="Validation summary")
        table.add_column("case", no_wrap=True)
        table.add_column("kind", no_wrap=True)
        for col in ("status", "checks", "time (s)"):
            table.add_column(col, no_wrap=True)
        table.add_column("reason", overflow="fold")
        for r in results:
            table.add_row(
                escape(r.name),
                escape(r.kind),
                f"[{COLOUR[r.status]}]{r.status}[/]",
                f"{r.passed}/{r.total}",
                f"{r.seconds:.1f}",
                escape(r.reason),
            )
        console.print(table)
    else:
        console.print("[bold]Validation summary[/]")
        for r in results:
            console.print(f"[{COLOUR[r.status]}]{r.status}[/] [bold]{escape(r.name)}[/]")
            console.print(
                f"    {escape(r.kind)}, {r.passed}/{r.total} checks, {r.seconds:.1f} s",
                highlight=False,
            )
            if r.reason:
                console.print(f"    {escape(r.reason)}", highlight=False)
    documented = [(r.name, m) for r in results for m in r.misses]
    if documented:
        console.print("[bold]Documented misses[/] (not failures):")
        for name, m in documented:
            console.print(f"  {escape(name)}: {escape(m)}", highlight=False)
