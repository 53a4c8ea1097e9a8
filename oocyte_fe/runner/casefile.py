"""Reading and validating ``case.toml``: every error names the file, the field and the expectation.

The format (see ``docs/cases.md``)::

    kind = "afm_zp_cytoplasm"          # a registered case kind
    description = "..."
    reading = "..."                    # optional: how an ambiguous paper was read
    timeout_s = 600                    # optional (default 1800 s)
    cost_s = 90                        # optional: typical run time, orders a first run
    heavy = true                       # optional: a heavy extra, run only with --full
    [inputs]   ...                     # checked against the kind's schema
    [quick]    ...                     # optional: input overrides for ``--quick``
    [full]     ...                     # optional: input overrides for ``--full`` (fine meshes)
    [reference.NAME]  value = 7.01, source = "seed 001, Section 3.1", unit = "kPa"
    [tolerances.NAME] rel = 0.05       # or abs, min, max (any combination)
    [sweep]    ...                     # optional: a parameter sweep (see docs/sweeps.md)

A case with a ``[sweep]`` table names aggregated metrics (``METRIC.mean``, ``.sd``, ``.p05``,
``.p50``, ``.p95``, ``n_ok``, ``n_failed``) in ``[reference]`` and ``[tolerances]``.
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from types import UnionType
from typing import Annotated, Any, Literal, NoReturn, Union, get_args, get_origin

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.runner.registry import CaseKind, get_kind
from oocyte_fe.runner.schema import DataFile, RuleBroken, readers_of
from oocyte_fe.sweep.spec import SweepSpec, check_sweep, resolved_inputs, sweep_metric_names

CASE_FILE = "case.toml"
DEFAULT_TIMEOUT_S = 1800.0
"""A case without ``timeout_s`` stops after this many seconds (30 min), reported ERROR."""


MAX_DEPTH = 16
"""Deepest nesting of tables and arrays accepted in ``case.toml``."""
MAX_TIMEOUT_S = 30 * 86400.0

__all__ = ["DataFile", "Case", "CaseSpec", "load_case", "read_toml", "discover"]


class Reference(BaseModel):
    """A figure to compare with, and where it comes from."""

    model_config = ConfigDict(extra="forbid")
    value: float = Field(description="the reference value, in `unit`")
    source: str = Field(min_length=1, description="seed table or analytic formula")
    unit: str | None = None


class Tolerance(BaseModel):
    """How close a metric must be: ``rel``/``abs`` to its reference, or ``min``/``max`` bounds.

    A goal the model cannot reach for a documented reason is declared with ``known_miss``
    (the reason) and ``worst`` (the value, or for ``rel``/``abs`` the deviation
    ``|computed - reference|``, beyond which the miss counts as a regression): such a check
    is ``MISS`` while the value lies between the goal and ``worst``, ``FAIL`` beyond
    ``worst``, and ``PASS`` with the advice to remove ``known_miss`` once the goal is met.
    """

    model_config = ConfigDict(extra="forbid")
    rel: float | None = Field(default=None, ge=0)
    abs: float | None = Field(default=None, ge=0)
    min: float | None = None
    max: float | None = None
    note: str | None = None
    known_miss: str | None = Field(
        default=None, min_length=1, description="why the goal is not reached (documented)"
    )
    worst: float | None = Field(
        default=None, description="the value (deviation for rel/abs) past which a miss FAILs"
    )

    @model_validator(mode="after")
    def _one_given(self) -> Tolerance:
        bounds = (self.rel, self.abs, self.min, self.max)
        if all(v is None for v in bounds):
            raise ValueError("at least one of rel, abs, min, max")
        if any(v is not None and not math.isfinite(v) for v in (*bounds, self.worst)):
            raise ValueError("finite numbers for rel, abs, min, max and worst")
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError("min <= max")
        if (self.known_miss is None) != (self.worst is None):
            raise ValueError("known_miss and worst together (the reason and the regression bound)")
        if self.worst is not None:
            self._check_worst(self.worst)
        return self

    def _check_worst(self, worst: float) -> None:
        sides = [self.min is not None, self.max is not None, self.needs_reference]
        if sum(sides) != 1:
            raise ValueError("known_miss with one kind of goal: min, max, or rel/abs")
        if self.max is not None and worst <= self.max:
            raise ValueError(f"worst above the goal max = {self.max:g}")
        if self.min is not None and worst >= self.min:
            raise ValueError(f"worst below the goal min = {self.min:g}")
        if self.needs_reference and worst <= 0:
            raise ValueError("worst > 0 (the largest deviation |computed - reference| allowed)")

    @property
    def needs_reference(self) -> bool:
        return self.rel is not None or self.abs is not None

    def describe(self) -> str:
        parts = []
        if self.rel is not None:
            parts.append(f"rel <= {self.rel:g}")
        if self.abs is not None:
            parts.append(f"abs <= {self.abs:g}")
        if self.min is not None:
            parts.append(f">= {self.min:g}")
        if self.max is not None:
            parts.append(f"<= {self.max:g}")
        return ", ".join(parts)

    def accepts(self, computed: float, reference: float | None) -> bool:
        if not math.isfinite(computed):
            return False
        ok = True
        if reference is not None:
            err = abs(computed - reference)
            if self.rel is not None:
                ok &= err <= self.rel * abs(reference)
            if self.abs is not None:
                ok &= err <= self.abs
        if self.min is not None:
            ok &= computed >= self.min
        if self.max is not None:
            ok &= computed <= self.max
        return bool(ok)

    def judge(self, computed: float, reference: float | None) -> tuple[str, str]:
        """``(status, remark)``: ``PASS``, ``MISS`` (documented, within ``worst``) or ``FAIL``.

        The remark of a miss gives the distance to the goal; a known miss whose goal is met
        passes with "now passes: remove known_miss".
        """
        if self.accepts(computed, reference):
            return "PASS", "now passes: remove known_miss" if self.known_miss else ""
        if self.known_miss is None or self.worst is None or not math.isfinite(computed):
            return "FAIL", ""
        if self.max is not None:
            over, beyond = computed - self.max, computed > self.worst
            distance = f"{over:.3g} above the goal {self.describe()}"
            if self.max > 0:
                distance += f" ({computed / self.max:.3g} x)"
        elif self.min is not None:
            over, beyond = self.min - computed, computed < self.worst
            distance = f"{over:.3g} below the goal {self.describe()}"
        else:
            assert reference is not None
            dev = abs(computed - reference)
            limits = [self.rel * abs(reference)] if self.rel is not None else []
            limits += [self.abs] if self.abs is not None else []
            over, beyond = dev - min(limits), dev > self.worst
            distance = f"deviation {dev:.3g}, {over:.3g} past the goal {self.describe()}"
        if beyond:
            return "FAIL", f"regression: worse than worst = {self.worst:g} ({distance})"
        return "MISS", f"known miss, {distance}: {self.known_miss}"


class CaseSpec(BaseModel):
    """The top level of ``case.toml``."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)
    kind: str = Field(min_length=1)
    description: str = Field(min_length=1)
    reading: str | None = None
    heavy: bool = Field(default=False, strict=True, description="run only with --full/--only")
    timeout_s: float | None = Field(
        default=DEFAULT_TIMEOUT_S, gt=0, le=MAX_TIMEOUT_S, strict=True, description="limit, s"
    )
    cost_s: float | None = Field(
        default=None,
        gt=0,
        le=MAX_TIMEOUT_S,
        strict=True,
        description="typical run time, s: cases never run before start longest first by it",
    )
    inputs: dict[str, Any] = Field(default_factory=dict)
    quick: dict[str, Any] = Field(default_factory=dict)
    full: dict[str, Any] = Field(default_factory=dict)
    reference: dict[str, Reference] = Field(default_factory=dict)
    tolerances: dict[str, Tolerance] = Field(default_factory=dict)
    sweep: SweepSpec | None = None


