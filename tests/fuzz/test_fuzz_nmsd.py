"""Fuzz the public functions of ``nmsd``: nonsense arguments end in ``InputError`` naming the
argument, valid ones in finite results (never another exception, never a hang)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from nmsd.approach_pid import PidGains, pid_approach
from nmsd.calibration import calibrate
from nmsd.cytoplasm_loss import aspirated_length_for, loss_fraction
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.pipette import Pipette
from nmsd.press import press_setup, simulate_press
from nmsd.spindle import approach_setup, predict_spindle_offset
from nmsd.tableII import ForceDisplacement
from oocyte_fe.errors import InputError
from tests.fuzz.harness import NUMBERS, capped, check_outcome, fuzz_settings

SMALL = circular_lattice(40.0, 4)


@fuzz_settings(ci_examples=60, full_examples=800)
@given(d=NUMBERS, n=capped(NUMBERS, 60), shift=NUMBERS)
def test_circular_lattice(d: object, n: object, shift: object) -> None:
    lattice = check_outcome("nmsd.circular_lattice", lambda: circular_lattice(d, n, shift))
    if lattice is not None:
        assert len(lattice.nodes) > 0


@fuzz_settings(ci_examples=60, full_examples=800)
@given(d=NUMBERS, n=NUMBERS, rho=NUMBERS)
def test_node_mass_for(d: object, n: object, rho: object) -> None:
    mass = check_outcome("nmsd.node_mass_for", lambda: node_mass_for(d, n, rho))
    if mass is not None:
        assert mass > 0


@fuzz_settings(ci_examples=60, full_examples=800)
@given(w=NUMBERS, angle=NUMBERS, x=NUMBERS, y=NUMBERS, dx=NUMBERS, dy=NUMBERS, k=NUMBERS)
def test_pipette(w: object, angle: object, x: object, y: object, dx, dy, k: object) -> None:
    check_outcome("nmsd.Pipette", lambda: Pipette(w, angle, (x, y), (dx, dy), k).faces())


@fuzz_settings(ci_examples=60, full_examples=800)
@given(period=NUMBERS, speed=NUMBERS, duration=capped(NUMBERS, 20.0), band=NUMBERS)
def test_pid_approach(period: object, speed: object, duration: object, band: object) -> None:
    def call() -> object:
        gains = PidGains(period_s=max(period, 1e-3) if isinstance(period, float) else period)
        trace = pid_approach(
            lambda _p: np.array([10.0, 5.0]), gains, (0.0, 0.0), speed, duration, band
        )
        return trace.position_um, trace.final_error_um, trace.overshoot_um  # settling may be inf

    check_outcome("nmsd.pid_approach", call)


def test_pid_approach_refuses_absurd_work() -> None:
    start = time.perf_counter()
    with pytest.raises(InputError, match="duration_s/period_s"):
        pid_approach(lambda _p: np.array([10.0, 5.0]), PidGains(period_s=1e-9), duration_s=100)
    assert time.perf_counter() - start < 1.0


@fuzz_settings(ci_examples=40, full_examples=500)
@given(speed=NUMBERS, travel=capped(NUMBERS, 12.0), steps=capped(NUMBERS, 8), gap=NUMBERS)
def test_simulate_press(speed: object, travel: object, steps: object, gap: object) -> None:
    def call() -> object:
        setup = press_setup(SMALL, gap_um=gap, n_steps=4, symmetric=False)
        return simulate_press(
            setup.lattice, NmsdParameters(), setup.pipette, setup.held, speed, travel, steps
        ).force_nN

    check_outcome("nmsd.simulate_press", call)


DATA = ForceDisplacement(np.array([0.0, 2.0, 4.0]), np.array([0.0, 50.0, 120.0]))
SETUP = press_setup(SMALL, travel_um=4.0, n_steps=4)
COUNTS = st.one_of(st.sampled_from([0, -1, 2.5, 4.0, True, None, "4", float("nan")]), st.just(4))


@fuzz_settings(ci_examples=20, full_examples=300)
@given(evals=COUNTS, starts=st.sampled_from([0, 1, -2, 1.5, None]), seed=NUMBERS, tol=NUMBERS)
def test_calibrate_arguments(evals: object, starts: object, seed: object, tol: object) -> None:
    check_outcome(
        "nmsd.calibrate",
        lambda: (
            calibrate(
                SETUP,
                DATA,
                "linear_msd",
                n_starts=starts,
                seed=seed,
                max_evaluations=evals,
                tolerance=tol,
            ).force_nN
        ),
    )


TARGETS = st.one_of(
    st.tuples(NUMBERS, NUMBERS).map(np.array),
    st.sampled_from([np.array([1.0]), np.zeros(3), "here", None, np.array([np.nan, 1.0])]),
)


@fuzz_settings(ci_examples=40, full_examples=500)
@given(goal=TARGETS)
def test_pid_approach_target(goal: object) -> None:
    """A target callable returning NaN, a wrong shape or text: refused, never a NaN trace."""

    def call() -> object:
        trace = pid_approach(lambda _p: goal, PidGains(), duration_s=0.5)  # type: ignore[arg-type]
        return trace.position_um, trace.final_error_um

    check_outcome("nmsd.pid_approach (target)", call)


@fuzz_settings(ci_examples=60, full_examples=800)
@given(
    length=NUMBERS,
    pipette=st.one_of(NUMBERS, st.floats(1, 50)),
    cell=st.one_of(NUMBERS, st.floats(50, 200)),
    plane=st.booleans(),
    fraction=st.one_of(NUMBERS, st.floats(0, 1)),
)
def test_loss_fraction(length: object, pipette: object, cell: object, plane, fraction) -> None:
    def call() -> object:
        loss = loss_fraction(length, pipette, cell, plane)  # type: ignore[arg-type]
        return loss, aspirated_length_for(fraction, pipette, cell, plane)  # type: ignore[arg-type]

    check_outcome("nmsd.loss_fraction", call)


@fuzz_settings(ci_examples=60, full_examples=800)
@given(
    x=st.one_of(NUMBERS, st.floats(0, 40)),
    y=st.one_of(NUMBERS, st.floats(-20, 20)),
    hold=st.one_of(NUMBERS, st.floats(0, 30)),
    step=NUMBERS,
)
def test_spindle_approach(x: object, y: object, hold: object, step: object) -> None:
    """Spindle outside the cell, at the puncture point, a hold holding no node, a step of 0 or
    NaN: refused naming the argument (the press itself is run only for small lattices)."""

    def call() -> object:
        approach = approach_setup(SMALL, (x, y), hold_half_width_um=hold)  # type: ignore[arg-type]
        if isinstance(step, float) and step > 2.0:  # a few steps: the press itself runs
            return predict_spindle_offset(SMALL, NmsdParameters(), (x, y), step_um=step).final_um
        return approach.travel_um, approach.held.sum()

    check_outcome("nmsd.approach_setup", call)


def test_spindle_step_refused_before_a_press() -> None:
    for step in (0.0, -1.0, float("nan"), 1e-300, True):
        with pytest.raises(InputError, match="predict_spindle_offset: step_um"):
            predict_spindle_offset(SMALL, NmsdParameters(), (15.0, 2.0), step_um=step)
