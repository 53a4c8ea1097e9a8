"""Fuzz every case kind's inputs, generated from its pydantic model (a new kind needs no code).

Each registered kind starts from a valid ``case.toml``: a case of that kind in ``cases/``, or
one synthesised from the model's defaults and bounds. One key (an input at any depth, a
top-level key, a tolerance or a reference) is then replaced by a hostile value, removed or
misspelt, and the case is loaded as ``validate`` and ``run`` load it. It must be refused with
one line naming ``case.toml`` and the key, or accepted with finite, in-range, strictly typed
values (no ``"yes"`` read as true, no ``true`` read as 1).
"""

from __future__ import annotations

import copy
import math
import shutil
import tomllib
import typing
from pathlib import Path
from typing import Any

import pytest
import tomli_w
from hypothesis import given
from hypothesis import strategies as st
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import kinds
from oocyte_fe.runner.schema import (
    MAX_ABS,
    MEASURES,
    OPS,
    UNIT_BOUNDS,
    Distinct,
    Refining,
    Relation,
    Rule,
    unit_of,
)
from tests.fuzz.harness import ANYTHING_SCALARS, check_outcome, fuzz_settings

CASES = Path(__file__).resolve().parents[2] / "cases"
BUILTIN = "oocyte_fe.kinds"


def builtin_kinds() -> dict[str, Any]:
    return {k: v for k, v in kinds().items() if v.module.startswith(BUILTIN)}


def field_paths(model: type[BaseModel], prefix: tuple[str, ...] = ()) -> list[tuple[str, ...]]:
    """Dotted paths to every field of ``model``, nested input blocks included."""
    paths = []
    for name, info in model.model_fields.items():
        annotation = info.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            paths += field_paths(annotation, (*prefix, name))
        paths.append((*prefix, name))
    return paths


def _valid_number(info: FieldInfo, integer: bool) -> float:
    low, high = -10.0, 10.0
    for meta in info.metadata:
        for attr, side in (("gt", "low"), ("ge", "low"), ("lt", "high"), ("le", "high")):
            bound = getattr(meta, attr, None)
            if bound is not None and side == "low":
                low = float(bound)
            elif bound is not None:
                high = float(bound)
    value = (low + high) / 2 if high - low < 20 else low + 1.0
    return int(math.ceil(value)) if integer else value


def synthesise(model: type[BaseModel]) -> dict[str, Any]:
    """Inputs for ``model`` from defaults and bounds (for a kind without a case in cases/)."""
    data: dict[str, Any] = {}
    for name, info in model.model_fields.items():
        if not info.is_required():
            continue
        annotation = info.annotation
        origin = typing.get_origin(annotation)
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            data[name] = synthesise(annotation)
        elif annotation in (int, float):
            data[name] = _valid_number(info, annotation is int)
        elif origin is list:
            (item,) = typing.get_args(annotation)
            base = typing.get_args(item)[0] if typing.get_origin(item) else item
            data[name] = [_valid_number(info, base is int)] * max(1, _min_length(info))
        elif annotation is bool:
            data[name] = False
        else:
            data[name] = "x"
    return data


def _min_length(info: FieldInfo) -> int:
    return max([getattr(m, "min_length", 0) or 0 for m in info.metadata] or [0])


def base_cases(root: Path) -> dict[str, Path]:
    """kind -> a valid case folder under ``root`` (copies of cases/, or synthesised)."""
    shutil.copytree(CASES, root, dirs_exist_ok=True)
    found: dict[str, Path] = {}
    for folder in sorted(root.iterdir()):
        if (folder / "case.toml").is_file():
            kind = tomllib.loads((folder / "case.toml").read_text())["kind"]
            found.setdefault(kind, folder)
    for name, kind in builtin_kinds().items():
        if name not in found:
            folder = root / f"synthesised_{name}"
            folder.mkdir()
            raw = {"kind": name, "description": "synthesised", "inputs": synthesise(kind.inputs)}
            (folder / "case.toml").write_text(tomli_w.dumps(raw))
            found[name] = folder
    return found


