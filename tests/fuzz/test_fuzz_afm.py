"""Property tests (hypothesis) of the public functions of ``afm`` with nonsense arguments.

Every call either returns finite numbers or raises :class:`afm.errors.InputError` naming
the argument; never another exception (IndexError, ZeroDivisionError, LinAlgError, numpy's
ValueError, ...), never a hang. CI runs 25 derandomized examples per test (seconds in all);
``OOCYTE_FUZZ_FULL=1`` runs 1 000 random ones per test, like the rest of ``tests/fuzz``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from afm.creep import (
    CreepData,
    compliance_from_indentation,
    fit_creep,
    fit_creep_tip,
    indentation_from_compliance,
)
from afm.curve import ForceCurve, force_from_deflection, spring_constant_nN_per_um
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
from oocyte_fe.errors import InputError
from tests.fuzz.harness import FULL

EXAMPLES = 1000 if FULL else 25
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,  # a wall-clock deadline fails on a loaded machine; nothing here loops
    derandomize=not FULL,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

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
_T = np.linspace(0.0, 6.0, 301)
GOOD_HOLD = CreepData(
    _T,
    np.full(_T.size, 5.0),
    creep_indentation(RelaxationProny(7.01 / 3, (0.3,), (0.5,)), _T, 5.0),
)


def _finite(*values: float) -> bool:
    return all(math.isfinite(float(v)) for v in values)


def _call(func, *args, **kwargs):
    """Run ``func``; InputError is an accepted outcome (returns None), anything else fails."""
    try:
        return func(*args, **kwargs)
    except InputError as exc:
        assert str(exc).count("\n") == 0 and exc.expected
        return None


@FUZZ
@given(
    name=st.sampled_from(["nu", "n_sigma", "model", "contact_method", "geometry", "fit_range"]),
    value=NONSENSE,
)
def test_fit_indentation_arguments(name, value):
    kwargs = {name: value}
    if name == "geometry":
        kwargs = {"geometry": {"half_angle_deg": value}}
    if name == "fit_range":
        fit_range = _call(FitRange, max_indentation_um=value)
        if fit_range is None:
            return
        kwargs = {"fit_range": fit_range}
    fit = _call(fit_indentation, GOOD_CURVE, **kwargs)
    if fit is not None:
        assert _finite(fit.E_kPa, fit.contact_point_um) and fit.E_kPa > 0


@FUZZ
@given(
    piezo_scale=st.floats(allow_nan=True, allow_infinity=True),
    force_scale=st.floats(allow_nan=True, allow_infinity=True),
    k=NONSENSE,
)
def test_scaled_curves(piezo_scale, force_scale, k):
    def build():
        return ForceCurve(
            GOOD_CURVE.piezo_um * piezo_scale, GOOD_CURVE.force_nN * force_scale, k, "scaled.csv"
        )

    curve = _call(build)
    if curve is not None:
        fit = _call(fit_indentation, curve)
        if fit is not None:
            assert _finite(fit.E_kPa, fit.contact_point_um)
            assert fit.rating.startswith(("good (", "poor: "))  # issue 28's rating never raises


@FUZZ
@given(
    force=hnp.arrays(
        np.float64,
        st.integers(0, 40),
        elements=st.floats(allow_nan=True, allow_infinity=True, width=64),
    ),
)
def test_arbitrary_force_arrays(force):
    curve = _call(ForceCurve, np.arange(force.size, dtype=float), force, 1.0)
    if curve is not None:
        fit = _call(fit_indentation, curve)
        if fit is not None:
            assert _finite(fit.E_kPa, fit.contact_point_um)
            assert fit.rating.startswith(("good (", "poor: "))  # issue 28's rating never raises


@FUZZ
@given(
    name=st.sampled_from(["nu", "min_drop_fraction", "geometry", "model", "contact_method"]),
    value=NONSENSE,
)
def test_fit_pierce_arguments(name, value):
    kwargs = {"geometry": {"half_angle_deg": value}} if name == "geometry" else {name: value}
    fit = _call(fit_pierce, GOOD_PIERCE, **kwargs)
    if fit is not None:
        assert _finite(fit.zp.E_kPa, fit.cytoplasm.E_kPa)


@FUZZ
@given(name=st.sampled_from(["half_angle_deg", "nu", "per_decade"]), value=NONSENSE)
def test_fit_creep_arguments(name, value):
    fit = _call(fit_creep, GOOD_HOLD, **{name: value})
    if fit is not None:
        assert _finite(fit.E0_kPa, fit.E_inf_kPa, fit.relative_rms)


@FUZZ
@given(name=st.sampled_from(["model", "geometry", "radius_um", "nu", "per_decade"]), value=NONSENSE)
def test_fit_creep_tip_arguments(name, value):
    # issue 28: the creep fit takes any tip of afm.models
    kwargs: dict = {"model": "hertz_paraboloid", "geometry": {"radius_um": 5.0}}
    if name == "radius_um":
        kwargs["geometry"] = {"radius_um": value}
    else:
        kwargs[name] = value
    fit = _call(fit_creep_tip, GOOD_HOLD, **kwargs)
    if fit is not None:
        assert _finite(fit.E0_kPa, fit.E_inf_kPa, fit.relative_rms)


@FUZZ
@given(
    indentation=hnp.arrays(
        np.float64, st.integers(0, 30), elements=st.floats(allow_nan=True, allow_infinity=True)
    ),
    force=st.floats(allow_nan=True, allow_infinity=True),
)
def test_creep_records(indentation, force):
    t = np.arange(indentation.size, dtype=float)
    data = _call(CreepData, t, np.full(indentation.size, force), indentation)
    if data is not None:
        fit = _call(fit_creep, data)
        if fit is not None:
            assert _finite(fit.E0_kPa, fit.relative_rms)


@FUZZ
@given(j0=NONSENSE, j=NONSENSE, lam=NONSENSE)
def test_prony_conversions(j0, j, lam):
    creep = _call(CreepProny, j0, (j,), (lam,))
    if creep is not None:
        relax = _call(relaxation_from_creep, creep)
        if relax is not None:
            assert _finite(relax.G0_kPa, *relax.g, *relax.tau_s)
    relax = _call(RelaxationProny, j0, (j,), (lam,))
    if relax is not None:
        creep = _call(creep_from_relaxation, relax)
        if creep is not None:
            assert _finite(creep.J0_per_kPa, *creep.J_per_kPa, *creep.lambda_s)


@FUZZ
@given(a=NONSENSE, b=NONSENSE, c=NONSENSE, d=NONSENSE)
def test_conversions(a, b, c, d):
    for func, args in (
        (compliance_from_indentation, (np.array([1.0]), a, b, c)),
        (indentation_from_compliance, (np.array([0.1]), a, b, c)),
        (spring_constant_nN_per_um, (a,)),
        (force_from_deflection, (np.array([0.1]), a, b)),
    ):
        out = _call(func, *args)
        if out is not None:
            assert np.all(np.isfinite(out))
    del d


@FUZZ
@given(name=st.text(max_size=20), source=st.text(max_size=40), e=NONSENSE, nu=NONSENSE)
def test_material_and_exports(name, source, e, nu):
    material = _call(MaterialFile, name, source, e, nu, (0.2,), (1.0,))
    if material is not None:
        assert "\n" not in ansys_prony_block(material).split("\n", 1)[0]
        _call(febio_material, material)


@pytest.mark.parametrize("n_sigma", [float("nan"), 0.0, -1.0, float("inf")])
def test_issue_examples_n_sigma(n_sigma):
    with pytest.raises(InputError, match="n_sigma"):
        fit_indentation(GOOD_CURVE, n_sigma=n_sigma)


@FUZZ
@given(
    name=st.sampled_from(
        ["E_kPa", "contact_point_um", "max_piezo_um", "n_points", "k_nN_per_um", "noise_fraction"]
    ),
    value=NONSENSE,
)
def test_synthetic_curve_arguments(name, value):
    kwargs = {"E_kPa": 7.01, "contact_point_um": 5.0, "n_points": 200, name: value}
    curve = _call(indentation_curve, **kwargs)
    if curve is not None:
        assert np.all(np.isfinite(curve.force_nN))


@FUZZ
@given(
    name=st.sampled_from(["E_zp_kPa", "pierce_force_nN", "residual_fraction", "trigger_force_nN"]),
    value=NONSENSE,
)
def test_synthetic_pierce_arguments(name, value):
    kwargs = {"E_zp_kPa": 7.01, "E_cytoplasm_kPa": 1.55, "n_points": 300, name: value}
    curve = _call(pierce_curve, **kwargs)
    if curve is not None:
        assert np.all(np.isfinite(curve.force_nN))
