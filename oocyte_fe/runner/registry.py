"""The case-kind registry: one dict, filled by the :func:`case_kind` decorator.

A case kind is a plain function ``run(ctx: CaseContext) -> CaseOutcome`` plus its input
schema (a subclass of :class:`oocyte_fe.runner.schema.CaseInputs`: strict types, finite
numbers, no unknown keys) and the names of the metrics it reports.
Kinds for ``afm``, ``nmsd`` and ``oocyte_fe`` live in :mod:`oocyte_fe.kinds`, one module each;
they call the plain library functions of those packages (``afm`` and ``nmsd`` never import
``oocyte_fe``).
"""

from __future__ import annotations

import difflib
import functools
import importlib
import importlib.util
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import BaseModel

from oocyte_fe.errors import InputError
from oocyte_fe.runner.schema import CaseInputs

_KINDS: dict[str, CaseKind] = {}
_BUILTINS = "oocyte_fe.kinds"
_BATCH_RUNNERS = {"sweep": "oocyte_fe.sweep.run:run_sweeps"}
"""Runners of cases that hold a table of many runs (``[sweep]``), by table; resolved at call
time, so the layers import one way: the sweep builds on case execution, not the reverse."""


@dataclass(frozen=True)
class Figure:
    """A figure file written by a kind into ``ctx.out_dir`` and its caption."""

    file: str
    caption: str


@dataclass(frozen=True)
class Check:
    """A pass/fail comparison shown in the report (computed vs reference vs tolerance)."""

    name: str
    computed: float
    passed: bool
    tolerance: str
    reference: float | None = None
    source: str | None = None
    unit: str | None = None
    status: str = ""
    """``PASS``, ``MISS`` (a documented known miss) or ``FAIL``; from ``passed`` if not given."""
    remark: str = ""
    """The tolerance's note, or the distance and reason of a known miss (shown below the table)."""

    def __post_init__(self) -> None:
        if not self.status:
            object.__setattr__(self, "status", "PASS" if self.passed else "FAIL")

    @property
    def deviation(self) -> str:
        if self.reference is None:
            return ""
        diff = self.computed - self.reference
        if self.reference != 0:
            return f"{diff:+.4g} ({100 * diff / abs(self.reference):+.2f} %)"
        return f"{diff:+.4g}"


@dataclass
class CaseOutcome:
    """What a kind returns: scalar metrics, figures, extra report sections and checks.

    ``metrics`` holds numbers (or lists of numbers) in the internal unit system; the runner
    compares those named in the case's ``[tolerances]`` against ``[reference]``. ``checks``
    are comparisons the kind evaluates itself (for example over a whole curve).
    """

    metrics: dict[str, float | list[float]]
    figures: list[Figure] = field(default_factory=list)
    sections: list[tuple[str, str]] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    skipped: str = ""
    """Why the case did not run here (an external tool missing) and the line that installs it;
    the case is then ``SKIPPED``: its ``[tolerances]`` are not evaluated."""


@dataclass
class CaseContext:
    """Everything a running kind may use: its validated inputs and where to write."""

    name: str
    case_dir: Path
    out_dir: Path
    inputs: BaseModel
    quick: bool
    log: logging.Logger
    scheduler: str | None = None  # the CLI's --scheduler: a Dask address for kinds that use one
    notify: Callable[[str], None] = lambda _msg: None
    on_progress: Callable[[int, int, str | None], None] = lambda _done, _total, _stage: None

    def step(self, message: str) -> None:
        """Log a step and show it on the progress display (it becomes the current stage)."""
        self.log.info(message)
        self.notify(message)

    def progress(self, done: int, total: int, stage: str | None = None) -> None:
        """Report ``done`` of ``total`` units of the current stage (FE steps, evaluations...).

        ``stage`` (optional) names the counted work; the display shows a bar and an ETA.
        Cheap: call it once per unit of work.
        """
        self.on_progress(done, total, stage)

    def output(self, relative: str) -> Path:
        """Path of an output file inside the case's (temporary) result folder."""
        path = self.out_dir / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        return path