@dataclass(frozen=True)
class Case:
    """A validated case, ready to run (``quick``/``full``: loaded with the ``[quick]``/``[full]``
    overrides)."""

    name: str
    directory: Path
    spec: CaseSpec
    kind: CaseKind
    inputs: BaseModel
    quick: bool = False
    full: bool = False

    @property
    def raw_inputs(self) -> dict[str, Any]:
        """``[inputs]`` as written, with the overrides this case was loaded with."""
        return overridden(self.spec, self.quick, self.full)

    @property
    def file(self) -> Path:
        return self.directory / CASE_FILE

    def started(self, quick: bool) -> str:
        """``started``, with the override tables the run uses: ``started (quick, full)``."""
        tables = ", ".join(name for name, on in (("quick", quick), ("full", self.full)) if on)
        return f"started ({tables})" if tables else "started"


def _loc(loc: tuple[Any, ...]) -> str:
    return ".".join(str(p) for p in loc) if loc else "(top level)"


def _walk(model: type[BaseModel] | None, loc: tuple[Any, ...]) -> tuple[list[str], tuple]:
    """Follow pydantic's error location ``loc`` through ``model``: (the field names of the
    (sub-)model it ends in, for "did you mean"; ``loc`` without the tags pydantic adds for
    the member of a union, such as ``sphere`` in ``tools.probe.sphere.radius_um``, which the
    file does not have). Where the walk cannot follow, no names and ``loc`` as it is."""
    current: Any = model
    shown: list[Any] = []
    for i, part in enumerate(loc):
        rest = (*shown, *loc[i:])  # where the walk stops: the location from here as it is
        while get_origin(current) is Annotated:
            current = get_args(current)[0]
        origin = get_origin(current)
        if isinstance(current, type) and issubclass(current, BaseModel):
            if not isinstance(part, str) or part not in current.model_fields:
                return [], rest
            current = current.model_fields[part].annotation
        elif origin is dict:
            current = get_args(current)[1]
        elif origin in (list, tuple):
            current = get_args(current)[0]
        elif origin in (Union, UnionType):
            tagged = [m for m, tags in map(_member, get_args(current)) if part in tags]
            if len(tagged) == 1:
                current = tagged[0]
                continue  # the union's tag (sphere, inline, file): not a key of the file
            return [], rest
        else:
            return [], rest
        shown.append(part)
    while get_origin(current) is Annotated:
        current = get_args(current)[0]
    if isinstance(current, type) and issubclass(current, BaseModel):
        return list(current.model_fields), tuple(shown)
    return [], tuple(shown)


