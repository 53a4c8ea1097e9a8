"""Fuzz the public functions of ``oocyte_fe.microchannel``: nonsense arguments end in
``InputError`` naming the argument, valid ones in finite results (never a complex number, a NaN,
a slit read for an unknown geometry, another exception or a hang)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.duct_fe import radial_mesh, rectangle_mesh, solve_duct_flow
from oocyte_fe.microchannel.junction_deformation import (
    JunctionCell,
    JunctionParameters,
    fit_junction_model,
    junction_deformation,
)
from oocyte_fe.microchannel.poiseuille import (
    PoiseuilleFlow,
    power_law_flow_rate,
    pressure_gradient_for_mean_velocity,
    rectangular_duct_flow_rate,
)
from oocyte_fe.microchannel.rabinowitsch import fully_developed_flow
from oocyte_fe.microchannel.rheology_fit import fit_viscosity
from oocyte_fe.microchannel.tables import read_deformation_table, read_flow_curve
from oocyte_fe.microchannel.viscosity import Rheology
from tests.fuzz.harness import NUMBERS, capped, check_outcome, fuzz_settings

GEOMETRY = st.one_of(
    st.sampled_from(["pipe", "slit"]), st.sampled_from(["bogus", "", "PIPE"]), NUMBERS
)
CARREAU = Rheology.of("carreau", eta0=1e-3, eta_inf=1e-6, time_constant=0.1, n=0.5)
NEWTONIAN = Rheology.of("newtonian", mu=1e-6)
CHANNEL = Channel(250.0, 1e-15, 1e-6, 100.0, 1.0)
CASES = Path(__file__).resolve().parents[2] / "cases"


@fuzz_settings(ci_examples=60, full_examples=800)
@given(values=st.tuples(NUMBERS, NUMBERS, NUMBERS, NUMBERS, NUMBERS))
def test_channel(values: tuple) -> None:
    def call() -> object:
        channel = Channel(*values)
        return channel.mean_velocity(np.array([1.0, 2.0])), channel.hydraulic_length

    check_outcome("microchannel.Channel", call)


@fuzz_settings(ci_examples=80, full_examples=1000)
@given(geometry=GEOMETRY, size=NUMBERS, gradient=NUMBERS, mu=NUMBERS)
def test_poiseuille(geometry: object, size: object, gradient: object, mu: object) -> None:
    def call() -> object:
        flow = PoiseuilleFlow(geometry, size, gradient, mu)  # type: ignore[arg-type]
        return flow.flow_rate, flow.wall_shear_rate, flow.velocity(np.array([0.0]))

    check_outcome("microchannel.PoiseuilleFlow", call)
    check_outcome(
        "microchannel.pressure_gradient_for_mean_velocity",
        lambda: pressure_gradient_for_mean_velocity(geometry, size, gradient, mu),  # type: ignore[arg-type]
    )


@fuzz_settings(ci_examples=80, full_examples=1000)
@given(geometry=GEOMETRY, size=NUMBERS, tau=NUMBERS, k=NUMBERS, n=NUMBERS)
def test_power_law(geometry: object, size: object, tau: object, k: object, n: object) -> None:
    check_outcome(
        "microchannel.power_law_flow_rate",
        lambda: power_law_flow_rate(geometry, size, tau, k, n),  # type: ignore[arg-type]
    )


@fuzz_settings(ci_examples=60, full_examples=800)
@given(w=NUMBERS, h=NUMBERS, g=NUMBERS, mu=NUMBERS, terms=capped(NUMBERS, 500))
def test_rectangular_duct(w: object, h: object, g: object, mu: object, terms: object) -> None:
    check_outcome(
        "microchannel.rectangular_duct_flow_rate",
        lambda: rectangular_duct_flow_rate(w, h, g, mu, terms),  # type: ignore[arg-type]
    )


@fuzz_settings(ci_examples=40, full_examples=500)
@given(geometry=GEOMETRY, size=NUMBERS, gradient=NUMBERS)
def test_rabinowitsch(geometry: object, size: object, gradient: object) -> None:
    def call() -> object:
        flow = fully_developed_flow(CARREAU, geometry, size, gradient)  # type: ignore[arg-type]
        return flow.flow_rate, flow.wall_shear_stress

    check_outcome("microchannel.fully_developed_flow", call)


@fuzz_settings(ci_examples=30, full_examples=300)
@given(w=NUMBERS, h=NUMBERS, cells=capped(NUMBERS, 4), g=NUMBERS, steps=capped(NUMBERS, 3))
def test_duct_fe(w: object, h: object, cells: object, g: object, steps: object) -> None:
    def call() -> object:
        mesh = rectangle_mesh(w, h, cells)  # type: ignore[arg-type]
        return solve_duct_flow(mesh, NEWTONIAN, g, steps=steps).flow_rate  # type: ignore[arg-type]

    check_outcome("microchannel.solve_duct_flow", call)
    check_outcome("microchannel.radial_mesh", lambda: radial_mesh(w, cells).p)  # type: ignore[arg-type]


@fuzz_settings(ci_examples=60, full_examples=800)
@given(d=NUMBERS, modulus=NUMBERS, load=NUMBERS, length=NUMBERS, p=NUMBERS)
def test_junction(d: object, modulus: object, load: object, length: object, p: object) -> None:
    def call() -> object:
        cell = JunctionCell(d, modulus, CARREAU)  # type: ignore[arg-type]
        params = JunctionParameters(load, length)  # type: ignore[arg-type]
        return junction_deformation(CHANNEL, cell, params, np.array([p, 1.0]))

    check_outcome("microchannel.junction_deformation", call)


FLOW_CURVE = read_flow_curve(CASES / "microchannel_carreau_fit" / "table2_viscosity.csv")
DEFORMATION = read_deformation_table(CASES / "microchannel_deformation" / "table4_deformation.csv")


def _degenerate(values: np.ndarray, how: str, k: int) -> np.ndarray:
    """``values`` cut to ``k`` rows, made all equal, or with a huge, tiny or NaN last value."""
    if how == "rows":
        return values[:k]
    if how == "equal":
        return np.full_like(values, values[0])
    last = {"huge": 1e300, "tiny": 1e-300, "nan": np.nan, "zero": 0.0}[how]
    return np.r_[values[:-1], last]


HOW = st.sampled_from(["rows", "equal", "huge", "tiny", "nan", "zero"])


@fuzz_settings(ci_examples=60, full_examples=1000)
@given(
    model=st.sampled_from(["carreau", "cross", "power_law", "carreau_yasuda"]),
    column=st.sampled_from(["shear_rate", "viscosity"]),
    how=HOW,
    k=st.integers(0, 6),
)
def test_viscosity_fit_on_degenerate_data(model: str, column: str, how: str, k: int) -> None:
    """Issue 26, class 4: no scipy error escapes, no NaN R^2 is reported as a success."""
    gamma, eta = FLOW_CURVE.shear_rate, FLOW_CURVE.viscosity
    if column == "shear_rate":
        gamma = _degenerate(gamma, how, k)
        eta = eta[: gamma.size]
    else:
        eta = _degenerate(eta, how, k)
        gamma = gamma[: eta.size]

    def call() -> object:
        fit = fit_viscosity(model, gamma, eta)
        return fit.r2, fit.r2_log, fit.rmse, fit.rheology.params

    check_outcome("microchannel.fit_viscosity (degenerate)", call)


@fuzz_settings(ci_examples=40, full_examples=600)
@given(column=st.sampled_from(["pressure", "ratio"]), how=HOW, k=st.integers(0, 4))
def test_junction_fit_on_degenerate_data(column: str, how: str, k: int) -> None:
    pressure, ratio = DEFORMATION.pressure, DEFORMATION.ratio_experiment
    if column == "pressure":
        pressure = _degenerate(pressure, how, k)
        ratio = ratio[: pressure.size]
    else:
        ratio = _degenerate(ratio, how, k)
        pressure = pressure[: ratio.size]
    cell = JunctionCell(140.0, 1.0, CARREAU)

    def call() -> object:
        fit = fit_junction_model(CHANNEL, cell, pressure, ratio, list(DEFORMATION.pressure[:2]))
        return fit.params, fit.ratio

    check_outcome("microchannel.fit_junction_model (degenerate)", call)
