"""The base of every case kind's input model: strict types, finite and bounded numbers, safe files.

A kind's inputs subclass :class:`CaseInputs` (the registry refuses any other model), so each
rule below holds for every kind, a new one included, without a line of its own:

* unknown keys are refused (``extra = "forbid"``);
* types are strict: ``true`` is not a number, ``"yes"`` is not a boolean, ``2.5`` is not an
  integer, ``"1"`` is not a number (TOML arrays are accepted for tuple fields);
* every float, also inside lists, tuples and tables, is finite (``inf``, ``nan``, ``1e400``
  refused) and of magnitude at most :data:`MAX_ABS` unless the field sets its own bound with
  ``json_schema_extra={"max_abs": ...}`` (``1e308`` would overflow the first product);
* a :data:`DataFile` lies inside the case folder and is a regular UTF-8 file; a field made with
  :func:`data_file` is also *read* at validation with the reader ``run`` uses, so
  ``validate`` finds an empty, binary or wrong-column file, not the run.

Documentation convention (``oocyte-fe kinds`` and ``oocyte-fe new`` read it)::

    E0_kPa: float = Field(7.0, gt=0, description="instantaneous modulus",
                          json_schema_extra={"unit": "kPa"})

with ``unit = "1"`` for dimensionless numbers and no unit for strings, paths and booleans.
"""

from __future__ import annotations

import typing
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
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


def _first_too_large(value: Any, bound: float) -> float | None:
    """The first float in ``value`` (nested lists, tuples, dicts) with ``|x| > bound``."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, float):
            if abs(item) > bound:
                return item
        elif isinstance(item, list | tuple):
            stack.extend(item)
        elif isinstance(item, dict):
            stack.extend(item.values())
    return None


class CaseInputs(BaseModel):
    """Base of the input models of case kinds (the rules are in the module docstring)."""

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)

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
        bad = _first_too_large(value, bound)
        if bad is not None:
            raise ValueError(f"numbers of magnitude at most {bound:g} (got {bad:g})")
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