def _member(annotation: Any) -> tuple[type, set[str]]:
    """A union member without its ``Annotated`` wrapper, and the tags it answers to (its
    ``Tag``, the literal values of its fields, its class name)."""
    tags: set[str] = set()
    while get_origin(annotation) is Annotated:
        annotation, *meta = get_args(annotation)
        tags |= {str(m.tag) for m in meta if hasattr(m, "tag")}
    if not isinstance(annotation, type):
        return type(None), tags
    if issubclass(annotation, BaseModel):
        tags |= {
            str(value)
            for info in annotation.model_fields.values()
            if get_origin(info.annotation) is Literal
            for value in get_args(info.annotation)
        }
    return annotation, tags | {annotation.__name__}


def _misplaced_input(file: Path, raw: dict, err: ValidationError, kind_module: str | None) -> None:
    """An unknown top-level key that is an input of the case's kind (written above the first
    ``[inputs...]`` table header, or after a table's end): one line saying where it goes."""
    unknown = [e["loc"][0] for e in err.errors() if e["type"] == "extra_forbidden"]
    if not unknown or len(err.errors()[0]["loc"]) != 1 or not isinstance(raw.get("kind"), str):
        return
    try:
        inputs = get_kind(raw["kind"], file, module=kind_module).inputs.model_fields
    except InputError:
        return  # the kind's own error is named by the schema
    key = str(unknown[0])
    if key in inputs:
        raise InputError(
            file,
            key,
            f"no such key at the top level: {key!r} is an input, write it in the [inputs] "
            f"table (inputs.{key}: a bare key belongs to the table whose header is above it)",
        )


