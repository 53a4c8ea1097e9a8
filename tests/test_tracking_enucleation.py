"""The closed enucleation loop on a cell whose constants are the model's own."""

from __future__ import annotations

import numpy as np

from nmsd.approach_pid import PidGains
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters, node_mass_for
from oocyte_fe.tracking import enucleation as loop
from oocyte_fe.tracking.synthetic import CELL_DIAMETER_UM, SequenceSpec


def test_loop_with_the_true_model_lands_on_the_spindle() -> None:
    """Spread 0: the prediction from the true start is the true end point, so the PID tip
    ends within the MP285 resolution (0.04 um) plus the PID's error of it; aiming at the start
    misses by the spindle's displacement (give or take the tracking error); from the tracked
    start the removal point moves by about the tracking error (the model is smooth)."""
    lattice = circular_lattice(CELL_DIAMETER_UM, 8)
    params = NmsdParameters(node_mass=node_mass_for(CELL_DIAMETER_UM, lattice.n_nodes))
    [cell] = loop.virtual_cells(params, 1, spread=0.0, start_spread_um=0.0)
    video = SequenceSpec(
        name="loop", seed=3, n_frames=50, enter_frames=20, approach_frames=25,
        contrast=0.2, shape=(200, 200),
    )  # fmt: skip
    out = loop.run_cell(
        cell, lattice, params, np.zeros(2), video, PidGains(), click_error_um=0.5, step_um=2.0
    )
    np.testing.assert_allclose(out.targets["proposed_truth"], out.true_final, atol=1e-9)
    assert out.distance("proposed_truth") < 0.1
    moved = float(np.linalg.norm(out.true_final - out.true_initial))
    assert abs(out.distance("initial_position") - moved) < out.tracking_error_um + 0.1
    assert out.tracking_error_um < 1.0
    assert out.prediction_shift_um < 2.0 * out.tracking_error_um + 0.05
