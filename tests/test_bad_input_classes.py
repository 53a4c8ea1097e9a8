"""The classes of bad input of issue 26, one test per class (the fuzz suite, ``tests/fuzz``,
generates many inputs of each; these are the fixed, fast examples).

1. cross-field geometry, found by ``validate`` and named against the field the rule names;
2. magnitudes outside the physical bounds of their quantity, booleans as numbers, nonsense
   steps and targets of the ``nmsd`` functions;
3. special paths and tables of the wrong type;
4. degenerate data handed to fits (one row, all equal, a huge value).

Class 5 (AFM curve and creep files) belongs to the ``afm`` package's tests.
"""

from __future__ import annotations

import math
import shutil
import tomllib
from pathlib import Path
from typing import Any, Literal, get_args, get_origin

import numpy as np
import pytest
import tomli_w

from afm.curve import spring_constant_nN_per_um
from nmsd.approach_pid import PidGains, pid_approach
from nmsd.cytoplasm_loss import loss_fraction
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters
from nmsd.spindle import predict_spindle_offset
from oocyte_fe.checks import QUANTITIES
from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import kinds
from oocyte_fe.runner.schema import (
    UNIT_BOUNDS,
    Distinct,
    Increasing,
    Refining,
    Relation,
    unit_of,
)
from tests.case_copies import edited_case

CASES = Path(__file__).resolve().parents[1] / "cases"


# --- 1. cross-field geometry -----------------------------------------------------------------

SHIPPED = {
    "nmsd_calibration": "nmsd_calibration_tableII",
    "nmsd_spindle_offset": "nmsd_spindle_offset",
    "microchannel_vof": "microchannel_vof_quick",
    "fe_verification": "fe_verification",
    "enucleation_loop": "enucleation_loop",
    "afm_creep_prony": "afm_creep_prony",
    "nmsd_vs_fe": "nmsd_vs_fe",
    "spindle_tracking": "spindle_tracking",
    "rtdc_elastic_cell": "rtdc_elastic_cell",
    "microchannel_flow": "microchannel_flow",
    "microchannel_carreau_fit": "microchannel_carreau_fit",
}
RELATIONS = [
    (kind, block, rule)
    for kind, case in SHIPPED.items()
    for block, model in [((), kinds()[kind].inputs)]
    + [
        ((name,), info.annotation)
        for name, info in kinds()[kind].inputs.model_fields.items()
        if isinstance(info.annotation, type) and hasattr(info.annotation, "rules")
    ]
    for rule in model.rules
    if isinstance(rule, Relation | Refining | Increasing | Distinct)
]


@pytest.mark.parametrize(
    ("kind", "block", "rule"), RELATIONS, ids=[f"{k}:{r.field}" for k, _, r in RELATIONS]
)
def test_each_declared_rule_is_refused_against_its_field(
    tmp_path: Path,
    kind: str,
    block: tuple[str, ...],
    rule: Relation | Refining | Increasing | Distinct,
) -> None:
    inputs = load_case(CASES / SHIPPED[kind]).inputs
    for name in block:
        inputs = getattr(inputs, name)
    value = getattr(inputs, rule.field)
    empty = isinstance(value, list | tuple) and not value  # an empty list breaks nothing
    if empty and not isinstance(rule, Distinct):  # (no finer mesh): a refining pair, scaled
        value = [2.0, 1.0]  # or reversed below
    if isinstance(rule, Distinct):  # a value twice (pressures: two runs in one folder)
        (item,) = get_args(type(inputs).model_fields[rule.field].annotation)
        if value:
            broken: Any = [*value, value[0]]
        elif get_origin(item) is Literal:
            broken = [get_args(item)[0]] * 2  # an allowed name twice
        else:
            broken = ["a", "a"] if item is str else [300.0, 300.0]
    elif isinstance(rule, Refining | Increasing):
        broken = list(value)[::-1]
    else:
        bound = rule.bound(inputs)
        target = bound * 1.5 if rule.op in ("<", "<=") else bound / 1.5
        broken = target if rule.measure == "value" else [v * target / max(value) for v in value]
        if rule.measure == "norm":
            broken = [v * target / math.hypot(*value) for v in value]
    field = ".".join((*block, rule.field))
    folder = edited_case(tmp_path, SHIPPED[kind], **{field: broken})
    with pytest.raises(InputError, match=rf"case\.toml: inputs\.{field}: expected") as err:
        load_case(folder)
    if isinstance(rule, Relation):
        assert rule.says in str(err.value)  # the bound is named, with its value
    if isinstance(rule, Distinct):
        assert "each value once" in str(err.value)


