"""The ``oocyte-fe`` command line: thin wrappers over :mod:`oocyte_fe.runner`, one function
per command (``run``, ``validate``, ``kinds``, ``new``, ``track``).

Bad input is one line on stderr naming the file, the field and the expectation, exit code 2
(``--debug`` shows the traceback). ``run`` exits 0 when every case passes or misses only
documented goals (``known_miss``), 1 when a check fails or a case errors. Each command imports
what it uses when it runs (``track`` does not load the case runner).
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer
from rich.console import Console
from rich.markup import escape

from oocyte_fe import __version__
from oocyte_fe.errors import InputError

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    rich_markup_mode=None,  # help texts show [sweep], [quick] literally
    context_settings={"help_option_names": ["-h", "--help"]},
    help="oocyte-fe validation cases: run, validate, list kinds, start a case of your own.",
)
console = Console()
err_console = Console(stderr=True)


def _fail(exc: Exception, debug: bool) -> typer.Exit:
    if debug:
        raise exc
    err_console.print(f"[bold red]error:[/] {escape(str(exc))}", highlight=False, soft_wrap=True)
    return typer.Exit(2)


def _version(value: bool) -> None:
    if value:
        console.print(f"oocyte-fe {__version__}", highlight=False)
        raise typer.Exit(0)


@app.callback()
def main_options(
    version: bool = typer.Option(
        False, "--version", callback=_version, is_eager=True, help="Show the version and exit."
    ),
) -> None:
    """oocyte-fe validation cases: run, validate, list kinds, start a case of your own."""


@app.command()
def run(
    paths: list[Path] = typer.Argument(..., help="Case folders, or folders of cases."),
    only: list[str] = typer.Option(None, "--only", help="Run only this case (repeatable)."),
    list_: bool = typer.Option(False, "--list", help="List the cases found and stop."),
    out: str = typer.Option("results", "--out", help="Results folder ('.' for the current one)."),
    jobs: int = typer.Option(
        None, "-j", "--jobs", min=1, help="Cases run at once, one process each (default: cores)."
    ),
    quick: bool = typer.Option(False, "--quick", help="Coarse settings (the [quick] table)."),
    full: bool = typer.Option(
        False,
        "--full",
        help="The heavy extras too: the [full] overrides (fine meshes) and the heavy = true cases.",
    ),
    quiet: bool = typer.Option(False, "-q", "--quiet", help="No progress; the summary only."),
    verbose: bool = typer.Option(
        False, "-v", "--verbose", help="Step counters in the log lines; VTK warnings to vtk.log."
    ),
    scheduler: str = typer.Option(
        None,
        "--scheduler",
        help="Dask scheduler address for sweeps and VOF runs (default: local cluster).",
    ),
    workers: int = typer.Option(
        None, "--workers", min=1, help="Worker processes of the local sweep cluster (one per core)."
    ),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Run validation cases; write results/<case>/ and results/summary.md (and index.html).

    Cases with a [sweep] table run their samples on Dask (docs/sweeps.md).
    """
    from oocyte_fe.runner.display import LiveDisplay, PlainDisplay, summary_table
    from oocyte_fe.runner.progress import ignore
    from oocyte_fe.runner.run import default_jobs, plan, run_cases

    if not out.strip():
        raise _fail(InputError("--out", "", "a folder name ('.' for the current folder)"), debug)
    out_root = Path(out)
    try:
        run_plan = plan(paths, only=only, quick=quick, full=full)
    except InputError as exc:
        raise _fail(exc, debug) from None
    if list_:
        for case in run_plan.cases:
            # one line a case: cut to the terminal's width there, whole in a file or pipe
            console.print(
                f"{case.name:32s} {case.kind.name:28s} {escape(case.spec.description)}",
                highlight=False,
                no_wrap=True,
                overflow="ellipsis" if console.is_terminal else "ignore",
                crop=console.is_terminal,
            )
        for name in run_plan.skipped:
            console.print(f"{name:32s} [dim]heavy (run with --full)[/]", highlight=False)
        for name, err in run_plan.invalid:
            console.print(f"{name:32s} [red]INVALID[/] {escape(err)}", highlight=False)
        raise typer.Exit(0 if not run_plan.invalid else 2)
    for name, err in run_plan.invalid:
        err_console.print(f"[bold red]invalid case {name}:[/] {escape(err)}", highlight=False)
    if run_plan.skipped and not quiet:
        console.print(f"Not run (heavy, add --full): {', '.join(run_plan.skipped)}")
    n = len(run_plan.cases)
    live = console.is_terminal and not quiet and not verbose
    display = (
        ignore
        if quiet
        else LiveDisplay(console, n)
        if live
        else PlainDisplay(console, verbose=verbose)
    )
    options = {
        "jobs": jobs or default_jobs(),
        "quick": quick,
        "scheduler": scheduler,
        "workers": workers,
        "verbose": verbose,
    }
    try:
        if isinstance(display, LiveDisplay):
            with display:
                results = run_cases(run_plan, out_root, events=display, **options)
        else:
            results = run_cases(run_plan, out_root, events=display, **options)
    except InputError as exc:
        raise _fail(exc, debug) from None
    summary_table(results, console)
    console.print(f"Results in {out_root}/ (summary: {out_root / 'summary.md'}, index.html)")
    raise typer.Exit(0 if all(r.ok for r in results) else 1)