class Bases(dict):
    """kind -> (case folder, raw case.toml); a short repr for hypothesis' reports."""

    def __repr__(self) -> str:
        return f"<{len(self)} case kinds>"


@pytest.fixture(scope="module")
def bases(tmp_path_factory: pytest.TempPathFactory) -> Bases:
    root = tmp_path_factory.mktemp("fuzz_cases")
    out = Bases()
    for kind, folder in base_cases(root).items():
        load_case(folder)  # the start is valid, so a refusal is due to the mutation
        work = root / f"fuzz_{kind}"  # mutated here; the originals (chained cases) stay valid
        shutil.copytree(folder, work)
        out[kind] = (work, tomllib.loads((folder / "case.toml").read_text()))
    return out


def test_every_builtin_kind_has_a_valid_start(bases: dict) -> None:
    assert set(bases) >= set(builtin_kinds())


FLOATS = st.floats(allow_nan=True, allow_infinity=True)
HOSTILE = st.one_of(
    st.sampled_from([v for v in ANYTHING_SCALARS if v is not None and not isinstance(v, complex)]),
    FLOATS,
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.text(max_size=12),
    st.sampled_from(["../afm_creep_prony/case.toml", "/etc/passwd", "..", ".", "x" * 300]),
    st.lists(st.one_of(FLOATS, st.integers(-5, 5)), max_size=4),
    st.dictionaries(st.text(min_size=1, max_size=6), FLOATS, max_size=3),
    st.integers(1, 40).map(lambda n: _nested(n)),
)


def _nested(depth: int) -> list:
    value: list = [1.0]
    for _ in range(depth):
        value = [value]
    return value


def _set(table: dict[str, Any], path: tuple[str, ...], value: Any) -> None:
    for key in path[:-1]:
        table = table.setdefault(key, {})
        if not isinstance(table, dict):
            return
    table[path[-1]] = value


def _get(obj: Any, path: tuple[str, ...]) -> Any:
    for key in path:
        obj = getattr(obj, key)
    return obj


def _typo(word: str, index: int) -> str:
    i = index % len(word)
    return word[:i] + word[i + 1 :] if len(word) > 3 else word + "x"


def _assert_in_range(value: Any, where: str) -> None:
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, float):
            assert math.isfinite(item) and abs(item) <= MAX_ABS, f"{where} accepted {item!r}"
        elif isinstance(item, BaseModel):
            stack.extend(item.__dict__.values())
        elif isinstance(item, list | tuple):
            stack.extend(item)
        elif isinstance(item, dict):
            stack.extend(item.values())


def _assert_physical(inputs: BaseModel, where: str) -> None:
    """Every accepted float of a field with a unit of UNIT_BOUNDS is 0 or within its bounds."""
    for name, info in type(inputs).model_fields.items():
        value = getattr(inputs, name)
        if isinstance(value, BaseModel):
            _assert_physical(value, f"{where}.{name}")
            continue
        unit = unit_of(info)
        if unit not in UNIT_BOUNDS:
            continue
        low, high = UNIT_BOUNDS[unit]
        items = value if isinstance(value, list | tuple) else [value]
        for x in items:
            if isinstance(x, float):
                assert x == 0 or low <= abs(x) <= high, f"{where}.{name} accepted {x!r} {unit}"


