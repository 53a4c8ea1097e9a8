"""The base of every case kind's input model: strict types, finite and bounded numbers, safe files.

A kind's inputs subclass :class:`CaseInputs` (the registry refuses any other model), so each
rule below holds for every kind, a new one included, without a line of its own:

* unknown keys are refused (``extra = "forbid"``);
* types are strict: ``true`` is not a number, ``"yes"`` is not a boolean, ``2.5`` is not an
  integer, ``"1"`` is not a number (TOML arrays are accepted for tuple fields);
* every float, also inside lists, tuples and tables, is finite (``inf``, ``nan``, ``1e400``
  refused) and of magnitude at most :data:`MAX_ABS` unless the field sets its own bound with
  ``json_schema_extra={"max_abs": ...}`` (``1e308`` would overflow the first product);
* a float whose field declares a unit of :data:`UNIT_BOUNDS` (kPa, um, s, nN, nN/um, N/m,
  Pa s, Pa, hPa), list elements included, is 0 or of a magnitude within the physical bounds of its
  quantity (:data:`oocyte_fe.checks.QUANTITIES`): a modulus of ``1e-320`` kPa is refused with
  the bound named, not divided by later;
* a float whose field names its quantity (``json_schema_extra={"unit": "deg", "quantity":
  "cone_half_angle_deg"}``, a key of :data:`oocyte_fe.checks.QUANTITIES`) lies within that
  quantity's bounds, 0 included in the refusal: for quantities a unit does not identify (an
  angle may be a cone's half angle or a position on the cell);
* cross-field rules are declared on the model (``rules = (Relation(...), Refining(...),
  Setup(...))``, see :class:`Relation`), checked after the fields and reported against the
  field they name; the fuzz suite reads the declarations and breaks each rule;
* a :data:`DataFile` lies inside the case folder and is a regular UTF-8 file; a field made with
  :func:`data_file` is also *read* at validation with the reader ``run`` uses, so
  ``validate`` finds an empty, binary or wrong-column file, not the run.

Documentation convention (``oocyte-fe kinds`` and ``oocyte-fe new`` read it)::

    E0_kPa: float = Field(7.0, gt=0, description="instantaneous modulus",
                          json_schema_extra={"unit": "kPa"})

with ``unit = "1"`` for dimensionless numbers and no unit for strings, paths and booleans.
"""

from __future__ import annotations

import math
import operator
import typing
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, ClassVar, Literal, Self

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic.fields import FieldInfo

from oocyte_fe import checks
from oocyte_fe.errors import InputError

MAX_ABS = 1.0e12
"""Largest magnitude of a float input unless its field says otherwise (``max_abs``)."""


def _extra(info: FieldInfo) -> dict[str, Any]:
    extra = info.json_schema_extra
    return extra if isinstance(extra, dict) else {}


def unit_of(info: FieldInfo) -> str | None:
    """The unit a field declares (``json_schema_extra={"unit": ...}``), or ``None``."""
    unit = _extra(info).get("unit")
    return str(unit) if unit is not None else None


UNIT_BOUNDS: dict[str, tuple[float, float]] = {
    unit: (checks.QUANTITIES[quantity][0] * per, checks.QUANTITIES[quantity][1] * per)
    for unit, quantity, per in (
        ("kPa", "modulus_kPa", 1.0),
        ("um", "length_um", 1.0),
        ("s", "time_s", 1.0),
        ("nN", "force_nN", 1.0),
        ("nN/um", "stiffness_nN_per_um", 1.0),
        ("N/m", "stiffness_nN_per_um", 1e-3),
        ("Pa s", "viscosity_kPa_s", 1e3),
        ("Pa", "pressure_kPa", 1e3),
        ("hPa", "pressure_kPa", 10.0),
    )
}
"""Unit of a case input -> (smallest, largest) non-zero magnitude, from the physical bounds of
:data:`oocyte_fe.checks.QUANTITIES` (converted: 1 kPa s = 1e3 Pa s, 1 kPa = 10 hPa, 1 N/m =
1e3 nN/um, so a spring constant lies in [1e-12, 1e9] N/m)."""