@app.command()
def validate(
    paths: list[Path] = typer.Argument(..., help="Case folders, or folders of cases."),
    quick: bool = typer.Option(False, "--quick", help="Also check the [quick] overrides."),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Check case files without running them."""
    from oocyte_fe.runner.casefile import discover, load_case

    try:
        folders = discover(paths)
    except InputError as exc:
        raise _fail(exc, debug) from None
    bad = 0
    for folder in folders:
        try:
            case = load_case(folder, quick=quick)
            console.print(f"[green]ok[/]      {folder.name} ({case.kind.name})", highlight=False)
        except InputError as exc:
            if debug:
                raise
            bad += 1
            msg = f"[red]invalid[/] {escape(str(exc))}"
            err_console.print(msg, highlight=False, soft_wrap=True)
    raise typer.Exit(2 if bad else 0)


@app.command("kinds")
def list_kinds(
    kind: str = typer.Argument(None, help="Show this kind only, with every input and metric."),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """List the registered case kinds (or one kind: inputs with unit, default, description)."""
    from oocyte_fe.runner.registry import get_kind
    from oocyte_fe.runner.registry import kinds as registered_kinds
    from oocyte_fe.runner.scaffold import describe_kind

    if kind is None:
        for k in registered_kinds().values():
            console.print(f"[bold]{k.name}[/]: {escape(k.description)}", highlight=False)
        console.print("Details of one kind: oocyte-fe kinds KIND", highlight=False)
        return
    try:
        found = get_kind(kind, "oocyte-fe kinds")
    except InputError as exc:
        raise _fail(exc, debug) from None
    for line in describe_kind(found):
        console.print(line, markup=False, highlight=False, soft_wrap=True)


@app.command()
def new(
    kind: str = typer.Argument(..., help="The case kind (oocyte-fe kinds lists them)."),
    folder: str = typer.Argument(..., help="The case folder to write (must not hold a case)."),
    template: str = typer.Option(
        None, "--template", help="A ready experiment of the kind (fe_experiment: plates, ...)."
    ),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Write a case folder for KIND: case.toml with every input and data-file templates."""
    from oocyte_fe.runner.registry import get_kind
    from oocyte_fe.runner.scaffold import new_case

    try:
        if not folder.strip():  # Path("") is "." : an empty name would write here unasked
            raise InputError("FOLDER", "folder", "a folder name (use . for this folder)", folder)
        written = new_case(get_kind(kind, "oocyte-fe new"), Path(folder), template)
    except InputError as exc:
        raise _fail(exc, debug) from None
    for path in written:
        console.print(f"wrote {path}", highlight=False)
    console.print(
        f"Edit {Path(folder) / 'case.toml'}, then: oocyte-fe run {folder}", highlight=False
    )


@app.command()
def track(
    video: str = typer.Argument(..., help="A TIFF stack, video or GIF of the oocyte."),
    box: str = typer.Option(..., "--box", help="The spindle on frame 0: X,Y,W,H in px."),
    out: Path = typer.Option(Path("track"), "--out", help="Folder for the outputs."),
    pixel_um: float = typer.Option(0.227, "--pixel-um", help="Pixel size in um."),
    fps: float = typer.Option(10.0, "--fps", help="Frame rate of the recording (frames/s)."),
    truth: str = typer.Option(
        None, "--truth", help="Ground-truth boxes CSV (x_px, y_px, w_px, h_px): adds OTB plots."
    ),
    tracker: str = typer.Option(
        "mfakcf",
        "--tracker",
        help="mfakcf (default), or an option for turning (signature, rotation), growing "
        "(scale) or fast-pushed (moving) spindles; docs/tracking.md.",
    ),
    max_speed: float = typer.Option(
        20.0,
        "--max-speed",
        help="Largest spindle speed (um/s): how far from where it was lost a target is taken back.",
    ),
    debug: bool = typer.Option(False, "--debug", help="Show tracebacks."),
) -> None:
    """Follow the spindle with MFAKCF: track.csv, overlay.gif, trajectory.png (docs/tracking.md)."""
    from oocyte_fe.tracking.cli_track import track_video  # the tracker loads only when used

    try:
        summary = track_video(
            video, box, out, pixel_um=pixel_um, fps=fps, truth=truth, tracker=tracker,
            max_speed_um_s=max_speed,
        )  # fmt: skip
    except InputError as exc:
        raise _fail(exc, debug) from None
    for key, value in summary.items():
        console.print(f"{key} = {value:.4g}", highlight=False)
    console.print(f"wrote {out}/track.csv, overlay.gif, trajectory.png", highlight=False)


def main() -> None:
    """Console-script entry point."""
    app(prog_name="oocyte-fe")


if __name__ == "__main__":
    sys.exit(main())
