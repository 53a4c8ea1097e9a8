"""Forward sensitivities of the NMSD press (nmsd.sensitivity) and the exact calibration Jacobian."""

from __future__ import annotations

import numpy as np
import pytest

from nmsd.calibration import calibrate, model_forces_and_jacobian
from nmsd.integrator import BackwardEulerStepper, NewtonFailure
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import press_setup
from nmsd.tableII import ForceDisplacement, read_force_displacement
from oocyte_fe.errors import InputError

TABLE = "cases/nmsd_calibration_tableII/nmsd_force_displacement_tableII.csv"
RECORD = [2.0, 4.0, 6.0, 8.0, 10.0]
GAP = 0.37  # not a multiple of the 0.25 um step: no node meets the mouth exactly at a step end


def _small_press(n_steps: int = 40, symmetric: bool = True):
    """A 10 um press of a 40 um lattice with fine steps: smooth in the constants."""
    lattice = circular_lattice(40.0, 5)
    setup = press_setup(lattice, n_steps=n_steps, travel_um=10.0, symmetric=symmetric)
    return setup.with_gap(GAP)


def _params(damping: str, **kw) -> NmsdParameters:
    # dl_c 0.05: many links pass the critical strain, so the linear continuation is exercised
    values = dict(k1=3.0, k2=8000.0, dl_c=0.05, d0=14.6, d1=0.55, damping=damping)
    if damping == "link":
        values.update(k1=85.7, k2=5.35e4, d0=139.5, d1=2.74)
    values.update(node_mass=node_mass_for(115.625, 231), **kw)
    return NmsdParameters(**values)


def _central_difference(setup, params, name, rel=1e-5, step_um=1e-4):
    if name == "gap_um":
        fp = setup.with_gap(GAP + step_um).run(params, record_um=RECORD).force_at(RECORD)
        fm = setup.with_gap(GAP - step_um).run(params, record_um=RECORD).force_at(RECORD)
        return (fp - fm) / (2 * step_um)
    value = getattr(params, name)
    h = rel * value
    fp = setup.run(params.with_values(**{name: value + h}), record_um=RECORD).force_at(RECORD)
    fm = setup.run(params.with_values(**{name: value - h}), record_um=RECORD).force_at(RECORD)
    return (fp - fm) / (2 * h)


@pytest.mark.parametrize(
    "damping, extra, symmetric",
    [
        ("nodal", {}, True),
        ("link", {}, True),
        ("link", {"area_stiffness": 2.0}, True),
        ("nodal", {"zona_stiffness_ratio": 3.0, "zona_inner_radius_um": 12.0}, True),
        ("nodal", {}, False),  # full lattice (no half-lattice solve)
        ("link", {}, False),
    ],
)
def test_press_sensitivities_match_central_differences(damping, extra, symmetric):
    setup = _small_press(symmetric=symmetric)
    assert (setup.mirror is None) != symmetric
    params = _params(damping, **extra)
    press = setup.run(params, record_um=RECORD, sensitivities=True)
    exact = press.sensitivity_at(RECORD)
    assert press.sensitivity_names == ("k1", "k2", "d0", "d1", "dl_c", "gap_um")
    assert np.all(press.force_at(RECORD) > 0)
    for j, name in enumerate(press.sensitivity_names):
        fd = _central_difference(setup, params, name)
        assert np.abs(fd).max() > 0, name
        # measured: <= 2.3e-7 (k1, nodal); 1e-9 - 1e-7 for the others
        assert np.abs(exact[:, j] - fd).max() < 1e-5 * np.abs(fd).max(), name


