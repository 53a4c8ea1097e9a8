"""Properties of the one validator (``oocyte_fe.checks``) and of the case-input bounds built on
it (``oocyte_fe.runner.schema``): each accepts exactly the values inside its bounds, returns
them unchanged, and refuses every other value with one :class:`InputError` line that states
the bound (issue 26 A, class 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import Field, ValidationError

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.runner.schema import MAX_ABS, UNIT_BOUNDS, CaseInputs

PROPERTY = settings(max_examples=50, derandomize=True, database=None, deadline=None)
"""Fixed examples (derandomized): the same inputs in every run, a fraction of a second per test."""
ANY_FLOAT = st.floats(allow_nan=True, allow_infinity=True)
NOT_NUMBERS = st.one_of(
    st.booleans(),
    st.text(max_size=5),
    st.none(),
    st.complex_numbers(allow_nan=False, allow_infinity=False, min_magnitude=1e-3),
    st.lists(st.floats(), max_size=2),
)


def _near(bound: float) -> st.SearchStrategy[float]:
    """Floats at, just inside and just outside ``bound`` (and scattered around it)."""
    exact = [bound, math.nextafter(bound, math.inf), math.nextafter(bound, -math.inf)]
    return st.one_of(st.sampled_from(exact), st.floats(*sorted((bound * 0.5, bound * 2.0))))


def _values(low: float, high: float) -> st.SearchStrategy[float]:
    return st.one_of(ANY_FLOAT, _near(low), _near(high), st.floats(low, high), st.just(0.0))


@pytest.mark.parametrize("kind", sorted(checks.QUANTITIES))
@PROPERTY
@given(data=st.data())
def test_quantity_accepts_exactly_the_values_within_its_bounds(kind: str, data) -> None:
    low, high, unit = checks.QUANTITIES[kind]
    value = data.draw(_values(low, high), label="value")
    inside = math.isfinite(value) and low <= value <= high
    if inside:
        assert checks.quantity("f.csv", "x", value, kind) == value
    else:
        with pytest.raises(InputError) as err:
            checks.quantity("f.csv", "x", value, kind)
        message = str(err.value)
        assert message.startswith("f.csv: x: expected ") and "\n" not in message
        assert f"[{low:g}, {high:g}] {unit}" in message


@PROPERTY
@given(value=NOT_NUMBERS, kind=st.sampled_from(sorted(checks.QUANTITIES)))
def test_quantity_refuses_what_is_not_a_real_number(value: object, kind: str) -> None:
    with pytest.raises(InputError, match=r"^w: x: expected a number in \["):
        checks.quantity("w", "x", value, kind)


BOUNDS = st.tuples(
    st.one_of(st.none(), st.floats(-1e6, 1e6)),
    st.sampled_from(["gt", "ge"]),
    st.one_of(st.none(), st.floats(-1e6, 1e6)),
    st.sampled_from(["lt", "le"]),
)


@PROPERTY
@given(bounds=BOUNDS, data=st.data())
def test_number_accepts_exactly_the_values_its_bounds_allow(bounds, data) -> None:
    low, low_op, high, high_op = bounds
    value = data.draw(
        st.one_of(
            ANY_FLOAT,
            _near(low) if low else st.floats(),
            _near(high) if high else st.floats(),
            st.integers(-(10**7), 10**7),
        ),
        label="value",
    )
    kwargs = {low_op: low, high_op: high}
    inside = math.isfinite(value) and (
        (low is None or (value > low if low_op == "gt" else value >= low))
        and (high is None or (value < high if high_op == "lt" else value <= high))
    )
    if inside:
        assert checks.number("w", "x", value, **kwargs) == float(value)
    else:
        with pytest.raises(InputError, match=r"^w: x: expected a finite real number"):
            checks.number("w", "x", value, **kwargs)


@PROPERTY
@given(value=st.one_of(st.integers(-50, 150), ANY_FLOAT, st.booleans()))
def test_integer_accepts_exactly_the_ints_in_its_range(value: object) -> None:
    inside = type(value) is int and 0 <= value <= 100
    if inside:
        assert checks.integer("w", "n", value, 0, 100) == value
    else:
        with pytest.raises(InputError, match=r"^w: n: expected an integer in \[0, 100\]"):
            checks.integer("w", "n", value, 0, 100)


@PROPERTY
@given(value=st.one_of(ANY_FLOAT, _near(0.0), _near(1.0), _near(checks.TINY)))
def test_fraction_and_positive_accept_exactly_their_intervals(value: float) -> None:
    finite = math.isfinite(value)
    if finite and 0 < value < 1:
        assert checks.fraction("w", "f", value) == value
    else:
        with pytest.raises(InputError, match=r"expected a fraction in \(0, 1\)"):
            checks.fraction("w", "f", value)
    if finite and checks.TINY <= value <= checks.HUGE:
        assert checks.positive("w", "p", value) == value
    else:
        with pytest.raises(InputError, match=r"^w: p: expected"):
            checks.positive("w", "p", value)


@PROPERTY
@given(values=st.lists(st.one_of(ANY_FLOAT, st.floats(0.0, 10.0)), min_size=1, max_size=8))
def test_numbers_array_refuses_naming_the_first_element_outside(values: list[float]) -> None:
    array = np.array(values)
    bad = ~(np.isfinite(array) & (array >= 0) & (array <= 10))
    if not bad.any():
        np.testing.assert_array_equal(checks.numbers_array("w", "a", values, ge=0, le=10), array)
        return
    with pytest.raises(InputError, match=r"^w: a: expected an array of finite real numbers") as e:
        checks.numbers_array("w", "a", values, ge=0, le=10)
    first = array[bad][0]
    assert e.value.got == first or (math.isnan(first) and math.isnan(e.value.got))


@PROPERTY
@given(steps=st.lists(st.floats(-1.0, 1.0), min_size=1, max_size=12), nan_at=st.integers(-1, 11))
def test_increasing_names_the_first_row_out_of_order(steps: list[float], nan_at: int) -> None:
    column = np.cumsum([0.0, *steps])
    if 0 <= nan_at < column.size:
        column[nan_at] = math.nan
    finite = np.isfinite(column)
    back = np.flatnonzero(np.diff(column) <= 0)
    if finite.all() and back.size == 0:
        np.testing.assert_array_equal(checks.increasing("t.csv", "time_s", column), column)
        return
    with pytest.raises(InputError) as err:
        checks.increasing("t.csv", "time_s", column)
    row = int(np.flatnonzero(~finite)[0]) if not finite.all() else int(back[0]) + 1
    assert f"data row {row + 1}" in str(err.value)


class _Bounded(CaseInputs):
    length_um: float = Field(1.0, json_schema_extra={"unit": "um"})
    lengths_um: list[float] = Field(default_factory=list, json_schema_extra={"unit": "um"})
    angle_deg: float = Field(
        10.0, json_schema_extra={"unit": "deg", "quantity": "cone_half_angle_deg"}
    )


@PROPERTY
@given(value=_values(*UNIT_BOUNDS["um"]), field=st.sampled_from(["length_um", "lengths_um"]))
def test_a_case_input_with_a_unit_is_zero_or_within_its_physical_bounds(
    value: float, field: str
) -> None:
    low, high = UNIT_BOUNDS["um"]
    given_value = [value] if field == "lengths_um" else value
    inside = math.isfinite(value) and (value == 0 or low <= abs(value) <= high)
    if inside:
        assert getattr(_Bounded.model_validate({field: given_value}), field) == given_value
    else:
        with pytest.raises(ValidationError, match=field):
            _Bounded.model_validate({field: given_value})


@PROPERTY
@given(value=_values(*checks.QUANTITIES["cone_half_angle_deg"][:2]))
def test_a_case_input_naming_its_quantity_is_within_that_quantity(value: float) -> None:
    low, high, unit = checks.QUANTITIES["cone_half_angle_deg"]
    if math.isfinite(value) and low <= value <= high:
        assert _Bounded.model_validate({"angle_deg": value}).angle_deg == value
    else:
        with pytest.raises(ValidationError, match="angle_deg") as err:
            _Bounded.model_validate({"angle_deg": value})
        if math.isfinite(value) and abs(value) <= MAX_ABS:  # beyond: the magnitude bound first
            assert f"[{low:g}, {high:g}] {unit}" in str(err.value)


def test_unit_that_fits_names_the_nearest_unit_that_reads_the_value_in_range() -> None:
    """The shared "looks like unit X" guess of the AFM and NMSD readers: metres under
    ``piezo_um`` (8e-6 um; the AFM travel units nm, um, m) read as ``piezo_m`` give 8 um;
    of two units that would both fit, the nearer in scale is named; none when no unit fits or
    the column's unit is unknown."""
    import pytest

    from oocyte_fe.checks import unit_that_fits

    lengths = {"nm": 1e-3, "um": 1.0, "mm": 1e3, "m": 1e6}
    assert unit_that_fits("piezo_um", 8e-6, (1e-3, 1e3), {"nm": 1e-3, "um": 1.0, "m": 1e6}) == (
        "piezo_m",
        pytest.approx(8.0),
    )
    assert unit_that_fits("d_um", 0.5, (1.0, 1e6), lengths) == ("d_mm", pytest.approx(500.0))
    assert unit_that_fits("d_um", 1e-30, (1.0, 1e3), lengths) is None
    assert unit_that_fits("deflection_V", 1e-9, (1e-3, 1e6), lengths) is None


def test_toml_files_and_tables_fail_in_one_line_naming_the_key(tmp_path) -> None:
    """checks.read_toml and checks.toml_table: the one TOML reading of the material,
    fitted-rheology and NMSD constants files."""
    path = tmp_path / "f.toml"
    path.write_text("[a]\nx = 1\ny = 2\n[b]\nz = [1, 2]\n")
    data = checks.read_toml(path)
    assert checks.toml_table(path, data, "a", {"x", "y"}) == {"x": 1, "y": 2}
    assert checks.toml_table(path, data, "c", set(), required=False) == {}
    for key, allowed, required, field, says in (
        ("a", {"x"}, True, "a.y", "one of ['x']"),
        ("c", set(), True, "[c]", "this table (it is required)"),
    ):
        with pytest.raises(InputError) as err:
            checks.toml_table(path, data, key, allowed, required)
        assert (err.value.field, err.value.expected) == (field, says)
    path.write_text("a = " + "[" * 3000 + "]" * 3000)
    with pytest.raises(InputError, match="TOML nested less deeply"):
        checks.read_toml(path)
    path.write_text("a = = 1\n")
    with pytest.raises(InputError, match="valid TOML"):
        checks.read_toml(path)
