"""Incremental PID approach (eq 10) and the displacement-field hook for the FE cross-check."""

from __future__ import annotations

import numpy as np
import pytest

from nmsd.approach_pid import PidGains, pid_approach
from nmsd.displacement_field import press_displacements
from nmsd.parameters import NmsdParameters
from nmsd.press import press_setup
from oocyte_fe.errors import InputError


def test_pid_reaches_fixed_target_within_resolution():
    goal = np.array([25.6972, 49.127])
    trace = pid_approach(lambda _s: goal, PidGains(), duration_s=4.0)
    assert trace.final_error_um < 0.1
    assert np.isfinite(trace.settling_time_s)
    # commands are quantised to 0.04 um, so the end point sits within half a step per axis
    assert np.all(np.abs(trace.position_um[-1] - goal) <= 0.02 + 1e-9)


def test_pid_follows_moving_target():
    def target(progress: float) -> np.ndarray:
        return np.array([10.0, 10.0]) + 0.2 * progress

    trace = pid_approach(target, PidGains(), duration_s=4.0)
    assert trace.final_error_um < 0.1
    assert not np.allclose(trace.target_um[0], trace.target_um[-1])


def test_bad_gain():
    with pytest.raises(InputError, match="period_s"):
        PidGains(period_s=0.0)


def test_displacement_field_at_nodes_matches_interpolation():
    setup = press_setup(n_steps=10, travel_um=20.0)
    params = NmsdParameters(k1=20.0, k2=2000.0, d0=1.0, d1=0.05)
    nodes = setup.lattice.nodes[[5, 100, 200]]
    field = press_displacements(setup, params, [10.0, 20.0], points_um=nodes)
    for a in (10.0, 20.0):
        assert np.allclose(field.at_points[a], field.nodal[a][[5, 100, 200]], atol=1e-9)
    assert np.abs(field.nodal[20.0]).max() > np.abs(field.nodal[10.0]).max() > 0