@dataclass(frozen=True)
class CaseKind:
    """A registered case kind."""

    name: str
    description: str
    inputs: type[BaseModel]
    metrics: Mapping[str, str]
    run: Callable[[CaseContext], CaseOutcome]
    templates: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    """Ready ``[inputs]`` tables by name, for ``oocyte-fe new KIND DIR --template NAME``."""

    @property
    def module(self) -> str:
        return self.run.__module__


def case_kind(
    name: str,
    *,
    inputs: type[BaseModel],
    metrics: Mapping[str, str],
    description: str = "",
    templates: Mapping[str, Mapping[str, Any]] | None = None,
) -> Callable[[Callable[[CaseContext], CaseOutcome]], Callable[[CaseContext], CaseOutcome]]:
    """Register ``run`` as the case kind ``name``.

    ``metrics`` maps each metric name the kind reports to a one-line description with its
    unit; case files may only name these in ``[reference]`` and ``[tolerances]``.
    ``templates`` are ready ``[inputs]`` tables by name (``oocyte-fe new --template``).
    """
    if not issubclass(inputs, CaseInputs):
        raise TypeError(
            f"case kind {name!r}: its inputs model must subclass "
            "oocyte_fe.runner.schema.CaseInputs (strict, finite, bounded inputs)"
        )

    def register(run: Callable[[CaseContext], CaseOutcome]) -> Callable[[CaseContext], CaseOutcome]:
        existing = _KINDS.get(name)
        if existing is not None and existing.module != run.__module__:
            raise ValueError(f"case kind {name!r} is already registered by {existing.module}")
        text = description or ((run.__doc__ or "").strip().splitlines() or [""])[0]
        _KINDS[name] = CaseKind(
            name, text, inputs, dict(metrics), _naming_the_case_file(run), dict(templates or {})
        )
        return run

    return register


def _naming_the_case_file(
    run: Callable[[CaseContext], CaseOutcome],
) -> Callable[[CaseContext], CaseOutcome]:
    """``run`` with the argument errors it lets through (named ``<input>``, the
    libraries' placeholder for values passed from Python) re-raised as the case file's error:
    a case's user is told ``case.toml: inputs``, not a library's argument name alone."""

    @functools.wraps(run)
    def guarded(ctx: CaseContext) -> CaseOutcome:
        try:
            return run(ctx)
        except InputError as exc:
            if exc.file not in ("<input>", ""):
                raise  # it names a data file already
            where = f"inputs (passed on as argument {exc.field!r})"
            raise InputError(ctx.case_dir / "case.toml", where, exc.expected, exc.got) from None

    return guarded


def _load_builtins() -> None:
    importlib.import_module(_BUILTINS).import_all()


def _load_module_of(name: str) -> None:
    """Import the built-in module named like kind ``name``, if there is one."""
    if name.isidentifier() and importlib.util.find_spec(f"{_BUILTINS}.{name}") is not None:
        importlib.import_module(f"{_BUILTINS}.{name}")


def kinds() -> dict[str, CaseKind]:
    """All registered kinds, the built-in ones included."""
    _load_builtins()
    return dict(_KINDS)


def get_kind(name: str, file: str | Path = "case.toml", module: str | None = None) -> CaseKind:
    """Look a kind up by name; ``module`` is imported first (kinds registered outside)."""
    if module is not None:
        importlib.import_module(module)
    if name in _KINDS:
        return _KINDS[name]
    _load_module_of(name)
    if name in _KINDS:
        return _KINDS[name]
    known = kinds()
    if name not in known:
        close = difflib.get_close_matches(str(name), list(known), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InputError(file, "kind", f"one of {', '.join(sorted(known))}{hint}", got=name)
    return known[name]


def batch_runner(table: str) -> Callable[..., None]:
    """The runner for cases with the table ``table`` (``"sweep"``), imported on first use.

    It is called as ``runner(cases, out_root, events, scheduler, workers)`` and reports each
    case's end through ``events``.
    """
    module, _, name = _BATCH_RUNNERS[table].partition(":")
    return getattr(importlib.import_module(module), name)
