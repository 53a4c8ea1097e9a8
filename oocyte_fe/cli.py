"""The ``oocyte-fe`` command line: thin wrappers over :mod:`oocyte_fe.runner`.

``oocyte-fe run PATH... [--scheduler ADDRESS]``, ``oocyte-fe validate PATH...``,
``oocyte-fe kinds``. Bad input is one line on stderr naming the file, the field and the
expectation, exit code 2 (``--debug`` shows the traceback). ``run`` exits 0 only when every
check of every case passes.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer
from rich.console import Console
from rich.live import Live
from rich.table import Table

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import discover, load_case
from oocyte_fe.runner.registry import kinds as registered_kinds
from oocyte_fe.runner.run import CaseResult, plan, run_cases

app = typer.Typer(add_completion=False, no_args_is_help=True, help="oocyte-fe validation cases.")
console = Console()
err_console = Console(stderr=True)


def _fail(exc: Exception, debug: bool) -> typer.Exit:
    if debug:
        raise exc
    err_console.print(f"[bold red]error:[/] {exc}", highlight=False, soft_wrap=True)
    return typer.Exit(2)


def _summary_table(results: list[CaseResult]) -> Table:
    table = Table(title="Validation summary")
    for col in ("case", "kind", "status", "checks", "time (s)", "reason"):
        table.add_column(col)
    colour = {"PASS": "green", "FAIL": "yellow", "ERROR": "red"}
    for r in results:
        table.add_row(
            r.name,
            r.kind,
            f"[{colour[r.status]}]{r.status}[/]",
            f"{r.passed}/{r.total}",
            f"{r.seconds:.1f}",
            r.reason,
        )
    return table


@app.command()
def run(
    paths: list[Path] = typer.Argument(..., help="Case folders, or folders of cases."),
    only: list[str] = typer.Option(None, "--only", help="Run only this case (repeatable)."),
    list_: bool = typer.Option(False, "--list", help="List the cases found and stop."),
    out: Path = typer.Option(Path("results"), "--out", help="Results folder."),
    jobs: int = typer.Option(1, "-j", "--jobs", min=1, help="Cases run in parallel processes."),
    quick: bool = typer.Option(False, "--quick", help="Coarse settings (the [quick] table)."),
    scheduler: str = typer.Option(
        None, "--scheduler", help="Dask scheduler address for sweeps (default: local cluster)."
    ),
    workers: int = typer.Option(
        None, "--workers", min=1, help="Worker processes of the local sweep cluster (one per core)."
    ),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Run validation cases; write results/<case>/ and results/summary.md.

    Cases with a [sweep] table run their samples on Dask (docs/sweeps.md).
    """
    try:
        run_plan = plan(paths, only=only, quick=quick)
    except InputError as exc:
        raise _fail(exc, debug) from None
    if list_:
        for case in run_plan.cases:
            console.print(f"{case.name:32s} {case.kind.name:28s} {case.spec.description}")
        for name, err in run_plan.invalid:
            console.print(f"{name:32s} [red]INVALID[/] {err}", highlight=False)
        raise typer.Exit(0 if not run_plan.invalid else 2)
    for name, err in run_plan.invalid:
        err_console.print(f"[bold red]invalid case {name}:[/] {err}", highlight=False)
    steps: dict[str, str] = {c.name: "waiting" for c in run_plan.cases}

    def progress_table() -> Table:
        table = Table(show_header=False, box=None)
        for name, step in steps.items():
            table.add_row(name, step)
        return table

    try:
        with Live(progress_table(), console=console, transient=True, refresh_per_second=4) as live:

            def notify(name: str, msg: str) -> None:
                steps[name] = msg
                live.update(progress_table())

            results = run_cases(
                run_plan,
                out,
                jobs=jobs,
                quick=quick,
                notify=notify,
                scheduler=scheduler,
                workers=workers,
            )
    except InputError as exc:
        raise _fail(exc, debug) from None
    console.print(_summary_table(results))
    console.print(f"Results in {out}/ (summary: {out / 'summary.md'})")
    raise typer.Exit(0 if all(r.ok for r in results) else 1)


@app.command()
def validate(
    paths: list[Path] = typer.Argument(..., help="Case folders, or folders of cases."),
    quick: bool = typer.Option(False, "--quick", help="Also check the [quick] overrides."),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Check case files without running them."""
    try:
        folders = discover(paths)
    except InputError as exc:
        raise _fail(exc, debug) from None
    bad = 0
    for folder in folders:
        try:
            case = load_case(folder, quick=quick)
            console.print(f"[green]ok[/]      {folder.name} ({case.kind.name})")
        except InputError as exc:
            if debug:
                raise
            bad += 1
            err_console.print(f"[red]invalid[/] {exc}", highlight=False, soft_wrap=True)
    raise typer.Exit(2 if bad else 0)


@app.command("kinds")
def list_kinds() -> None:
    """List the registered case kinds, their inputs and metrics."""
    for kind in registered_kinds().values():
        console.print(f"[bold]{kind.name}[/]: {kind.description}")
        for name, field in kind.inputs.model_fields.items():
            req = "required" if field.is_required() else f"default {field.default!r}"
            console.print(f"    input  {name}: {field.description or ''} ({req})", highlight=False)
        for name, desc in kind.metrics.items():
            console.print(f"    metric {name}: {desc}", highlight=False)


def main() -> None:
    """Console-script entry point."""
    app(prog_name="oocyte-fe")


if __name__ == "__main__":
    sys.exit(main())
