"""Viscosity registry, log-space fits to Table 2 of seed 001, and bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.microchannel.tables import read_flow_curve
from oocyte_fe.microchannel.viscosity import Rheology, get_model, viscosity_models

TABLE2 = Path(__file__).parents[1] / "cases" / "microchannel_carreau_fit" / "table2_viscosity.csv"


def test_registry_style_same_key_same_unit() -> None:
    seen: dict[str, str] = {}
    for model in viscosity_models().values():
        assert model.equation and model.parameters
        assert model.function.__doc__ and "kPa s" in model.function.__doc__
        for p in model.parameters:
            assert seen.setdefault(p.key, p.unit) == p.unit, p.key
            assert p.lower < p.upper


def test_models_limits_and_reduction() -> None:
    car = Rheology.of("carreau", eta0=2.0, eta_inf=0.1, time_constant=10.0, n=0.4)
    assert car.viscosity(1e-9) == pytest.approx(2.0, rel=1e-12)
    assert car.viscosity(1e9) == pytest.approx(0.1, rel=1e-4)
    cy = Rheology.of("carreau_yasuda", eta0=2.0, eta_inf=0.1, time_constant=10.0, n=0.4, a=2.0)
    g = np.logspace(-3, 3, 13)
    np.testing.assert_allclose(cy.viscosity(g), car.viscosity(g), rtol=1e-13)
    cross = Rheology.of("cross", eta0=2.0, eta_inf=0.0 + 1e-12, time_constant=1.0, m=1.0)
    assert cross.viscosity(1.0) == pytest.approx(1.0, rel=1e-9)  # half-way at gamma = 1/lambda


def test_slope_and_inverse_flow_curve() -> None:
    car = Rheology.of("carreau", eta0=2.0, eta_inf=0.1, time_constant=10.0, n=0.4)
    g = np.array([1e-3, 0.1, 1.0, 30.0])
    # analytic: eta'/gamma = (eta0 - eta_inf) (n - 1) lambda^2 [1 + (lambda gamma)^2]^((n-3)/2)
    exact = 1.9 * (0.4 - 1.0) * 100.0 * (1.0 + (10.0 * g) ** 2) ** ((0.4 - 3.0) / 2.0)
    np.testing.assert_allclose(car.viscosity_slope(g), exact, rtol=1e-12)
    # limit at gamma -> 0: (n - 1) lambda^2 (eta0 - eta_inf)
    assert car.viscosity_slope(np.array([0.0]))[0] == pytest.approx(-0.6 * 100 * 1.9, rel=1e-9)
    for tau in (1e-4, 0.3, 50.0):
        assert car.stress(car.shear_rate(tau)) == pytest.approx(tau, rel=1e-12)


def test_table2_carreau_fit_r2_and_uncertainty() -> None:
    curve = read_flow_curve(TABLE2)
    assert curve.viscosity[0] == pytest.approx(969.1e-3)  # Pa s -> kPa s at the file boundary
    fit = fit_viscosity("carreau", curve.shear_rate, curve.viscosity)
    assert fit.success and fit.r2 >= 0.999  # issue 7 check
    assert 0.0 < fit.params["n"] < 0.3  # strongly shear-thinning
    assert np.isfinite(fit.stderr["eta0"]) and fit.stderr["eta0"] < fit.params["eta0"]
    # the data (rates <= 0.052 1/s) cannot determine the infinite-shear plateau
    assert "eta_inf" in fit.unidentified and fit.stderr["eta_inf"] == np.inf


def test_fit_recovers_synthetic_parameters() -> None:
    true = {"eta0": 1.2, "eta_inf": 1e-3, "time_constant": 50.0, "m": 0.8}
    g = np.logspace(-4, 3, 30)
    eta = Rheology.of("cross", **true).viscosity(g)
    fit = fit_viscosity("cross", g, eta)
    for key, value in true.items():
        assert fit.params[key] == pytest.approx(value, rel=1e-5)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)


def test_fixed_parameter_is_kept() -> None:
    curve = read_flow_curve(TABLE2)
    fit = fit_viscosity("carreau", curve.shear_rate, curve.viscosity, fixed={"eta_inf": 1.368e-3})
    assert fit.params["eta_inf"] == 1.368e-3 and fit.stderr["eta_inf"] == 0.0


@pytest.mark.parametrize(
    ("rate", "eta", "field"),
    [
        ([0.1, -1.0, 1.0, 2.0, 3.0], [1.0] * 5, "shear_rate"),
        ([0.1, 0.2, 1.0, 2.0, 3.0], [1.0, 0.0, 1.0, 1.0, 1.0], "viscosity"),
        ([0.1, 0.2, 0.3], [1.0, 0.9, 0.8], "shear_rate"),  # 3 points, 4 Carreau parameters
    ],
)
def test_fit_bad_input(rate: list, eta: list, field: str) -> None:
    with pytest.raises(InputError, match=f"table.csv: {field}"):
        fit_viscosity("carreau", np.array(rate), np.array(eta), source="table.csv")


def test_unknown_model_and_out_of_bounds_parameter() -> None:
    with pytest.raises(InputError, match="one of carreau"):
        get_model("bingham")
    with pytest.raises(InputError, match=r"carreau\.n: expected a value in"):
        Rheology.of("carreau", eta0=1.0, eta_inf=1e-3, time_constant=1.0, n=-0.5)


def test_bad_units_in_column_name(tmp_path: Path) -> None:
    f = tmp_path / "t.csv"
    f.write_text("strain_rate_1_s,viscosity_poise\n0.1,1\n")
    with pytest.raises(InputError, match="viscosity_poise: expected a viscosity unit"):
        read_flow_curve(f)
    f.write_text("strain_rate_1_s,viscosity_Pa_s\n0.1,-1\n")
    with pytest.raises(InputError, match=r"viscosity: expected values in \[1e-12, 1e\+09\] kPa s"):
        read_flow_curve(f)


@pytest.mark.parametrize("model", ["carreau", "cross", "carreau_yasuda"])
def test_table2_fit_does_not_move_with_round_off(model: str) -> None:
    """The brief's rule: Table 2 times 1 + 1e-9 N(0, 1) in rate and viscosity moves no
    identified parameter by 0.5 % (measured 2026-12-05: at most 7e-5, Carreau-Yasuda's eta0);
    the unidentified ones are reported as such, not as figures."""
    curve = read_flow_curve(TABLE2)
    base = fit_viscosity(model, curve.shear_rate, curve.viscosity)
    rng = np.random.default_rng(3)
    for _ in range(3):
        noise = 1e-9 * rng.standard_normal((2, curve.shear_rate.size))
        fit = fit_viscosity(
            model, curve.shear_rate * (1 + noise[0]), curve.viscosity * (1 + noise[1])
        )
        assert fit.unidentified == base.unidentified
        for key, value in base.params.items():
            if key not in base.unidentified:
                assert fit.params[key] == pytest.approx(value, rel=5e-3), key


def test_a_noiseless_power_law_does_not_identify_carreaus_eta0_and_lambda() -> None:
    """20 noiseless points of eta = K gamma^(n-1) (K = 2 Pa s^n, n = 0.5, 0.1-100 1/s): only
    eta0 lambda^(n-1) is in the data. With the residual alone as the noise eta0 and lambda
    came out to 6 and 12 %; with the 1 % floor their errors exceed a factor e: not
    identified, and n = 0.5 within its error (0.004)."""
    rate = np.logspace(-1, 2, 20)
    fit = fit_viscosity("carreau", rate, 2e-3 * rate ** (0.5 - 1.0))
    assert {"eta0", "time_constant"} <= set(fit.unidentified)
    assert fit.stderr["eta0"] == np.inf and fit.stderr["time_constant"] == np.inf
    assert "n" not in fit.unidentified
    assert abs(fit.params["n"] - 0.5) < fit.stderr["n"] < 0.01
