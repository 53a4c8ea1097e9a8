"""A hold at the farthest travel (stress relaxation) is part of the approach, not a retract."""

import numpy as np

from afm.viscoelastic import RampCurve


def _ramp_hold(noise_um: float, retract: bool) -> RampCurve:
    # ramp to 1 um in 0.7 s, hold 4.5 s (the tester's ve_hold), optionally a retract of 0.7 s
    t = np.arange(0.0, 5.2 + (0.7 if retract else 0.0), 0.001)
    x = np.minimum(t / 0.7, 1.0)
    if retract:
        x = np.where(t > 5.2, 1.0 - (t - 5.2) / 0.7, x)
    x = x + noise_um * np.random.default_rng(1).standard_normal(t.size)
    return RampCurve(t, x, np.zeros_like(t), "ramp.csv")


def test_hold_without_retract_has_no_turn():
    ramp = _ramp_hold(0.002, retract=False)
    assert ramp.turn == ramp.time_s.size - 1
    # the hold starts where the travel comes within 1 % of the farthest point (0.693 s on a
    # 0.7 s ramp, noise 0.2 % of the travel)
    assert abs(ramp.time_s[ramp.hold_start] - 0.693) < 0.01


def test_hold_then_retract_turns_where_the_travel_reverses():
    ramp = _ramp_hold(0.002, retract=True)
    # noise 0.002 um, retract 1.43 um/s: 4 sigma are left 6 ms after the reversal at 5.2 s
    assert abs(ramp.time_s[ramp.turn] - 5.2) < 0.01


def test_noise_free_ramp_turns_at_its_farthest_point():
    t = np.linspace(0.0, 1.0, 201)
    x = 1.0 - np.abs(t - 0.5)
    ramp = RampCurve(t, x, np.zeros_like(t))
    assert ramp.turn == int(np.argmax(x)) == 100