def _first_outside(value: Any, low: float, high: float, signed: bool = False) -> float | None:
    """The first float in ``value`` (nested lists, tuples, dicts) that is neither 0 nor of a
    magnitude in ``[low, high]`` (``signed``: that is not itself in ``[low, high]``)."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, float):
            inside = low <= item <= high if signed else item == 0 or low <= abs(item) <= high
            if not inside:
                return item
        elif isinstance(item, list | tuple):
            stack.extend(item)
        elif isinstance(item, dict):
            stack.extend(item.values())
    return None


class RuleBroken(ValueError):
    """A cross-field rule that failed; ``field`` is the input it names (in its own block)."""

    def __init__(self, field: str, expected: str, got: object = None) -> None:
        super().__init__(f"{field}: {expected}")
        self.field = field
        self.expected = expected
        self.got = got


OPS: dict[str, Callable[[float, float], bool]] = {
    "<": operator.lt,
    "<=": operator.le,
    ">": operator.gt,
    ">=": operator.ge,
}
MEASURES: dict[str, Callable[[Any], float]] = {
    "value": float,
    "norm": lambda v: math.hypot(*v),
    "max": max,
}
"""What of a field a :class:`Relation` compares: the number, the length of a point (from the
origin of its frame), the largest element of a list."""


@dataclass(frozen=True)
class Relation:
    """Cross-field rule ``measure(field) op bound(inputs)``, for example a pipette travel
    below the cell's diameter less the gap: ``Relation("travel_um", "<", lambda m:
    m.cell_diameter_um - m.gap_um, "cell_diameter_um - gap_um")``.

    ``says`` is the bound as the error prints it, beside its value. The fuzz suite moves the
    field to the bound and beyond (``measure`` tells it how: scale the number, the point or
    the list), so a declared rule is tested with no code of its own.
    """

    field: str
    op: Literal["<", "<=", ">", ">="]
    bound: Callable[[Any], float]
    says: str
    measure: Literal["value", "norm", "max"] = "value"

    def check(self, inputs: BaseModel) -> None:
        value = getattr(inputs, self.field)
        if value is None or (isinstance(value, list | tuple) and not value):
            return  # not given, or a list with no element to break the rule
        bound = float(self.bound(inputs))
        if not OPS[self.op](MEASURES[self.measure](value), bound):
            what = self.field if self.measure == "value" else f"{self.measure}({self.field})"
            raise RuleBroken(self.field, f"{what} {self.op} {self.says} = {bound:g}", value)


@dataclass(frozen=True)
class Refining:
    """Cross-field rule of a mesh study: the sizes (or size fractions) in ``field`` strictly
    decrease, so each mesh refines the one before and an observed order exists."""

    field: str

    def check(self, inputs: BaseModel) -> None:
        sizes = list(getattr(inputs, self.field))
        if any(b >= a for a, b in zip(sizes, sizes[1:], strict=False)):
            raise RuleBroken(self.field, "strictly decreasing sizes (each mesh finer)", sizes)


@dataclass(frozen=True)
class Increasing:
    """Cross-field rule of a mesh study given by cell counts (the mirror of :class:`Refining`):
    the counts in ``field`` strictly increase, so each mesh refines the one before and the
    finest mesh is the last."""

    field: str

    def check(self, inputs: BaseModel) -> None:
        counts = list(getattr(inputs, self.field))
        if any(b <= a for a, b in zip(counts, counts[1:], strict=False)):
            expected = "strictly increasing cell counts (each mesh finer, the last finest)"
            raise RuleBroken(self.field, expected, counts)


@dataclass(frozen=True)
class Distinct:
    """Cross-field rule of a list of run settings (pressures, sizes): no value twice, since
    each names its own run, folder and table row."""

    field: str

    def check(self, inputs: BaseModel) -> None:
        values = list(getattr(inputs, self.field))
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:
            raise RuleBroken(self.field, "each value once", twice)


@dataclass(frozen=True)
class Setup:
    """Cross-field rule decided by the library: ``build(inputs)`` makes the kind's cheap
    setup (a lattice, a pipette and the nodes its holder holds), so ``validate`` finds what
    ``run`` would. A library :class:`InputError` names its argument; ``fields`` maps that
    argument to the input (an argument of the same name needs no entry)."""

    build: Callable[[Any], object]
    fields: tuple[tuple[str, str], ...] = ()

    def check(self, inputs: BaseModel) -> None:
        try:
            self.build(inputs)
        except InputError as exc:
            field = dict(self.fields).get(exc.field, exc.field)
            if field not in type(inputs).model_fields:
                raise TypeError(f"Setup of {type(inputs).__name__}: map {exc.field!r}") from None
            raise RuleBroken(field, exc.expected, exc.got) from None


Rule = Relation | Refining | Increasing | Distinct | Setup


class CaseInputs(BaseModel):
    """Base of the input models of case kinds (the rules are in the module docstring)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)
    rules: ClassVar[tuple[Rule, ...]] = ()
    """Cross-field rules of the kind, checked in order after every field is valid."""

    @model_validator(mode="after")
    def _cross_field(self) -> Self:
        for rule in type(self).rules:
            rule.check(self)
        return self

    @field_validator("*", mode="before")
    @classmethod
    def _arrays_for_tuples(cls, value: Any, info: ValidationInfo) -> Any:
        field = cls.model_fields.get(info.field_name or "")
        if field is not None and isinstance(value, list):
            annotation = field.annotation
            options = typing.get_args(annotation) if typing.get_origin(annotation) else ()
            if typing.get_origin(annotation) is tuple or any(
                typing.get_origin(a) is tuple for a in options
            ):
                return tuple(value)
        return value

    @field_validator("*", mode="after")
    @classmethod
    def _bounded(cls, value: Any, info: ValidationInfo) -> Any:
        field = cls.model_fields.get(info.field_name or "")
        bound = float(_extra(field).get("max_abs", MAX_ABS)) if field else MAX_ABS
        bad = _first_outside(value, 0.0, bound)
        if bad is not None:
            raise ValueError(f"numbers of magnitude at most {bound:g} (got {bad:g})")
        quantity = _extra(field).get("quantity") if field else None
        if quantity is not None:
            low, high, unit = checks.QUANTITIES[quantity]
            bad = _first_outside(value, low, high, signed=True)
            if bad is not None:
                raise ValueError(
                    f"a number in [{low:g}, {high:g}] {unit} (the physical bounds of "
                    f"{quantity}; got {bad:g})"
                )
            return value
        unit = unit_of(field) if field else None
        if unit in UNIT_BOUNDS:
            low, high = UNIT_BOUNDS[unit]
            bad = _first_outside(value, low, high)
            if bad is not None:
                raise ValueError(
                    f"0 or a magnitude in [{low:g}, {high:g}] {unit} (the physical bounds of "
                    f"the quantity; got {bad:g})"
                )
        return value