@fuzz_settings(ci_examples=250, full_examples=3000)
@given(data=st.data())
def test_case_inputs(bases: dict, data: st.DataObject) -> None:
    kind = data.draw(st.sampled_from(sorted(bases)), label="kind")
    folder, raw = bases[kind]
    raw = copy.deepcopy(raw)
    model = builtin_kinds()[kind].inputs
    path = data.draw(st.sampled_from(field_paths(model)), label="path")
    action = data.draw(st.sampled_from(["set", "set", "set", "remove", "misspell"]), label="do")
    value: Any = None
    inputs = raw.setdefault("inputs", {})
    if action == "set":
        value = data.draw(HOSTILE, label="value")
        _set(inputs, path, value)
    elif action == "remove":
        parent = inputs
        for key in path[:-1]:
            parent = parent.get(key, {})
        parent.pop(path[-1], None)
    else:
        parent = inputs
        for key in path[:-1]:
            parent = parent.get(key, {})
        if path[-1] in parent:
            parent[_typo(path[-1], data.draw(st.integers(0, 50)))] = parent.pop(path[-1])
    file = folder / "case.toml"
    file.write_text(tomli_w.dumps(raw))
    case = check_outcome(f"case inputs ({kind})", lambda: load_case(folder), names=path[-1][:3])
    if case is None:
        return
    _assert_in_range(case.inputs, f"{kind} inputs.{'.'.join(path)}")
    _assert_physical(case.inputs, kind)
    if action == "set" and not isinstance(value, dict | list):
        got = _get(case.inputs, path)
        if isinstance(value, bool):
            assert isinstance(got, bool), f"inputs.{'.'.join(path)}: {value!r} read as {got!r}"
        elif isinstance(value, str) and not isinstance(got, Path):
            assert got == value, f"inputs.{'.'.join(path)}: {value!r} read as {got!r}"
        elif isinstance(value, int | float):
            assert not isinstance(got, bool | str), f"{value!r} read as {got!r}"
            assert got == value


TOP = st.sampled_from(
    [
        ("inputs",),
        ("quick",),
        ("full",),
        ("reference",),
        ("tolerances",),
        ("sweep",),
        ("timeout_s",),
        ("kind",),
        ("description",),
        ("tolerances", "*", "rel"),
        ("tolerances", "*", "abs"),
        ("tolerances", "*", "min"),
        ("tolerances", "*", "max"),
        ("reference", "*", "value"),
        ("quick", "*"),
        ("sweep", "samples"),
        ("sweep", "quick_samples"),
        ("sweep", "seed"),
        ("sweep", "parameters", "*"),
        ("sweep", "parameters", "*", "mean"),
        ("sweep", "parameters", "*", "high"),
    ]
)


@fuzz_settings(ci_examples=100, full_examples=1500)
@given(data=st.data())
def test_case_top_level(bases: dict, data: st.DataObject) -> None:
    kind = data.draw(st.sampled_from(sorted(bases)), label="kind")
    folder, raw = bases[kind]
    raw = copy.deepcopy(raw)
    path = data.draw(TOP, label="path")
    value = data.draw(HOSTILE, label="value")
    if "*" in path:
        table: Any = raw
        for part in path[: path.index("*")]:
            table = table.get(part) if isinstance(table, dict) else None
        table = raw.get("inputs", {}) if path[0] == "quick" else table
        keys = sorted(table) if isinstance(table, dict) else []
        if not keys:
            return
        key = data.draw(st.sampled_from(keys), label="key")
        path = tuple(key if p == "*" else p for p in path)
    _set(raw, path, value)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    case = check_outcome(f"case top level ({kind})", lambda: load_case(folder))
    if case is None:
        return
    spec = case.spec
    if spec.timeout_s is not None:
        assert math.isfinite(spec.timeout_s)
        assert path != ("timeout_s",) or not isinstance(value, bool)
    for tol in spec.tolerances.values():
        bounds = [b for b in (tol.rel, tol.abs, tol.min, tol.max) if b is not None]
        assert all(math.isfinite(b) for b in bounds)
        assert tol.min is None or tol.max is None or tol.min <= tol.max
    for ref in spec.reference.values():
        assert math.isfinite(ref.value)


def test_misspelt_key_gets_a_suggestion(bases: dict) -> None:
    folder, raw = bases["afm_creep_prony"]
    raw = copy.deepcopy(raw)
    raw["inputs"]["E0_kpa"] = raw["inputs"].pop("E0_kPa")
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    with pytest.raises(InputError, match=r"inputs\.E0_kpa: .*did you mean 'E0_kPa'"):
        load_case(folder)


