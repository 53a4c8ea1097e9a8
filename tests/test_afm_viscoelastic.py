"""Ting's method and the viscoelastic ramp fit: closed forms, known parameters, FE curves."""

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.special import beta as beta_fn
from scipy.special import betainc

from afm import RampCurve, fit_ramp, ramp_from_piezo, read_material, write_material
from afm.models import get_model
from afm.viscoelastic import RELAXATION_MODELS, get_relaxation_model, ting_force
from oocyte_fe.errors import InputError

FE_DATA = Path(__file__).parent / "data" / "afm_ramp_fe"
PRONY_TRUE = {"E_inf_kPa": 0.4, "E_kPa": (0.3, 0.3), "tau_s": (0.05, 0.5)}
"""The FE material of tests/data/afm_ramp_fe (E0 = 1 kPa, g = 0.3, 0.3; nu = 0.5)."""

TIPS = {
    "sneddon_cone": ({"half_angle_deg": 20.0}, 2.0),
    "hertz_paraboloid": ({"radius_um": 5.0}, 1.5),
    "hertz_sphere": ({"radius_um": 5.0}, 1.5),
}


def _prefactor(model: str, geometry: dict, nu: float) -> float:
    """shape(delta) = prefactor * delta^n for the cone and the paraboloid."""
    return get_model(model).shape(np.array([1.0]), geometry, nu)[0]


def triangle(n: int, ramp_s: float = 1.0, speed: float = 1.0, pre: int = 0) -> tuple:
    """Times and indentation of a triangular ramp (``pre`` points before contact)."""
    h = ramp_s / (n - 1)
    t = h * np.arange(pre + 2 * n - 1)
    s = t - pre * h
    x = np.where(s <= ramp_s, speed * s, speed * (2 * ramp_s - s))
    return t, x, h


def synthetic_force(t, x, h, model, geometry, relaxation, amplitudes, theta, nu=0.5):
    rel = get_relaxation_model(relaxation)
    delta = np.clip(x, 0.0, None)
    phi = rel.integrals(h * np.arange(t.size + 1), np.asarray(theta)) @ np.asarray(amplitudes)
    return ting_force(get_model(model).shape(delta, geometry, 0.5), delta, phi, h)


# --- Ting's force against closed forms -------------------------------------------------------


@pytest.mark.parametrize("model", ["sneddon_cone", "hertz_paraboloid"])
def test_power_law_loading_and_retract_match_the_closed_forms(model):
    # delta = v t up to tm, v (2 tm - t) after; E = E0 (t/t0)^-beta; shape = C delta^n:
    # loading F = C E0 t0^b v^n n B(n, 1-b) t^(n-b) (Efremov 2017, eq. 8-9);
    # retract t1 = t - 2^(1/(1-b)) (t - tm), F = same with B(t1/t; n, 1-b) (incomplete)
    geometry, n = TIPS[model]
    e0, b, t0 = 2.0, 0.3, 0.5
    t, x, h = triangle(2001)
    force = synthetic_force(t, x, h, model, geometry, "power_law", [e0], [b, t0])
    c = _prefactor(model, geometry, 0.5)
    full = c * e0 * t0**b * n * beta_fn(n, 1 - b) * t ** (n - b)
    t1 = np.clip(t - 2 ** (1 / (1 - b)) * (t - 1.0), 0.0, None)
    exact = np.where(t <= 1.0, full, full * betainc(n, 1 - b, t1 / np.maximum(t, 1e-300)))
    # measured: loading 2e-5, retract 1e-4 (paraboloid) / 3e-4 (cone): t1 interpolated in a step
    assert np.max(np.abs(force - exact)) / exact.max() < 5e-4


