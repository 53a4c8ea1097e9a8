"""Spindle offset prediction (Section II.C of seed 000): the pipette, after puncture, advances
to the spindle's initial position and pushes the spindle (a material point) ahead of it.

Paper frame: origin at the puncture point (3 o'clock on the rim), X into the cell along the
pipette's entry axis, Y towards 12 o'clock; world (cell-centred) axes: ``x = R - X``,
``y = Y``. Scenario: the lattice is at rest when the approach starts (the membrane relaxed
after puncture); the pipette axis points from the puncture point to the spindle's initial
position; the mouth starts backed off along that axis just clear of every node and travels
until it reaches the spindle's initial position; the far-side rim nodes within the holding
pipette's half-width are held.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from nmsd.lattice import Lattice
from nmsd.material_point import MaterialPoints, locate
from nmsd.parameters import NmsdParameters
from nmsd.pipette import (
    CONTACT_STIFFNESS_NN_PER_UM,
    HOLD_HALF_WIDTH_UM,
    TABLE_I_TIP_ANGLE_DEG,
    TABLE_I_WIDTH_UM,
    Pipette,
)
from nmsd.press import MAX_STEPS, PressResult, held_far_side, simulate_press
from oocyte_fe import checks
from oocyte_fe.errors import InputError


@dataclass(frozen=True, eq=False)
class SpindleOffset:
    """Spindle start and end in the paper frame (um), its path (k, 2) and the press."""

    initial_um: np.ndarray
    final_um: np.ndarray
    path_um: np.ndarray
    pipette: Pipette
    press: PressResult
    advance_um: float


def to_world(lattice: Lattice, paper_xy: np.ndarray) -> np.ndarray:
    """Paper frame (origin at the puncture point, X inwards) to cell-centred axes, um."""
    p = np.atleast_2d(paper_xy)
    return np.column_stack([lattice.radius - p[:, 0], p[:, 1]])


def to_paper(lattice: Lattice, world_xy: np.ndarray) -> np.ndarray:
    """Cell-centred axes to the paper frame, um."""
    w = np.atleast_2d(world_xy)
    return np.column_stack([lattice.radius - w[:, 0], w[:, 1]])


def clear_back_off(lattice: Lattice, pipette: Pipette) -> float:
    """Smallest distance (um) the mouth must back off along its axis to leave every node outside.

    A node at (xi, eta) in the pipette frame is inside iff
    ``xi <= min(0, (d/2 - |eta|) / tan(theta/2))``.
    """
    a = np.asarray(pipette.direction)
    b = np.array([-a[1], a[0]])
    rel = lattice.nodes - pipette.start
    xi, eta = rel @ a, np.abs(rel @ b)
    slope = np.tan(np.radians(pipette.tip_angle_deg) / 2)
    with np.errstate(divide="ignore"):
        flank = np.where(slope > 0, (0.5 * pipette.width_um - eta) / slope, -np.inf)
    flank = np.where(eta <= 0.5 * pipette.width_um, 0.0, flank)
    return float(max(0.0, np.max(np.minimum(0.0, flank) - xi)) + 1e-9)


@dataclass(frozen=True, eq=False)
class Approach:
    """The approach before it runs: pipette backed off clear of the lattice, held rim nodes,
    the travel to the spindle's initial position (um) and the spindle as a material point."""

    pipette: Pipette
    held: np.ndarray
    travel_um: float
    spindle: MaterialPoints


def approach_setup(
    lattice: Lattice,
    spindle_initial_um: tuple[float, float] = (15.8718, 18.1392),
    width_um: float = TABLE_I_WIDTH_UM,
    tip_angle_deg: float = TABLE_I_TIP_ANGLE_DEG,
    hold_half_width_um: float = HOLD_HALF_WIDTH_UM,
    contact_stiffness: float = CONTACT_STIFFNESS_NN_PER_UM,
) -> Approach:
    """The scenario's geometry (module docstring); :class:`InputError` naming the argument for
    a spindle outside the cell, at the puncture point, or a hold that holds no rim node."""
    initial = checks.numbers_array("approach_setup", "spindle_initial_um", spindle_initial_um)
    if initial.shape != (2,):
        raise InputError("approach_setup", "spindle_initial_um", "an (x, y) pair", got=initial)
    target = to_world(lattice, initial)[0]
    puncture = np.array([lattice.radius, 0.0])
    direction = target - puncture
    if not np.hypot(*direction) > 1e-9 * lattice.radius:
        raise InputError(
            "approach_setup", "spindle_initial_um", "a spindle away from the puncture point (0, 0)"
        )
    try:
        spindle = locate(lattice, target[None, :])
    except InputError:
        raise InputError(
            "approach_setup",
            "spindle_initial_um",
            f"a point inside the cell's lattice (radius {lattice.radius:g} um)",
            got=initial.tolist(),
        ) from None
    probe = Pipette(width_um, tip_angle_deg, tuple(puncture), tuple(direction), contact_stiffness)
    back = clear_back_off(lattice, probe)
    pipette = replace(probe, start=tuple(puncture - back * np.asarray(probe.direction)))
    held = held_far_side(lattice, pipette, hold_half_width_um)
    return Approach(pipette, held, back + float(np.hypot(*direction)), spindle)


def predict_spindle_offset(
    lattice: Lattice,
    params: NmsdParameters,
    spindle_initial_um: tuple[float, float] = (15.8718, 18.1392),
    width_um: float = TABLE_I_WIDTH_UM,
    tip_angle_deg: float = TABLE_I_TIP_ANGLE_DEG,
    hold_half_width_um: float = HOLD_HALF_WIDTH_UM,
    contact_stiffness: float = CONTACT_STIFFNESS_NN_PER_UM,
    speed_um_s: float = 30.0,
    step_um: float = 0.5,
) -> SpindleOffset:
    """Run the approach of the scenario above; return the spindle's end point (paper frame).

    ``step_um`` (> 0, at most the travel) is the pipette advance per simulated step.
    """
    approach = approach_setup(
        lattice, spindle_initial_um, width_um, tip_angle_deg, hold_half_width_um, contact_stiffness
    )
    travel = approach.travel_um
    step_um = checks.number(
        "predict_spindle_offset", "step_um", step_um, ge=travel / MAX_STEPS, le=travel
    )
    n_steps = max(1, int(np.ceil(travel / step_um)))
    record = list(np.linspace(0.0, travel, n_steps + 1)[1:])
    press = simulate_press(
        lattice,
        params,
        approach.pipette,
        approach.held,
        speed_um_s,
        travel,
        n_steps,
        record_um=record,
    )
    frames = [lattice.nodes] + [press.snapshots[float(a)] for a in record]
    path = np.vstack([to_paper(lattice, approach.spindle.positions(f)) for f in frames])
    initial = np.asarray(spindle_initial_um, dtype=float)
    return SpindleOffset(initial, path[-1], path, approach.pipette, press, travel)