def did_you_mean(word: str, known: list[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``known``, or ``""``."""
    close = difflib.get_close_matches(str(word), known, n=1, cutoff=0.6)
    close = close or [k for k in known if k.startswith(f"{word}_")][:1]  # E -> E_kPa
    return f" (did you mean {close[0]!r}?)" if close else ""


def raise_validation_error(
    file: Path | str, err: ValidationError, prefix: str = "", model: type[BaseModel] | None = None
) -> NoReturn:
    """Turn the first pydantic error into one :class:`InputError` line.

    ``model`` (the validated class) lets an unknown key get a "did you mean" suggestion.
    """
    errors = sorted(err.errors(), key=lambda e: e["type"] != "extra_forbidden")  # typos first
    first = errors[0]
    raw_loc = tuple(first["loc"])
    _, loc = _walk(model, raw_loc)
    field = prefix + _loc(loc) if loc or not prefix else prefix.rstrip(".")
    kind = first["type"]
    broken = first.get("ctx", {}).get("error")
    if isinstance(broken, RuleBroken):  # a cross-field rule names its own field
        field = prefix + _loc((*loc, broken.field))
        raise InputError(file, field, broken.expected, got=broken.got) from None
    if kind == "missing":
        raise InputError(file, field, "this key (it is required)") from None
    if kind == "extra_forbidden":
        hint = did_you_mean(str(loc[-1]), _walk(model, raw_loc[:-1])[0]) if loc else ""
        raise InputError(file, field, f"no such key (unknown key){hint}") from None
    msg = first["msg"].removeprefix("Value error, ").removeprefix("Input should be ")
    if msg.startswith(("greater", "less")):
        msg = "a value " + msg
    more = len(errors) - 1
    expected = msg[0].lower() + msg[1:] if msg else "a valid value"
    if more:
        expected += f" (and {more} more error{'s' if more > 1 else ''})"
    got = first.get("input")
    if isinstance(got, dict) and "type =" in expected and "type" in got:  # a type's typo
        field, got = f"{field}.type", got["type"]
        named = re.findall(r"[a-z][a-z_]+", expected.split("type =", 1)[1])
        expected += did_you_mean(str(got), [w for w in named if w not in ("one", "of", "or")])
    if isinstance(got, dict | list | tuple) and len(repr(got)) > 80:
        got = None  # a whole table is no help in a one-line message
    raise InputError(file, field, expected, got=got) from None


def _check_values(file: Path, raw: Any) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH` and non-finite floats anywhere in the file.

    Iterative (no recursion), so a 2 000-deep array is one clear line, not a RecursionError.
    """
    stack: list[tuple[str, Any, int]] = [("", raw, 0)]
    while stack:
        where, value, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise InputError(file, where, f"tables and arrays nested at most {MAX_DEPTH} deep")
        if isinstance(value, float) and not math.isfinite(value):
            raise InputError(file, where, "a finite number (inf and nan are not accepted)", value)
        if isinstance(value, dict):
            stack.extend(
                (f"{where}.{k}" if where else str(k), v, depth + 1) for k, v in value.items()
            )
        elif isinstance(value, list):
            stack.extend((f"{where}.{i}", v, depth + 1) for i, v in enumerate(value))


def read_toml(file: Path) -> dict[str, Any]:
    """Read a TOML file safely (:mod:`oocyte_fe.checks`); every fault is one line."""
    text = checks.read_text(file)
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(file, "", f"valid TOML ({exc})") from None
    except RecursionError:
        raise InputError(file, "", f"tables and arrays nested at most {MAX_DEPTH} deep") from None
    _check_values(file, raw)
    return raw


def _check_tables(file: Path, spec: CaseSpec) -> None:
    """Cross-field rules of ``[reference]`` and ``[tolerances]`` (bounds ordered, numbers real)."""
    for key, ref in spec.reference.items():
        if isinstance(ref.value, bool) or not math.isfinite(ref.value):
            raise InputError(file, f"reference.{key}.value", "a finite number", got=ref.value)
    for key, tol in spec.tolerances.items():
        for name in ("rel", "abs", "min", "max"):
            value = getattr(tol, name)
            if value is not None and (isinstance(value, bool) or not math.isfinite(value)):
                raise InputError(file, f"tolerances.{key}.{name}", "a finite number", got=value)
        if tol.min is not None and tol.max is not None and tol.min > tol.max:
            raise InputError(
                file, f"tolerances.{key}", "min <= max", got={"min": tol.min, "max": tol.max}
            )


NUMBER_KEYS = {"reference": ("value",), "tolerances": ("rel", "abs", "min", "max")}


def _raw_numbers(file: Path, raw: dict[str, Any]) -> None:
    """Numbers of ``[reference]``/``[tolerances]`` as TOML numbers: ``true`` would read as 1 and
    ``"0.1"`` as 0.1 in the (lax) models the runner shares."""
    for table, keys in NUMBER_KEYS.items():
        entries = raw.get(table, {})
        if not isinstance(entries, dict):
            raise InputError(file, table, f"a table ([{table}.NAME] entries)", got=entries)
        for key, entry in entries.items():
            for name in keys:
                value = entry.get(name) if isinstance(entry, dict) else None
                if value is not None and (
                    isinstance(value, bool) or not isinstance(value, int | float)
                ):
                    raise InputError(file, f"{table}.{key}.{name}", "a number", got=value)


def check_data_files(file: Path, inputs: BaseModel) -> None:
    """Read every data file of ``inputs`` with the reader ``run`` uses (:class:`DataReader`).

    An error of the reader names the data file and its column; the message adds the input
    that named the file. Nested input blocks are walked too.
    """
    for name, reader in readers_of(type(inputs)).items():
        path = getattr(inputs, name)
        if path is None:
            continue
        try:
            reader(path)
        except InputError as exc:
            raise InputError(
                f"{exc.file or path} (from {file.name}: inputs.{name})",
                exc.field,
                exc.expected,
                got=exc.got,
            ) from None
    for name in type(inputs).model_fields:
        value = getattr(inputs, name)
        if isinstance(value, BaseModel):
            check_data_files(file, value)


def overridden(spec: CaseSpec, quick: bool = False, full: bool = False) -> dict[str, Any]:
    """``[inputs]`` with ``[full]`` (if ``full``) and then ``[quick]`` (if ``quick``) merged over
    it: ``--quick --full`` runs the heavy cases on coarse settings."""
    return {**spec.inputs, **(spec.full if full else {}), **(spec.quick if quick else {})}


def load_case(
    directory: Path | str, quick: bool = False, kind_module: str | None = None, full: bool = False
) -> Case:
    """Read, validate and resolve one case folder.

    ``full`` merges the ``[full]`` table over ``[inputs]``, ``quick`` the ``[quick]`` table over
    both. Every override table is validated whichever is asked for (``validate`` sees them all).
    Data files are read with the readers ``run`` uses, so a case that loads has readable data.
    Raises :class:`InputError`.
    """
    directory = Path(directory)
    file = directory / CASE_FILE
    raw = read_toml(file)
    _raw_numbers(file, raw)
    if isinstance(raw.get("full"), bool):
        raise InputError(
            file,
            "full",
            "a [full] table of input overrides for --full (a case that runs only with --full "
            "says heavy = true)",
            got=raw["full"],
        )
    try:
        spec = CaseSpec.model_validate(raw)
    except ValidationError as exc:
        _misplaced_input(file, raw, exc, kind_module)
        raise_validation_error(file, exc, model=CaseSpec)
    _check_tables(file, spec)
    kind = get_kind(spec.kind, file, module=kind_module)
    metrics = sweep_metric_names(kind.metrics) if spec.sweep else kind.metrics
    for table in ("reference", "tolerances"):
        for key in getattr(spec, table):
            if key not in metrics:
                expected = f"a metric of kind {kind.name!r}: {', '.join(kind.metrics)}"
                if spec.sweep:
                    stats = "METRIC.(mean|sd|p05|p50|p95), n_ok or n_failed"
                    expected = f"a sweep statistic {stats}; {expected}"
                raise InputError(
                    file, f"{table}.{key}", expected + did_you_mean(key, list(metrics))
                )
    for key, tol in spec.tolerances.items():
        if tol.needs_reference and key not in spec.reference:
            raise InputError(file, f"tolerances.{key}", f"a [reference.{key}] to be relative to")
    for table in ("quick", "full"):
        unknown = set(getattr(spec, table)) - set(kind.inputs.model_fields)
        if unknown:
            key = sorted(unknown)[0]
            hint = did_you_mean(key, list(kind.inputs.model_fields))
            raise InputError(file, f"{table}.{key}", f"a key of [inputs] to override{hint}")
    # the asked-for merge first (it is the one used), then each override table alone, so that
    # `validate` sees them all; a bad value is named in the table it comes from
    tables = [(overridden(spec, quick, full), quick, full)] + [
        (overridden(spec, **{name: True}), name == "quick", name == "full")
        for name in ("quick", "full")
        if getattr(spec, name) and overridden(spec, **{name: True}) != overridden(spec, quick, full)
    ]
    validated = []
    for data, with_quick, with_full in tables:
        try:
            validated.append(kind.inputs.model_validate(data, context={"case_dir": directory}))
        except ValidationError as exc:
            loc = exc.errors()[0]["loc"]
            key = str(loc[0]) if loc else ""
            table = (
                "quick"
                if with_quick and key in spec.quick
                else "full"
                if with_full and key in spec.full
                else "inputs"
            )
            raise_validation_error(file, exc, prefix=f"{table}.", model=kind.inputs)
    inputs = validated[0]
    check_data_files(file, inputs)
    if spec.sweep:
        check_sweep(
            str(file),
            spec.sweep,
            kind.name,
            kind.metrics,
            resolved_inputs(inputs),
            lambda d: kind.inputs.model_validate(d, context={"case_dir": directory}),
        )
    return Case(directory.name, directory, spec, kind, inputs, quick, full)


def discover(paths: list[Path]) -> list[Path]:
    """Case folders under ``paths``: a folder with ``case.toml``, or the folders below one."""
    found: list[Path] = []
    for path in paths:
        try:
            if (path / CASE_FILE).is_file():
                found.append(path)
            elif path.is_dir():
                found.extend(sorted(p.parent for p in path.glob(f"*/{CASE_FILE}")))
            else:
                raise InputError(path, "", "a case folder (with case.toml) or a folder of cases")
        except OSError as exc:  # a name too long, a loop, no permission
            raise InputError(path, "", "a readable case folder", got=exc.strerror) from None
    if not found:
        raise InputError(", ".join(map(str, paths)), "", "at least one case folder with case.toml")
    names = [p.name for p in found]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise InputError(sorted(dupes)[0], "", "case folder names to be unique (results/<name>/)")
    return found
