"""Property tests (hypothesis) of the public functions of ``afm`` with nonsense arguments.

Every call either returns finite numbers or raises :class:`oocyte_fe.errors.InputError` naming
the argument; never another exception (IndexError, ZeroDivisionError, LinAlgError, numpy's
ValueError, ...), never a hang. The harness (``tests/fuzz/harness.py``) runs each call under
its hang guard and tallies it; each test then asserts that its inputs were both refused and
accepted (:func:`exercised`), so the asserts on accepted results cannot go unrun because a
strategy is always refused. Explicit ``@example``s hold one valid and one bad input each.
CI runs 25 derandomized examples per test; ``OOCYTE_FUZZ_FULL=1`` runs 1 000 random ones.

Issue 26, class 5: force-curve and creep files with a time column that steps back, repeats or
holds NaN/inf, and creep records whose indentation shrinks during the hold
(:func:`test_curve_time_columns`, :func:`test_creep_files`): refused naming file, column and
data row; the same files without the fault are read.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from afm.bottom_effect import fit_factor
from afm.corrections import cone_zona_modulus, zona_modulus
from afm.creep import (
    CreepData,
    compliance_from_indentation,
    fit_creep,
    fit_creep_tip,
    indentation_from_compliance,
)
from afm.curve import ForceCurve, force_from_deflection, spring_constant_nN_per_um
from afm.curve_io import read_creep, read_curve, write_creep
from afm.fe_export import ansys_prony_block, febio_material
from afm.fit import FitRange, fit_indentation
from afm.material_file import MaterialFile
from afm.pierce import fit_pierce
from afm.prony_series import (
    CreepProny,
    RelaxationProny,
    creep_from_relaxation,
    relaxation_from_creep,
)
from afm.synthetic import creep_indentation, indentation_curve, pierce_curve
from afm.viscoelastic.fit import fit_ramp
from afm.viscoelastic.ramp import RampCurve
from oocyte_fe.errors import InputError
from tests.fuzz.harness import TALLY, check_outcome, fuzz_settings

FUZZ = fuzz_settings(ci_examples=25, full_examples=1000)

# nonsense a user can type: NaN, inf, zero, negative, tiny, huge, wrong types
NONSENSE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, -1.0, 1e-300, 5e-324, 1e300, 90.0, 0.5, 1.0, -1.0]),
    st.integers(min_value=-(10**6), max_value=10**6),
    st.booleans(),
    st.text(max_size=4),
    st.none(),
    st.lists(st.floats(), max_size=2),
)

GOOD_CURVE = indentation_curve(7.01, 5.0, n_points=300, noise_fraction=0.01, seed=1)
GOOD_PIERCE = pierce_curve(7.01, 1.55, n_points=600, noise_fraction=0.005, seed=2)
TRUTH = RelaxationProny(7.01 / 3, (0.3,), (0.5,))
_T = np.linspace(0.0, 6.0, 301)
GOOD_HOLD = CreepData(_T, np.full(_T.size, 5.0), creep_indentation(TRUTH, _T, 5.0), "good_hold.csv")


@contextmanager
def exercised(*labels: str, refused: bool = True) -> Iterator[None]:
    """Each of ``labels`` got at least one accepted input (so the asserts on results ran) and,
    if ``refused``, at least one refused input, within the block."""
    before = Counter(TALLY)
    yield
    for label in labels:
        accepted = TALLY[label, "accepted"] - before[label, "accepted"]
        assert accepted > 0, f"{label}: no input accepted: the asserts on results never ran"
        if refused:
            assert TALLY[label, "refused"] > before[label, "refused"], f"{label}: none refused"


def _finite(*values: float) -> bool:
    return all(math.isfinite(float(v)) for v in values)


def _fit_numbers(fit) -> tuple[float, float]:
    assert _finite(fit.E_kPa, fit.contact_point_um) and fit.E_kPa > 0
    assert fit.rating.startswith(("good (", "poor: "))  # issue 28's rating never raises
    return fit.E_kPa, fit.contact_point_um


# --- arguments -------------------------------------------------------------------------------


@FUZZ
@given(
    name=st.sampled_from(["nu", "n_sigma", "model", "contact_method", "geometry", "fit_range"]),
    value=NONSENSE,
)
@example(name="nu", value=0.45)
@example(name="nu", value=math.nan)
def _fit_indentation_arguments(name: str, value: object) -> None:
    def call() -> tuple[float, float]:
        kwargs: dict = {name: value}
        if name == "geometry":
            kwargs = {"geometry": {"half_angle_deg": value}}
        if name == "fit_range":
            kwargs = {"fit_range": FitRange(max_indentation_um=value)}
        return _fit_numbers(fit_indentation(GOOD_CURVE, **kwargs))

    check_outcome("afm.fit_indentation", call)


def test_fit_indentation_arguments() -> None:
    with exercised("afm.fit_indentation"):
        _fit_indentation_arguments()


@FUZZ
@given(
    piezo_scale=st.floats(allow_nan=True, allow_infinity=True),
    force_scale=st.floats(allow_nan=True, allow_infinity=True),
    k=NONSENSE,
)
@example(piezo_scale=1.0, force_scale=1.0, k=70.0)
@example(piezo_scale=math.nan, force_scale=1.0, k=70.0)
def _scaled_curves(piezo_scale: float, force_scale: float, k: object) -> None:
    def call() -> tuple[float, float]:
        with np.errstate(invalid="ignore", over="ignore"):  # the fuzz input: 0 x inf is NaN
            piezo, force = GOOD_CURVE.piezo_um * piezo_scale, GOOD_CURVE.force_nN * force_scale
        curve = ForceCurve(piezo, force, k, "scaled.csv")
        return _fit_numbers(fit_indentation(curve))

    check_outcome("afm.ForceCurve + fit_indentation (scaled)", call, own_file=True)


def test_scaled_curves() -> None:
    with exercised("afm.ForceCurve + fit_indentation (scaled)"):
        _scaled_curves()


@FUZZ
@given(
    force=hnp.arrays(
        np.float64,
        st.integers(0, 40),
        elements=st.floats(allow_nan=True, allow_infinity=True, width=64),
    ),
)
@example(force=GOOD_CURVE.force_nN[::10].copy())
@example(force=np.array([1.0, math.nan]))
def _arbitrary_force_arrays(force: np.ndarray) -> None:
    piezo = np.linspace(0.0, 8.0, force.size)
    check_outcome(
        "afm.ForceCurve + fit_indentation (any force array)",
        lambda: _fit_numbers(fit_indentation(ForceCurve(piezo, force, 70.0))),
    )


def test_arbitrary_force_arrays() -> None:
    with exercised("afm.ForceCurve + fit_indentation (any force array)"):
        _arbitrary_force_arrays()


@FUZZ
@given(
    name=st.sampled_from(["nu", "min_drop_fraction", "geometry", "model", "contact_method"]),
    value=NONSENSE,
)
@example(name="nu", value=0.45)
@example(name="nu", value=math.inf)
def _fit_pierce_arguments(name: str, value: object) -> None:
    kwargs = {"geometry": {"half_angle_deg": value}} if name == "geometry" else {name: value}

    def call() -> tuple[float, float]:
        fit = fit_pierce(GOOD_PIERCE, **kwargs)
        assert _finite(fit.zp.E_kPa, fit.cytoplasm.E_kPa)
        return fit.zp.E_kPa, fit.cytoplasm.E_kPa

    check_outcome("afm.fit_pierce", call)


def test_fit_pierce_arguments() -> None:
    with exercised("afm.fit_pierce"):
        _fit_pierce_arguments()


def _creep_numbers(fit) -> tuple[float, float, float]:
    assert _finite(fit.E0_kPa, fit.E_inf_kPa, fit.relative_rms) and fit.E0_kPa > 0
    return fit.E0_kPa, fit.E_inf_kPa, fit.relative_rms


@FUZZ
@given(name=st.sampled_from(["half_angle_deg", "nu", "per_decade"]), value=NONSENSE)
@example(name="per_decade", value=3)
@example(name="per_decade", value=True)
def _fit_creep_arguments(name: str, value: object) -> None:
    check_outcome(
        "afm.fit_creep",
        lambda: _creep_numbers(fit_creep(GOOD_HOLD, **{name: value})),
        names=name,
        own_file=True,
    )


def test_fit_creep_arguments() -> None:
    with exercised("afm.fit_creep"):
        _fit_creep_arguments()


@FUZZ
@given(name=st.sampled_from(["model", "geometry", "radius_um", "nu", "per_decade"]), value=NONSENSE)
@example(name="radius_um", value=2.0)
@example(name="radius_um", value=-2.0)
def _fit_creep_tip_arguments(name: str, value: object) -> None:
    # issue 28: the creep fit takes any tip of afm.models
    kwargs: dict = {"model": "hertz_paraboloid", "geometry": {"radius_um": 5.0}}
    if name == "radius_um":
        kwargs["geometry"] = {"radius_um": value}
    else:
        kwargs[name] = value
    check_outcome("afm.fit_creep_tip", lambda: _creep_numbers(fit_creep_tip(GOOD_HOLD, **kwargs)))


def test_fit_creep_tip_arguments() -> None:
    with exercised("afm.fit_creep_tip"):
        _fit_creep_tip_arguments()


@FUZZ
@given(
    indentation=hnp.arrays(
        np.float64, st.integers(0, 30), elements=st.floats(allow_nan=True, allow_infinity=True)
    ),
    force=st.floats(allow_nan=True, allow_infinity=True),
)
@example(indentation=GOOD_HOLD.indentation_um[::10].copy(), force=5.0)
@example(indentation=GOOD_HOLD.indentation_um[::-10].copy(), force=5.0)  # shrinking
def _creep_records(indentation: np.ndarray, force: float) -> None:
    t = np.arange(indentation.size, dtype=float)
    check_outcome(
        "afm.CreepData + fit_creep",
        lambda: _creep_numbers(fit_creep(CreepData(t, np.full(t.size, force), indentation))),
    )


def test_creep_records() -> None:
    with exercised("afm.CreepData + fit_creep"):
        _creep_records()


@FUZZ
@given(j0=NONSENSE, j=NONSENSE, lam=NONSENSE)
@example(j0=0.5, j=0.2, lam=1.0)
@example(j0=-0.5, j=0.2, lam=1.0)
def _prony_conversions(j0: object, j: object, lam: object) -> None:
    def relax() -> tuple[float, ...]:
        out = relaxation_from_creep(CreepProny(j0, (j,), (lam,)))
        assert out.G0_kPa > 0 and all(g >= 0 for g in out.g)
        return (out.G0_kPa, *out.g, *out.tau_s)

    def creep() -> tuple[float, ...]:
        out = creep_from_relaxation(RelaxationProny(j0, (j,), (lam,)))
        assert out.J0_per_kPa > 0
        return (out.J0_per_kPa, *out.J_per_kPa, *out.lambda_s)

    check_outcome("afm.relaxation_from_creep", relax)
    check_outcome("afm.creep_from_relaxation", creep)


def test_prony_conversions() -> None:
    with exercised("afm.relaxation_from_creep", "afm.creep_from_relaxation"):
        _prony_conversions()


CONVERSIONS: dict[str, Callable[[object, object, object], np.ndarray | float]] = {
    "afm.compliance_from_indentation": lambda a, b, c: compliance_from_indentation(
        np.array([1.0]), a, b, c
    ),
    "afm.indentation_from_compliance": lambda a, b, c: indentation_from_compliance(
        np.array([0.1]), a, b, c
    ),
    "afm.spring_constant_nN_per_um": lambda a, b, c: spring_constant_nN_per_um(a),
    "afm.force_from_deflection": lambda a, b, c: force_from_deflection(np.array([0.1]), a, b),
}


@FUZZ
@given(a=NONSENSE, b=NONSENSE, c=NONSENSE)
@example(a=5.0, b=10.0, c=0.5)
@example(a=5.0, b=10.0, c=math.nan)
@example(a=math.nan, b=10.0, c=0.5)
def _conversions(a: object, b: object, c: object) -> None:
    for label, func in CONVERSIONS.items():
        check_outcome(label, lambda func=func: np.asarray(func(a, b, c)))


def test_conversions() -> None:
    with exercised(*CONVERSIONS):
        _conversions()


@FUZZ
@given(name=st.text(max_size=20), source=st.text(max_size=40), e=NONSENSE, nu=NONSENSE)
@example(name="zp", source="fuzz", e=7.01, nu=0.5)
@example(name="zp", source="fuzz", e=-7.01, nu=0.5)
def _material_and_exports(name: str, source: str, e: object, nu: object) -> None:
    def call() -> str:
        material = MaterialFile(name, source, e, nu, (0.2,), (1.0,))
        assert "\n" not in ansys_prony_block(material).split("\n", 1)[0]
        return febio_material(material)

    check_outcome("afm.MaterialFile + exports", call)


def test_material_and_exports() -> None:
    with exercised("afm.MaterialFile + exports"):
        _material_and_exports()


@pytest.mark.parametrize("n_sigma", [float("nan"), 0.0, -1.0, float("inf")])
def test_issue_examples_n_sigma(n_sigma: float) -> None:
    with pytest.raises(InputError, match="n_sigma"):
        fit_indentation(GOOD_CURVE, n_sigma=n_sigma)


@FUZZ
@given(
    name=st.sampled_from(
        ["E_kPa", "contact_point_um", "max_piezo_um", "n_points", "k_nN_per_um", "noise_fraction"]
    ),
    value=NONSENSE,
)
@example(name="E_kPa", value=3.0)
@example(name="E_kPa", value=math.nan)
def _synthetic_curve_arguments(name: str, value: object) -> None:
    kwargs = {"E_kPa": 7.01, "contact_point_um": 5.0, "n_points": 200, name: value}
    check_outcome("afm.indentation_curve", lambda: indentation_curve(**kwargs).force_nN)


def test_synthetic_curve_arguments() -> None:
    with exercised("afm.indentation_curve"):
        _synthetic_curve_arguments()


@FUZZ
@given(
    name=st.sampled_from(["E_zp_kPa", "pierce_force_nN", "residual_fraction", "trigger_force_nN"]),
    value=NONSENSE,
)
@example(name="E_zp_kPa", value=5.0)
@example(name="E_zp_kPa", value=-5.0)
def _synthetic_pierce_arguments(name: str, value: object) -> None:
    kwargs = {"E_zp_kPa": 7.01, "E_cytoplasm_kPa": 1.55, "n_points": 300, name: value}
    check_outcome("afm.pierce_curve", lambda: pierce_curve(**kwargs).force_nN)


def test_synthetic_pierce_arguments() -> None:
    with exercised("afm.pierce_curve"):
        _synthetic_pierce_arguments()


# --- class 5: time columns and holds in files ------------------------------------------------

TIME_FAULTS = ("none", "back", "repeated", "nan", "inf")
"""What is done to one data row of a time column: nothing, a value below the row above it,
the same value, NaN or inf."""


def _time_with(fault: str, row: int, back: float, n: int, end: float) -> np.ndarray:
    time = np.linspace(0.0, end, n)
    if fault == "back":
        time[row] = time[row - 1] - back
    elif fault == "repeated":
        time[row] = time[row - 1]
    elif fault in ("nan", "inf"):
        time[row] = float(fault)
    return time


def _refused_naming(path: Path, column: str, expected: str, call: Callable[[], object]) -> None:
    with pytest.raises(InputError) as info:
        call()
    message = str(info.value)
    assert message.startswith(f"{path}: {column}: expected"), message
    assert expected in message, message


@FUZZ
@given(
    fault=st.sampled_from(TIME_FAULTS),
    fraction=st.floats(0.0, 1.0),
    back=st.floats(0.0, 1e6),
    separator=st.sampled_from([",", "\t", " "]),
)
def _curve_time_columns(
    tmp_path: Path, fault: str, fraction: float, back: float, separator: str
) -> None:
    n = GOOD_CURVE.piezo_um.size
    row = 1 + int(fraction * (n - 2))
    time = _time_with(fault, row, back, n, 1.5)
    path = tmp_path / "curve.txt"
    columns = (time, GOOD_CURVE.piezo_um, GOOD_CURVE.force_nN)
    rows = (separator.join(repr(float(v)) for v in r) for r in zip(*columns, strict=True))
    header = separator.join(("time_s", "piezo_um", "force_nN"))
    path.write_text(f"# spring_constant_N_per_m = 0.07\n{header}\n" + "\n".join(rows) + "\n")
    label = "afm.read_curve (time column)"
    if fault == "none":
        curve = check_outcome(label, lambda: read_curve(path))
        np.testing.assert_array_equal(curve.time_s, time)
        return
    what = "finite numbers" if fault in ("nan", "inf") else "values increasing row by row"
    check_outcome(label, lambda: read_curve(path), names=f"data row {row + 1}")
    _refused_naming(path, "time_s", f"{what} (data row {row + 1}", lambda: read_curve(path))


def test_curve_time_columns(tmp_path: Path) -> None:
    with exercised("afm.read_curve (time column)"):
        _curve_time_columns(tmp_path=tmp_path)


@FUZZ
@given(
    fault=st.sampled_from([*TIME_FAULTS, "hold shrinks", "hold reversed"]),
    fraction=st.floats(0.0, 1.0),
    back=st.floats(0.0, 1e6),
    noise=st.sampled_from([0.0, 1e-3, 3e-3]),
)
def _creep_files(tmp_path: Path, fault: str, fraction: float, back: float, noise: float) -> None:
    n = _T.size
    row = 1 + int(fraction * (n - 2))
    time = _time_with(fault, row, back, n, 6.0)
    delta = creep_indentation(TRUTH, _T, 5.0)
    delta *= 1 + noise * np.random.default_rng(row).standard_normal(n)
    if fault == "hold reversed":
        delta = delta[::-1]
    elif fault == "hold shrinks":  # loses 1 % to 30 % of its depth over the hold
        delta = delta[0] * (1 - (0.01 + 0.29 * fraction) * _T / _T[-1])
    contact, k, force = 5.0, 0.07, np.full(n, 5.0)
    path = write_creep(tmp_path / "hold.csv", time, force, contact + delta + 5.0 / 70, contact, k)
    label = "afm.read_creep"
    if fault == "none":
        data = check_outcome(label, lambda: read_creep(path))
        np.testing.assert_allclose(data.indentation_um, delta, rtol=1e-8, atol=1e-9)
        return
    if fault.startswith("hold"):
        column, expected = "indentation_um", "an indentation that does not shrink"
    else:
        column = "time_s"
        what = "finite numbers" if fault in ("nan", "inf") else "values increasing row by row"
        expected = f"{what} (data row {row + 1}"
    check_outcome(label, lambda: read_creep(path), names=column)
    _refused_naming(path, column, expected, lambda: read_creep(path))


def test_creep_files(tmp_path: Path) -> None:
    with exercised("afm.read_creep"):
        _creep_files(tmp_path=tmp_path)


_ZONA_ARGS = {
    "e_fit_kPa": 5.0,
    "depth_um": 1.5,
    "zona_um": 15.0,
    "cytoplasm_kPa": 1.55,
    "probe_um": 10.0,
    "cell_um": 70.0,
}
_CONE_ARGS = {**{k: v for k, v in _ZONA_ARGS.items() if k != "probe_um"}, "half_angle_deg": 10.0}


@FUZZ
@given(
    cone=st.booleans(),
    name=st.sampled_from(sorted({*_ZONA_ARGS, *_CONE_ARGS})),
    value=NONSENSE,
)
@example(cone=True, name="depth_um", value=2.8)
@example(cone=False, name="depth_um", value=5e-324)
@example(cone=True, name="half_angle_deg", value=math.inf)
def _shell_correction_arguments(cone: bool, name: str, value: object) -> None:
    # the shelled-oocyte corrections (issue 28 C): E_ZP finite and positive, or refused
    args = dict(_CONE_ARGS if cone else _ZONA_ARGS)
    if name in args:
        args[name] = value
    fn = cone_zona_modulus if cone else zona_modulus
    e_zp = check_outcome("afm.corrections", lambda: fn(**args))
    if e_zp is not None:
        assert e_zp > 0


def test_shell_correction_arguments() -> None:
    with exercised("afm.corrections"):
        _shell_correction_arguments()


@FUZZ
@given(
    cone=st.booleans(), name=st.sampled_from(["geometry", "depth_um", "layer_um"]), value=NONSENSE
)
@example(cone=False, name="depth_um", value=2.0)
@example(cone=True, name="layer_um", value=0.0)
def _bottom_effect_arguments(cone: bool, name: str, value: object) -> None:
    # the bonded-layer corrections (Dimitriadis, Garcia): a finite factor >= 1, or refused
    model, geometry = ("sneddon_cone", {"half_angle_deg": 35.0}) if cone else ("hertz_sphere", {})
    args: dict = {"geometry": geometry or {"radius_um": 5.0}, "depth_um": 2.0, "layer_um": 8.0}
    args[name] = value
    f = check_outcome("afm.bottom_effect", lambda: fit_factor(model, **args))
    if f is not None:
        assert f >= 1.0


def test_bottom_effect_arguments() -> None:
    with exercised("afm.bottom_effect"):
        _bottom_effect_arguments()


_T_RAMP = np.linspace(0.0, 0.1, 400)
_X_RAMP = np.concatenate([np.linspace(-1.0, 1.0, 200), np.linspace(1.0, -1.0, 200)])
_RAMP = RampCurve(_T_RAMP, _X_RAMP, 0.5 * np.clip(_X_RAMP, 0.0, None) ** 2)


@FUZZ
@given(
    name=st.sampled_from(["nu", "terms", "t0_s", "start_tau_s", "relaxation", "last_force"]),
    value=NONSENSE,
)
@example(name="start_tau_s", value=0.01)
@example(name="last_force", value=1e300)
@example(name="nu", value=0.5)
def _fit_ramp_arguments(name: str, value: object) -> None:
    # issue 28 B: the viscoelastic ramp fit; a scalar start_tau_s and a 1e300 force were a
    # traceback and an infinite residual
    force, kwargs = _RAMP.force_nN.copy(), {}
    if name == "last_force":
        force[-1] = value if isinstance(value, float) else force[-1]
    else:
        kwargs[name] = value
    fit = check_outcome(
        "afm.fit_ramp",
        lambda: fit_ramp(
            RampCurve(_T_RAMP, _X_RAMP, force), "hertz_paraboloid", {"radius_um": 5.0}, **kwargs
        ),
    )
    if fit is not None:
        assert math.isfinite(fit.residual_rms_nN) and math.isfinite(fit.r_squared)


def test_fit_ramp_arguments() -> None:
    with exercised("afm.fit_ramp"):
        _fit_ramp_arguments()