def declared_rules(
    model: type[BaseModel], prefix: tuple[str, ...] = ()
) -> list[tuple[tuple[str, ...], Rule]]:
    """(path of the input block, rule) for every cross-field rule of ``model`` and its blocks."""
    found = [(prefix, rule) for rule in getattr(model, "rules", ())]
    for name, info in model.model_fields.items():
        annotation = info.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            found += declared_rules(annotation, (*prefix, name))
    return found


RULES = [
    (kind, block, rule)
    for kind, entry in sorted(builtin_kinds().items())
    for block, rule in declared_rules(entry.inputs)
]


def test_kinds_declare_cross_field_rules() -> None:
    """The geometry kinds declare theirs (a rule removed by mistake fails here)."""
    with_rules = {kind for kind, _, _ in RULES}
    assert with_rules >= {
        "enucleation_loop",
        "fe_verification",
        "microchannel_vof",
        "nmsd_calibration",
        "nmsd_spindle_offset",
        "nmsd_spindle_offset_resampled",
    }
    assert len(RULES) >= 20


BEYOND = (1.0, 1.0 + 1e-9, 1.001, 1.5, 10.0, 1e3)
"""Factors that move a measure to its bound and beyond (inverted for ``>`` and ``>=``)."""


def _broken(rule: Relation, value: Any, bound: float, factor: float) -> Any:
    """``value`` moved so that its measure is ``bound * factor`` (or its inverse)."""
    target = bound * factor if rule.op in ("<", "<=") else bound / factor
    if rule.measure == "value":
        return target
    if rule.measure == "norm":
        norm = math.hypot(*value)
        return [target, 0.0] if norm == 0 else [v * target / norm for v in value]
    if not len(value):  # an empty list breaks no rule: one element at the target
        return [target]
    top = max(value)
    return [v * target / top for v in value] if top > 0 else [target] * len(value)


@fuzz_settings(ci_examples=120, full_examples=1500)
@given(data=st.data())
def test_cross_field_rules(bases: dict, data: st.DataObject) -> None:
    """Each declared rule, broken: refused naming its field; kept: loads or is refused."""
    kind, block, rule = data.draw(st.sampled_from(RULES), label="rule")
    folder, raw = bases[kind]
    raw = copy.deepcopy(raw)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    inputs = _get(load_case(folder).inputs, block)
    path = (*block, getattr(rule, "field", ""))
    if isinstance(rule, Relation):
        factor = data.draw(st.sampled_from(BEYOND), label="factor")
        bound = float(rule.bound(inputs))
        value = _broken(rule, getattr(inputs, rule.field), bound, factor)
        broken = not OPS[rule.op](MEASURES[rule.measure](value), bound)
    elif isinstance(rule, Refining):
        sizes = list(getattr(inputs, rule.field))
        order = data.draw(st.sampled_from(["reversed", "repeated", "kept"]), label="order")
        value = {"reversed": sizes[::-1], "repeated": [sizes[0], *sizes[:-1]], "kept": sizes}[order]
        broken = order != "kept"
    elif isinstance(rule, Distinct):  # one of the values again, or the list as it is
        values = list(getattr(inputs, rule.field))
        broken = bool(values) and data.draw(st.booleans(), label="twice")
        value = [*values, data.draw(st.sampled_from(values))] if broken else values
    else:  # a library setup: any number it reads, scaled; refused naming an input, or built
        numeric = [
            name
            for name, info in type(inputs).model_fields.items()
            if info.annotation in (float, int) and name != "seed"
        ]
        name = data.draw(st.sampled_from(numeric), label="field")
        factor = data.draw(st.sampled_from([0.0, 1e-3, 0.1, 0.5, 2.0, 10.0, -1.0]), label="x")
        value = getattr(inputs, name) * factor
        value = int(value) if isinstance(getattr(inputs, name), int) else value
        path, broken = (*block, name), False
    _set(raw.setdefault("inputs", {}), path, value)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    label = f"cross-field rules ({kind})"
    names = f"inputs.{'.'.join(path)}" if broken else None
    case = check_outcome(label, lambda: load_case(folder), names=names)
    assert case is None or not broken, f"silent acceptance: {'.'.join(path)} = {value!r}"