def test_standard_linear_solid_loading_matches_quadrature():
    # F(t) = C v^1.5 1.5 int_0^t [E_inf + E1 exp(-(t-s)/tau)] s^0.5 ds  (paraboloid, delta = v t)
    geometry, _ = TIPS["hertz_paraboloid"]
    e_inf, e1, tau = 0.4, 0.6, 0.2
    t, x, h = triangle(1001)
    force = synthetic_force(t, x, h, "hertz_paraboloid", geometry, "standard_linear_solid",
                            [e_inf, e1], [tau])  # fmt: skip
    c = _prefactor("hertz_paraboloid", geometry, 0.5)
    for ti in (0.1, 0.5, 1.0):
        integral = quad(lambda s, ti=ti: (e_inf + e1 * math.exp(-(ti - s) / tau)) * s**0.5, 0, ti)
        exact = c * 1.5 * integral[0]
        assert force[round(ti / h)] == pytest.approx(exact, rel=2e-4)


def test_elastic_limit_gives_the_elastic_force_on_loading_and_retract():
    # constant E: Ting reduces to F = E shape(delta(t)) both ways (t1: delta(t1) = delta(t))
    geometry, _ = TIPS["hertz_sphere"]
    t, x, h = triangle(801, pre=50)
    force = synthetic_force(t, x, h, "hertz_sphere", geometry, "prony", [1.7, 0.0], [0.1])
    elastic = 1.7 * get_model("hertz_sphere").shape(np.clip(x, 0, None), geometry, 0.5)
    assert np.max(np.abs(force - elastic)) / elastic.max() < 1e-3


@settings(max_examples=15, deadline=None)
@given(
    e0=st.floats(0.01, 100.0),
    b=st.floats(0.0, 0.8),
    speed=st.floats(0.05, 20.0),
)
def test_power_law_loading_is_linear_in_E0_and_matches_for_any_speed(e0, b, speed):
    geometry, n = TIPS["sneddon_cone"]
    t, x, h = triangle(401, ramp_s=1.0, speed=speed)
    force = synthetic_force(t, x, h, "sneddon_cone", geometry, "power_law", [e0], [b, 1.0])
    c = _prefactor("sneddon_cone", geometry, 0.5)
    exact = c * e0 * speed**n * n * beta_fn(n, 1 - b) * t[:401] ** (n - b)
    # the discretisation error grows with beta: 2e-4 of the peak at beta = 0.75 (400 steps)
    assert np.max(np.abs(force[:401] - exact)) <= 5e-4 * exact.max()


# --- fits on synthetic ramps with known parameters ---------------------------------------------


def synthetic_ramp(model, relaxation, amplitudes, theta, ramp_s=1.0, n=301, pre=60, x0=0.3):
    geometry, _ = TIPS[model]
    t, x, h = triangle(n, ramp_s=ramp_s, speed=0.5 / ramp_s, pre=pre)
    force = synthetic_force(t, x, h, model, geometry, relaxation, amplitudes, theta)
    return RampCurve(t, x + x0, force, f"{model} T={ramp_s:g}")


@pytest.mark.parametrize("model", sorted(TIPS))
@pytest.mark.parametrize(
    ("relaxation", "amplitudes", "theta"),
    [
        ("power_law", [1.5], [0.25, 1.0]),
        ("standard_linear_solid", [0.5, 1.0], [0.2]),
    ],
)
def test_fit_recovers_known_parameters_from_the_approach(model, relaxation, amplitudes, theta):
    ramp = synthetic_ramp(model, relaxation, amplitudes, theta)
    fit = fit_ramp(ramp, model, TIPS[model][0], relaxation=relaxation, use_retract=False)
    assert fit.amplitudes_kPa == pytest.approx(amplitudes, rel=1e-3)
    assert fit.theta[0] == pytest.approx(theta[0], rel=1e-3)
    assert fit.contact_points_um[0] == pytest.approx(0.3, abs=1e-4)
    assert fit.quality == "good"