def _resolve_data_file(value: Path, info: ValidationInfo) -> Path:
    case_dir = (info.context or {}).get("case_dir")
    field = f"inputs.{info.field_name}"
    where = Path(case_dir) / "case.toml" if case_dir is not None else Path("<inputs>")
    try:
        path = value if case_dir is None else checks.inside(value, case_dir, where, field)
        if not path.exists():
            raise ValueError("an existing data file (relative to the case folder), not found")
        return checks.regular_file(path, field)
    except InputError as exc:  # re-worded: pydantic names the case file and the field
        raise ValueError(exc.expected + ("" if exc.got is None else f" ({exc.got})")) from None


DataFile = Annotated[Path, Field(strict=False), AfterValidator(_resolve_data_file)]
"""An input naming a data file: inside the case folder, a regular file (checked to exist)."""


class DataReader:
    """The reader ``run`` uses for a data file: ``Annotated[DataFile, DataReader(f)]``."""

    def __init__(self, reader: Callable[[Path], object]) -> None:
        self.reader = reader


def readers_of(model: type[BaseModel]) -> dict[str, Callable[[Path], object]]:
    """Field name -> reader of the data-file fields of ``model`` (see :class:`DataReader`).

    Optional data files (``Annotated[DataFile, DataReader(f)] | None``) are found too.
    """
    found = {}
    for name, info in model.model_fields.items():
        metadata = list(info.metadata)
        for option in typing.get_args(info.annotation):
            metadata += list(getattr(option, "__metadata__", ()))
        for meta in metadata:
            if isinstance(meta, DataReader):
                found[name] = meta.reader
    return found