def test_sensitivities_follow_halved_steps(monkeypatch):
    # a stepper that refuses steps longer than 0.75 of the 20-step dt halves every step once:
    # the press, forces and sensitivities must equal the 40-step press
    params = _params("nodal")
    fine = _small_press(40).run(params, record_um=RECORD, sensitivities=True)
    original = BackwardEulerStepper.step
    limit = 0.75 * 10.0 / 20 / 30.0

    def refusing(self, x, v, advance, dt):
        if dt > limit:
            raise NewtonFailure("test: step too long")
        return original(self, x, v, advance, dt)

    monkeypatch.setattr(BackwardEulerStepper, "step", refusing)
    halved = _small_press(20).run(params, record_um=RECORD, sensitivities=True)
    assert len(halved.advance_um) == 21
    assert halved.force_at(RECORD) == pytest.approx(fine.force_at(RECORD), rel=1e-8)
    np.testing.assert_allclose(
        halved.sensitivity_at(RECORD), fine.sensitivity_at(RECORD), rtol=1e-6, atol=1e-9
    )


def test_press_without_sensitivities_has_none():
    press = _small_press(4).run(_params("nodal"), record_um=RECORD)
    assert press.force_sensitivity is None
    with pytest.raises(InputError, match="sensitivities"):
        press.sensitivity_at(RECORD)


@pytest.mark.parametrize("model", ["nmsd", "msd_d0", "linear_msd"])
def test_calibration_jacobian_is_the_chain_rule_of_the_sensitivities(model):
    setup = _small_press()
    params = _params("link").with_values(k1=40.0)
    if model != "nmsd":
        params = params.with_values(d1=0.0, k2=0.0 if model == "linear_msd" else params.k2)
    data = ForceDisplacement(np.array(RECORD), np.zeros(len(RECORD)), "test")
    extra = ("dl_c", "gap_um")
    forces, jac = model_forces_and_jacobian(setup, params, data, model, extra)
    assert forces == pytest.approx(setup.run(params, record_um=RECORD).force_at(RECORD))
    free = {
        "nmsd": ("k2", "s", "d0", "d1"),
        "msd_d0": ("k2", "s", "d0"),
        "linear_msd": ("k1", "d0"),
    }[model] + extra
    assert jac.shape == (len(RECORD), len(free))
    s = params.k1 / params.k2 if params.k2 > 0 else 0.0
    for j, name in enumerate(free):
        if name == "gap_um":
            fd = _central_difference(setup, params, "gap_um")
        else:

            def with_value(value, name=name):
                if name == "k2":
                    return params.with_values(k1=s * value, k2=value)
                if name == "s":
                    return params.with_values(k1=value * params.k2)
                return params.with_values(**{name: value})

            value = {"s": s}.get(name, getattr(params, name, None))
            h = 1e-5 * value
            fp = setup.run(with_value(value + h), record_um=RECORD).force_at(RECORD)
            fm = setup.run(with_value(value - h), record_um=RECORD).force_at(RECORD)
            fd = (fp - fm) / (2 * h)
        # (linear_msd: k2 = 0, so dl_c has no effect and both are exactly 0)
        assert np.abs(jac[:, j] - fd).max() <= 1e-4 * np.abs(fd).max(), name


def test_exact_jacobian_calibration_needs_one_press_per_evaluation():
    data = read_force_displacement(TABLE)
    setup = press_setup(n_steps=8)
    base = NmsdParameters(dl_c=0.8)
    exact = calibrate(setup, data, "nmsd", base, 1, max_evaluations=4)
    forward = calibrate(setup, data, "nmsd", base, 1, max_evaluations=4, jacobian="2-point")
    # least_squares counts residuals only: the exact run presses once per residual (+1 final),
    # forward differences add four presses per Jacobian
    assert exact.evaluations <= 5
    assert forward.evaluations >= exact.evaluations + 4
    assert exact.metrics.rmse_nN < 2 * forward.metrics.rmse_nN
    with pytest.raises(InputError, match="jacobian"):
        calibrate(setup, data, "nmsd", base, 1, jacobian="3-point")
    with pytest.raises(InputError, match="tolerance"):
        calibrate(setup, data, "nmsd", base, 1, tolerance=0.0)