def test_two_term_prony_from_two_speeds_with_retract_and_material_file(tmp_path):
    truth = ([0.4, 0.3, 0.3], [0.05, 0.5])
    ramps = [synthetic_ramp("hertz_paraboloid", "prony", *truth, ramp_s=s) for s in (0.1, 1.0)]
    fit = fit_ramp(ramps, "hertz_paraboloid", TIPS["hertz_paraboloid"][0], terms=2)
    assert fit.used_retract
    assert fit.amplitudes_kPa == pytest.approx(truth[0], rel=1e-3)
    assert fit.theta == pytest.approx(truth[1], rel=1e-3)
    path = write_material(fit.material("cytoplasm", "synthetic ramps"), tmp_path / "m.toml")
    back = read_material(path)
    assert back.E_kPa == pytest.approx(1.0, rel=1e-3)
    assert back.g == pytest.approx((0.3, 0.3), rel=1e-3)
    assert back.tau_s == pytest.approx(truth[1], rel=1e-3)
    assert "ramp fit (prony, Ting) good" in back.source


def test_ramp_from_piezo_removes_baseline_and_deflection():
    # a cantilever k = 50 nN/um and a tilted baseline (0.1 pN noise on it): the fit on the
    # recorded piezo and force equals the one on the tip position
    ramp = synthetic_ramp("hertz_paraboloid", "standard_linear_solid", [0.5, 1.0], [0.2], pre=300)
    k = 50.0
    piezo = ramp.tip_position_um + ramp.force_nN / k
    noise = 1e-4 * np.random.default_rng(1).standard_normal(piezo.size)
    built = ramp_from_piezo(ramp.time_s, piezo, ramp.force_nN + 0.02 + 0.01 * piezo + noise, k)
    assert np.max(np.abs(built.force_nN - ramp.force_nN)) < 1e-3 * ramp.force_nN.max()
    fit = fit_ramp(
        built, "hertz_paraboloid", {"radius_um": 5.0}, relaxation="standard_linear_solid"
    )
    assert fit.parameters["E0_kPa"] == pytest.approx(1.5, rel=0.01)
    assert fit.parameters["tau_s"] == pytest.approx(0.2, rel=0.01)


# --- FE curves of a Prony cell (benchmarks/afm_ramp_fe_curves.py) ------------------------------


def fe_ramp(ramp_s: float, pre: int = 20) -> RampCurve:
    """The FE's probe advance and force, with ``pre`` non-contact points of the same speed."""
    t, x, f = np.loadtxt(FE_DATA / f"ramp_T{ramp_s:g}s.csv", delimiter=",").T
    h = t[1] - t[0]
    before = -h * np.arange(pre, 0, -1)
    return RampCurve(
        np.r_[before, t] - before[0],
        np.r_[x[1] / h * before, x],
        np.r_[np.zeros(pre), f],
        f"FE ramp {ramp_s:g} s",
    )


R_STAR = {"radius_um": 10.0 * 70.0 / 80.0}
"""The effective radius Rp R / (Rp + R) of the 10 um probe on the 140 um cell, um."""


def test_fe_curves_two_speeds_recover_the_prony_series():
    # The FE is 1.5 % below Hertz's sphere at d/R* = 0.023 (docs/fe.md): all moduli within 3 %
    fit = fit_ramp([fe_ramp(0.1), fe_ramp(1.0)], "hertz_sphere", R_STAR, terms=2)
    par = fit.parameters
    assert fit.quality == "good", fit.quality
    assert par["E_inf_kPa"] == pytest.approx(PRONY_TRUE["E_inf_kPa"], rel=0.03)  # -2.6 %
    assert par["E_kPa"] == pytest.approx(PRONY_TRUE["E_kPa"], rel=0.03)  # -0.3, -0.7 %
    assert par["tau_s"] == pytest.approx(PRONY_TRUE["tau_s"], rel=0.10)  # 0, +3 %
    assert par["E0_kPa"] == pytest.approx(1.0, rel=0.03)  # -1.3 %


