"""Run the cheap kinds on inputs that pass validation but sit at the edges of what it allows.

``validate`` accepting a case is a promise that ``run`` either works or fails with the
project's error naming the case's own file and field (not ``<input>`` from a library, not a
bare ``ZeroDivisionError``). Each example sets one numeric input of a cheap kind (from the
model, so new inputs are covered) to an edge value (tiny, huge, zero, a bound), keeps it only if
the case still loads, and runs the kind: the outcome is finite metrics or such an error.
"""

from __future__ import annotations

import copy
import logging
import math
import shutil
from typing import Any

import pytest
import tomli_w
from hypothesis import assume, given
from hypothesis import strategies as st

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import CaseContext
from tests.fuzz.harness import check_outcome, fuzz_settings
from tests.fuzz.test_fuzz_case_schema import Bases, bases, builtin_kinds, field_paths  # noqa: F401

CHEAP = ("afm_creep_prony", "microchannel_carreau_fit", "microchannel_deformation")
"""Kinds whose quick run takes about a second (the others are covered by validation only)."""

EDGES = st.sampled_from(
    [1e-300, 1e-30, 1e-12, 1e-6, 0.0, 1e-3, 0.5, 0.999999, 1.0, 1e3, 1e6, 1e9, 1e12, -1e12, -1.0]
)


def _numeric_paths(kind: str) -> list[tuple[str, ...]]:
    model = builtin_kinds()[kind].inputs
    out = []
    for path in field_paths(model):
        info = model
        for key in path:
            field = info.model_fields[key]
            info = field.annotation
        text = str(field.annotation)
        if ("float" in text or "int" in text) and "Literal" not in text:
            out.append(path)
    return out


def _set(table: dict[str, Any], path: tuple[str, ...], value: Any) -> None:
    for key in path[:-1]:
        table = table.setdefault(key, {})
    table[path[-1]] = value


@pytest.mark.slow
@fuzz_settings(ci_examples=5, full_examples=300)
@given(data=st.data())
def test_run_accepted_edge_inputs(
    bases: Bases,  # noqa: F811
    tmp_path_factory: pytest.TempPathFactory,
    data: st.DataObject,
) -> None:
    kind = data.draw(st.sampled_from(CHEAP), label="kind")
    folder, raw = bases[kind]
    raw = copy.deepcopy(raw)
    path = data.draw(st.sampled_from(_numeric_paths(kind)), label="path")
    value = data.draw(EDGES, label="value")
    current = raw["inputs"]
    for key in path:
        current = current.get(key) if isinstance(current, dict) else None
    if isinstance(current, list):
        value = [value] * len(current)
    elif isinstance(current, dict):  # a table of numbers (label -> value): every entry
        value = dict.fromkeys(current, value)
    elif isinstance(current, int) and not isinstance(current, bool):
        value = int(value) if math.isfinite(value) and abs(value) < 2**62 else value
    _set(raw["inputs"], path, value)
    raw.pop("quick", None)
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    try:
        case = load_case(folder)
    except InputError:
        assume(False)  # refused at validation: covered by test_fuzz_case_schema
    out = tmp_path_factory.mktemp("run")
    ctx = CaseContext(case.name, case.directory, out, case.inputs, False, logging.getLogger("fuzz"))

    def run() -> object:
        try:
            return case.kind.run(ctx).metrics
        finally:
            shutil.rmtree(out, ignore_errors=True)

    metrics = check_outcome(f"run ({kind})", run, own_file=True)
    if metrics is None:
        return
    assert all(math.isfinite(v) if isinstance(v, float) else True for v in metrics.values()), (
        f"{kind}: inputs.{'.'.join(path)} = {value!r} gave non-finite metrics {metrics}"
    )