@pytest.mark.parametrize(
    ("inputs", "field", "expected"),
    [
        ({"hold_half_width_um": 0.01}, "hold_half_width_um", "holds at least one rim node"),
        ({"spindle_initial_um": [5.0, 50.0]}, "spindle_initial_um", "inside the cell"),
        ({"spindle_initial_um": [0.0, 0.0]}, "spindle_initial_um", "away from the puncture"),
        ({"travel_um": 120.0}, "travel_um", "cell_diameter_um - gap_um = 115.625"),
    ],
)
def test_spindle_geometry_is_found_at_validate(
    tmp_path: Path, inputs: dict, field: str, expected: str
) -> None:
    """What ``run`` would refuse after a calibration (the library's own setup, run at
    validation), named against the case's field."""
    folder = edited_case(tmp_path, "nmsd_spindle_offset", **inputs)
    with pytest.raises(InputError, match=rf"inputs\.{field}: expected .*{expected}"):
        load_case(folder)


# --- 2. magnitudes ---------------------------------------------------------------------------

UNIT_FIELDS = [
    (kind, name, unit_of(info))
    for kind in SHIPPED
    for name, info in kinds()[kind].inputs.model_fields.items()
    if info.annotation is float and unit_of(info) in UNIT_BOUNDS
]


@pytest.mark.parametrize(("kind", "name", "unit"), UNIT_FIELDS)
@pytest.mark.parametrize("value", [1e-320, 1e-7, 5e11])
def test_physical_bounds_per_unit(
    tmp_path: Path, kind: str, name: str, unit: str, value: float
) -> None:
    low, high = UNIT_BOUNDS[unit]
    folder = edited_case(tmp_path, SHIPPED[kind], **{name: value})
    if low <= value <= high:
        return  # within the bounds of this unit (5e11 is a fine time in s, not in um)
    with pytest.raises(InputError, match=rf"inputs\.{name}: expected") as err:
        load_case(folder)
    message = str(err.value)
    assert f"[{low:g}, {high:g}] {unit}" in message or "expected a value" in message, message


def _shipped_case(kind: str) -> str:
    """The first case of ``cases/`` of ``kind``."""
    return next(
        folder.name
        for folder in sorted(CASES.iterdir())
        if (folder / "case.toml").is_file()
        and tomllib.loads((folder / "case.toml").read_text())["kind"] == kind
    )


QUANTITY_FIELDS = [
    (kind, name, info.json_schema_extra["quantity"])
    for kind, spec in kinds().items()
    for name, info in spec.inputs.model_fields.items()
    if isinstance(info.json_schema_extra, dict) and "quantity" in info.json_schema_extra
]
CONE_FIELDS = [
    pytest.param(kind, name)
    for kind, spec in kinds().items()
    for name, info in spec.inputs.model_fields.items()
    if "cone half angle" in (info.description or "").lower()
]


@pytest.mark.parametrize(("kind", "name"), CONE_FIELDS)
def test_every_cone_half_angle_declares_its_quantity(kind: str, name: str) -> None:
    assert (kind, name, "cone_half_angle_deg") in QUANTITY_FIELDS


@pytest.mark.parametrize(("kind", "name", "quantity"), QUANTITY_FIELDS)
@pytest.mark.parametrize("where", ["low", "high"])
def test_a_declared_quantity_is_held_to_its_bounds(
    tmp_path: Path, kind: str, name: str, quantity: str, where: str
) -> None:
    """Each field naming a quantity of ``checks.QUANTITIES`` (a cone half angle in [0.1, 89]
    deg) takes its bound and refuses what lies beyond it (0 and the sign included), naming it."""
    low, high, unit = QUANTITIES[quantity]
    bound = low if where == "low" else high
    case = _shipped_case(kind)
    assert (
        getattr(load_case(edited_case(tmp_path / "at", case, **{name: bound})).inputs, name)
        == bound
    )
    beyond = [low * (1 - 1e-9), 0.0, -low] if where == "low" else [high * (1 + 1e-9), 2 * high]
    for value in beyond:
        folder = edited_case(tmp_path / repr(value), case, **{name: value})
        with pytest.raises(InputError, match=rf"inputs\.{name}: expected") as err:
            load_case(folder)
        assert f"[{low:g}, {high:g}] {unit}" in str(err.value)