@pytest.mark.parametrize(("ramp_s", "flagged"), [(0.1, "tau_2"), (1.0, "tau_1")])
def test_fe_single_speed_flags_the_time_it_cannot_resolve(ramp_s, flagged):
    # 0.1 s in contact cannot separate tau = 0.5 s from E_inf; 33 ms steps do not resolve 0.05 s
    fit = fit_ramp(fe_ramp(ramp_s), "hertz_sphere", R_STAR, terms=2)
    assert any(line.startswith(flagged) for line in fit.undetermined), fit.undetermined
    assert fit.quality.startswith("poor")


# --- input checks ------------------------------------------------------------------------------


def test_registry_and_bad_input():
    assert set(RELAXATION_MODELS) == {"power_law", "standard_linear_solid", "prony"}
    ramp = synthetic_ramp("hertz_paraboloid", "power_law", [1.0], [0.2, 1.0])
    with pytest.raises(InputError, match="relaxation"):
        fit_ramp(ramp, relaxation="maxwell", geometry={"radius_um": 5.0})
    with pytest.raises(InputError, match="terms"):
        fit_ramp(ramp, geometry={"radius_um": 5.0}, terms=0)
    with pytest.raises(InputError, match="t0_s"):
        fit_ramp(ramp, geometry={"radius_um": 5.0}, relaxation="power_law", t0_s=-1.0)
    with pytest.raises(InputError, match="time_s"):
        RampCurve(ramp.time_s[::-1], ramp.tip_position_um, ramp.force_nN)
    with pytest.raises(InputError, match="material"):
        fit = fit_ramp(ramp, geometry={"radius_um": 5.0}, relaxation="power_law")
        fit.material("x", "y")


def test_uneven_sampling_is_resampled():
    ramp = synthetic_ramp("hertz_paraboloid", "standard_linear_solid", [0.5, 1.0], [0.2])
    keep = np.ones(ramp.time_s.size, bool)
    keep[5::7] = False  # drop every 7th sample
    uneven = RampCurve(ramp.time_s[keep], ramp.tip_position_um[keep], ramp.force_nN[keep])
    assert uneven.resampled
    fit = fit_ramp(uneven, geometry={"radius_um": 5.0}, relaxation="standard_linear_solid")
    assert fit.parameters["E0_kPa"] == pytest.approx(1.5, rel=0.02)


def test_viscoelastic_imports_only_the_ground_floor_of_oocyte_fe():
    import subprocess
    import sys

    code = (
        "import sys, afm.viscoelastic; "
        "print(sorted(m for m in sys.modules if m.startswith('oocyte_fe')))"
    )
    root = Path(__file__).parents[1]
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=root,
        env={"PYTHONPATH": str(root), "PATH": ""},
    ).stdout
    assert out.strip() == "['oocyte_fe', 'oocyte_fe.checks', 'oocyte_fe.errors']"


@pytest.mark.parametrize("key", sorted(RELAXATION_MODELS))
def test_every_relaxation_model_is_documented_and_its_integral_is_consistent(key):
    # the convolution uses Phi = int E; the fit's modulus uses the basis: Phi' must equal it
    import sys

    model = RELAXATION_MODELS[key]
    doc = sys.modules[model.integrals.__module__].__doc__
    assert "kPa" in doc and "[s]" in doc and "Reference" in doc
    theta = {"power_law": [0.3, 0.7], "standard_linear_solid": [0.2], "prony": [0.05, 0.5]}[key]
    t = np.linspace(0.01, 2.0, 50)
    eps = 1e-6
    slope = model.integrals(t + eps, np.array(theta)) - model.integrals(t - eps, np.array(theta))
    basis = model.basis(t, np.array(theta))
    np.testing.assert_allclose(slope / (2 * eps), basis, rtol=1e-6, atol=1e-8)
    assert model.integrals(np.array([0.0]), np.array(theta)) == pytest.approx(0.0, abs=1e-15)


