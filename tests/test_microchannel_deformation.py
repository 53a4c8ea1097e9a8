"""Reduced junction model: limits, fit on three pressures, bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.junction_deformation import (
    JunctionCell,
    JunctionParameters,
    axis_ratio,
    fit_junction_model,
    junction_deformation,
)
from oocyte_fe.microchannel.tables import read_deformation_table
from oocyte_fe.microchannel.viscosity import Rheology

CASE = Path(__file__).parents[1] / "cases" / "microchannel_deformation"
CHANNEL = Channel(250.0, 1.008e-12, 1.66e-6, 106.5, 30.0)


def cell(eta: float) -> JunctionCell:
    return JunctionCell(140.0, 1.55, Rheology.of("newtonian", mu=eta))


def test_elastic_and_viscous_limits() -> None:
    params = JunctionParameters(load_factor=0.5, junction_length=1000.0)
    p = np.array([20.0, 90.0])
    u = CHANNEL.mean_velocity(p)
    stress = 0.5 * 8 * 1.66e-6 * u * 140.0 / 125.0**2
    # a nearly inviscid cell deforms elastically: D = sigma / E
    np.testing.assert_allclose(
        junction_deformation(CHANNEL, cell(1e-12), params, p), stress / 1.55, rtol=1e-9
    )
    # a very viscous cell creeps: D = sigma t_res / eta, independent of the pressure
    d = junction_deformation(CHANNEL, cell(1e3), params, p)
    np.testing.assert_allclose(d, 0.5 * 8 * 1.66e-6 * 140.0 * 1000.0 / (125.0**2 * 1e3), rtol=1e-5)
    assert axis_ratio(np.array([0.0]))[0] == 1.0


def test_fit_recovers_parameters_from_synthetic_ratios() -> None:
    true = JunctionParameters(0.4, 2000.0)
    c = cell(1.368e-3)
    p = np.array([20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 90.0])
    ratio = axis_ratio(junction_deformation(CHANNEL, c, true, p))
    fit = fit_junction_model(CHANNEL, c, p, ratio, [20.0, 50.0, 90.0])
    assert fit.params.load_factor == pytest.approx(0.4, rel=1e-5)
    assert fit.params.junction_length == pytest.approx(2000.0, rel=1e-5)
    np.testing.assert_allclose(fit.ratio, ratio, rtol=1e-9)


def test_table4_prediction_beats_the_papers_4_percent() -> None:
    table = read_deformation_table(CASE / "table4_deformation.csv")
    assert table.pressure[0] == pytest.approx(20.0)  # 200 hPa -> kPa
    fit = fit_junction_model(
        CHANNEL, cell(1.368e-3), table.pressure, table.ratio_experiment, [20.0, 50.0, 90.0]
    )
    err = np.abs(fit.ratio / table.ratio_experiment - 1.0)
    assert err.mean() < 0.04


def test_fit_pressures_must_come_from_the_table() -> None:
    p = np.array([20.0, 30.0, 90.0])
    with pytest.raises(InputError, match="fit_pressures: expected two or three distinct"):
        fit_junction_model(CHANNEL, cell(1e-3), p, np.array([0.97, 0.93, 0.9]), [25.0, 90.0])
    with pytest.raises(InputError, match="fit_pressures"):
        fit_junction_model(CHANNEL, cell(1e-3), p, np.array([0.97, 0.93, 0.9]), [20.0])


def test_bad_ratio_column(tmp_path: Path) -> None:
    f = tmp_path / "t.csv"
    f.write_text("pressure_hPa,ratio_experiment,ratio_simulation\n200,1.2,0.9\n")
    with pytest.raises(InputError, match="ratio_experiment: expected axis ratios in"):
        read_deformation_table(f)
    f.write_text("pressure_psi,ratio_experiment,ratio_simulation\n200,0.9,0.9\n")
    with pytest.raises(InputError, match="pressure_psi: expected a pressure unit"):
        read_deformation_table(f)