@pytest.mark.parametrize("value", [1e-320, 1e-13, 2e9])
def test_spring_constants_have_a_physical_bound(tmp_path: Path, value: float) -> None:
    """N/m (spring constants): [1e-12, 1e9] N/m, the bound of nN/um over 1000, in both the case
    schema and the afm conversion every reader uses."""
    folder = edited_case(tmp_path, "afm_creep_prony", spring_constant_N_per_m=value)
    bound = "[1e-12, 1e+09] N/m"
    with pytest.raises(InputError, match=r"inputs\.spring_constant_N_per_m: expected") as err:
        load_case(folder)
    assert bound in str(err.value)
    with pytest.raises(InputError, match=r"spring_constant_N_per_m: expected") as err:
        spring_constant_nN_per_um(value)
    assert bound in str(err.value)
    assert spring_constant_nN_per_um(0.07) == pytest.approx(70.0, rel=1e-15)


def test_booleans_are_not_numbers() -> None:
    with pytest.raises(InputError, match="NmsdParameters: k1: expected a finite real number"):
        NmsdParameters(k1=True)  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"k2: expected 0 or a magnitude in \[1e-09, 1e\+12\] nN"):
        NmsdParameters(k2=1e-320)


def test_nmsd_steps_lengths_and_targets() -> None:
    lattice = circular_lattice(40.0, 4)
    for step in (0.0, math.nan):
        with pytest.raises(InputError, match="predict_spindle_offset: step_um"):
            predict_spindle_offset(lattice, NmsdParameters(), (15.0, 2.0), step_um=step)
    with pytest.raises(InputError, match="pid_approach: target: expected .* finite"):
        pid_approach(lambda _s: np.array([math.nan, 1.0]), PidGains())
    for args, name in (((-1.0, 20.0, 115.0), "length_um"), ((10.0, 0.0, 115.0), "pipette_um")):
        with pytest.raises(InputError, match=f"loss_fraction: {name}"):
            loss_fraction(*args)
    assert float(loss_fraction(30.0, 20.0, 115.625)) == pytest.approx(
        (math.pi * 20.0**2 / 4 * 30.0) / (math.pi * 115.625**3 / 6), rel=1e-12
    )


# --- 3. special paths and tables of the wrong type -------------------------------------------


@pytest.mark.parametrize("table", ["reference", "tolerances", "quick", "inputs", "sweep"])
def test_a_table_of_the_wrong_type_is_one_line(tmp_path: Path, table: str) -> None:
    folder = tmp_path / "c"
    shutil.copytree(CASES / "nmsd_calibration_tableII", folder)
    raw = tomllib.loads((folder / "case.toml").read_text())
    raw[table] = 5
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    with pytest.raises(InputError, match=rf"case\.toml: {table}: expected .*, got 5$"):
        load_case(folder)


# --- 4. degenerate data handed to fits -------------------------------------------------------

RATE = np.array([0.01, 0.1, 1.0, 10.0, 100.0, 1000.0])
ETA = np.array([1.0, 0.9, 0.5, 0.1, 0.02, 0.01])


@pytest.mark.parametrize(
    ("rate", "eta", "expected"),
    [
        (RATE[:1], ETA[:1], "shear_rate: expected at least 4 distinct"),
        (np.full(6, 1.0), ETA, "shear_rate: expected at least 4 distinct"),
        (RATE, np.full(6, 0.5), "viscosity: expected viscosities that vary"),
        (RATE, np.r_[ETA[:-1], 1e300], r"viscosity: expected .*<= 1e\+09"),
        (RATE, np.r_[ETA[:-1], math.nan], "viscosity: expected"),
    ],
)
def test_degenerate_flow_curves_are_refused_before_the_fit(
    rate: np.ndarray, eta: np.ndarray, expected: str
) -> None:
    with pytest.raises(InputError, match=expected):
        fit_viscosity("carreau", rate, eta)


def test_a_fit_on_good_data_reports_a_finite_r2() -> None:
    fit = fit_viscosity("carreau", RATE, ETA)
    assert fit.success and 0.9 < fit.r2 <= 1.0 and math.isfinite(fit.r2_log)
    # the two figures are their definitions, 1 - SS_res / SS_tot on eta and on ln eta, of the
    # fitted curve (round-off: 1e-12)
    eta_fit = fit.rheology.viscosity(RATE)
    for y, y_fit, r2 in ((ETA, eta_fit, fit.r2), (np.log(ETA), np.log(eta_fit), fit.r2_log)):
        defined = 1.0 - np.sum((y - y_fit) ** 2) / np.sum((y - y.mean()) ** 2)
        assert r2 == pytest.approx(defined, rel=1e-12, abs=1e-12)


def test_rules_are_declared_where_a_new_kind_inherits_them() -> None:
    """A subclass of a kind's inputs keeps the cross-field rules (the resampled spindle kind)."""
    base = kinds()["nmsd_spindle_offset"].inputs.rules
    resampled = kinds()["nmsd_spindle_offset_resampled"].inputs.rules
    assert resampled == base and len(base) >= 7