def test_ting_force_refuses_bad_input():
    with pytest.raises(InputError, match="integrals"):
        ting_force(np.zeros(5), np.zeros(5), np.zeros(5), 0.1)
    with pytest.raises(InputError, match="step_s"):
        ting_force(np.zeros(5), np.zeros(5), np.zeros(6), 0.0)
    with pytest.raises(InputError, match="delta"):
        ting_force(np.zeros(5), np.array([0, 1, np.nan, 0, 0]), np.zeros(6), 0.1)


def test_retract_amplitude_derivative_matches_finite_differences():
    # dF/dA_k = basis force + change through t1 (ting.retract_force docstring)
    from afm.viscoelastic.ting import retract_force

    geometry, _ = TIPS["hertz_paraboloid"]
    t, x, h = triangle(201, pre=20)
    delta = np.clip(x, 0.0, None)
    d_shape = np.diff(get_model("hertz_paraboloid").shape(delta, geometry, 0.5), prepend=0.0)
    d_delta = np.diff(delta, prepend=0.0)
    rel = get_relaxation_model("prony")
    w_basis = np.diff(rel.integrals(h * np.arange(t.size + 1), np.array([0.05, 0.5])), axis=0) / h
    turn, rows = int(np.argmax(delta)), np.arange(int(np.argmax(delta)) + 1, t.size)
    amps = np.array([0.4, 0.3, 0.3])

    def force(a):
        return retract_force(d_shape, d_delta, w_basis @ a, turn, rows, w_basis) @ a

    values, sens = retract_force(d_shape, d_delta, w_basis @ amps, turn, rows, w_basis, True)
    assert np.abs(sens).max() > 0.05 * np.abs(values).max()  # t1 matters
    for k in range(3):
        step = 1e-6 * np.eye(3)[k]
        numeric = (force(amps + step) - force(amps - step)) / 2e-6
        np.testing.assert_allclose(values[:, k] + sens[:, k], numeric, atol=1e-6 * values.max())


def test_two_speeds_with_noise_recover_the_prony_series():
    # the docs example: 0.5 um paraboloid ramps of 0.1 s and 1 s, 0.2 % noise of the peak force
    truth = ([0.4, 0.3, 0.3], [0.05, 0.5])
    ramps = []
    for i, ramp_s in enumerate((0.1, 1.0)):
        clean = synthetic_ramp("hertz_paraboloid", "prony", *truth, ramp_s=ramp_s, n=201, pre=50)
        noise = 0.002 * clean.force_nN.max()
        noisy = clean.force_nN + noise * np.random.default_rng(i).standard_normal(clean.time_s.size)
        ramps.append(RampCurve(clean.time_s, clean.tip_position_um, noisy, clean.source))
    fit = fit_ramp(ramps, "hertz_paraboloid", TIPS["hertz_paraboloid"][0], terms=2)
    # measured: moduli within 0.5 %, times within 1.7 %
    assert fit.amplitudes_kPa == pytest.approx(truth[0], rel=0.02)
    assert fit.theta == pytest.approx(truth[1], rel=0.05)
    assert fit.quality == "good"


@pytest.mark.slow
def test_fe_script_reproduces_the_stored_curves_on_a_coarser_mesh():
    # benchmarks/afm_ramp_fe_curves.py with 0.5 um contact elements (about 10 s): the FE
    # driver still runs the script and its force stays within 1.5 % of the stored 0.25 um
    # curve (measured 0.75 %)
    import importlib.util

    from oocyte_fe.experiment import run_experiment
    from oocyte_fe.experiment.analysis import push_force_nN

    path = Path(__file__).parents[1] / "benchmarks" / "afm_ramp_fe_curves.py"
    spec = importlib.util.spec_from_file_location("afm_ramp_fe_curves", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    result = run_experiment(script.experiment(1.0, mesh_scale=2.0))
    stored = np.loadtxt(FE_DATA / "ramp_T1s.csv", delimiter=",")
    assert result.success
    np.testing.assert_allclose(result.times_s, stored[:, 0], rtol=1e-9)
    force = push_force_nN(result, "probe")
    assert np.max(np.abs(force - stored[:, 2])) < 0.015 * stored[:, 2].max()
