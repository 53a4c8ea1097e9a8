"""Creep fit with the measured force history (Boltzmann superposition, Lee-Radok).

The indentation is computed here from the closed form of the hereditary integral for a force
step F0 followed by a linear rise F0 c t (cone, Lee-Radok):

    delta(t)^2 = pi (1 - nu) / (4 tan alpha) * [F0 J(t) + F0 c int_0^t J(u) du]
    int_0^t J(u) du = J0 t + sum J_i (t - lambda_i (1 - exp(-t/lambda_i)))
"""

import math

import numpy as np
import pytest

from afm.creep import CreepData, fit_creep

J0, J_TERMS, LAMBDAS = 3 / 7, (0.15, 0.2), (0.5, 2.0)  # 1/kPa, 1/kPa, s
NU, ALPHA, F0 = 0.5, 10.0, 5.0
E0 = 2 * (1 + NU) / J0  # 7 kPa
E_INF = 2 * (1 + NU) / (J0 + sum(J_TERMS))  # 3.8532 kPa


def _drifting_hold(rate_per_s: float, t: np.ndarray) -> CreepData:
    j = J0 + sum(a * (1 - np.exp(-t / lam)) for a, lam in zip(J_TERMS, LAMBDAS, strict=True))
    integral = J0 * t + sum(
        a * (t - lam * (1 - np.exp(-t / lam))) for a, lam in zip(J_TERMS, LAMBDAS, strict=True)
    )
    cone = math.pi * (1 - NU) / (4 * math.tan(math.radians(ALPHA)))
    delta = np.sqrt(cone * (F0 * j + F0 * rate_per_s * integral))
    return CreepData(t, F0 * (1 + rate_per_s * t), delta, "drift.csv")


def test_drifting_force_recovers_the_series():
    # the tester's record: 1.2 %/s over 10 s (the step fit gave E0 7.42, E_inf 1.08 kPa and a
    # 222 s term). Noise-free and inside the fitted family: measured to 1e-8 (E0), the
    # optimiser's stopping tolerance; asserted to 1e-6 (moduli) and 1e-5 (terms)
    fit = fit_creep(_drifting_hold(0.012, np.arange(0.0, 10.0, 0.002)), ALPHA, NU)
    assert fit.E0_kPa == pytest.approx(E0, rel=1e-6)
    assert fit.E_inf_kPa == pytest.approx(E_INF, rel=1e-6)
    assert fit.creep.J_per_kPa == pytest.approx(J_TERMS, rel=1e-5)
    assert fit.creep.lambda_s == pytest.approx(LAMBDAS, rel=1e-5)
    assert fit.quality == "good"
    # the plotted step compliance is J(t) itself for an exact record
    assert fit.compliance_per_kPa == pytest.approx(fit.creep(fit.time_s), rel=1e-6)


def test_drifting_noisy_force_recovers_the_moduli_within_1_percent():
    # 0.4 % force noise (sensor) and 0.2 % indentation noise on the drifting record: the
    # smoothed force history keeps E0 and E_inf within 1 % (measured 0.1-0.3 %)
    t = np.arange(0.0, 10.0, 0.002)
    exact = _drifting_hold(0.012, t)
    rng = np.random.default_rng(3)
    force = exact.force_nN + 0.02 * rng.standard_normal(t.size)
    delta = exact.indentation_um * (1 + 0.002 * rng.standard_normal(t.size))
    fit = fit_creep(CreepData(t, force, delta), ALPHA, NU)
    assert fit.E0_kPa == pytest.approx(E0, rel=0.01)
    assert fit.E_inf_kPa == pytest.approx(E_INF, rel=0.01)


def test_clamped_force_is_the_step_fit():
    # f = 1: R_i = 1 - exp(-t/lambda_i) to round-off, so the fit is the step fit of
    # J(t) = 2 (1 + nu) shape(delta) / F0 (same record with rate 0)
    fit = fit_creep(_drifting_hold(0.0, np.arange(0.0, 10.0, 0.002)), ALPHA, NU)
    assert fit.E0_kPa == pytest.approx(E0, rel=1e-6)
    assert fit.E_inf_kPa == pytest.approx(E_INF, rel=1e-6)
    step_j = fit.creep(fit.time_s)
    assert fit.compliance_per_kPa == pytest.approx(step_j, rel=1e-6)


def test_perturbed_force_moves_the_moduli_by_less_than_half_a_percent():
    t = np.arange(0.0, 10.0, 0.002)
    hold = _drifting_hold(0.012, t)
    base = fit_creep(hold, ALPHA, NU)
    moved = fit_creep(CreepData(t, hold.force_nN * (1 + 1e-9), hold.indentation_um), ALPHA, NU)
    assert moved.E0_kPa == pytest.approx(base.E0_kPa, rel=0.005)
    assert moved.E_inf_kPa == pytest.approx(base.E_inf_kPa, rel=0.005)
