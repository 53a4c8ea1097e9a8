"""A pipette driven at constant speed into the lattice: the force-displacement experiment.

Seed 000, Sections II.B.2 and III.C: the pipette presses the oocyte from 3 o'clock at
30 um/s over 65 um while the opposite side is held; the force on the pipette (``F^ext`` of
eq 1, summed over the nodes it touches, along its motion) is the model output. Held nodes
are the rim nodes on the far side within ``hold_half_width_um`` of the pipette axis (the
holding pipette's mouth).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from nmsd.errors import NmsdDivergence
from nmsd.integrator import BackwardEulerStepper, NewtonFailure
from nmsd.lattice import Lattice, circular_lattice
from nmsd.parameters import NmsdParameters
from nmsd.pipette import (
    CONTACT_STIFFNESS_NN_PER_UM,
    HOLD_HALF_WIDTH_UM,
    TABLE_I_TIP_ANGLE_DEG,
    TABLE_I_WIDTH_UM,
    Pipette,
)
from nmsd.sensitivity import NAMES, PressSensitivity
from nmsd.symmetry import Mirror, mirror_of
from oocyte_fe import checks
from oocyte_fe.errors import InputError

MAX_HALVINGS = 6


@dataclass(frozen=True)
class PressResult:
    """Time history of one press.

    ``advance_um``, ``time_s``, ``force_nN`` (force on the cell along the pipette motion) at
    every step; ``snapshots`` maps each requested advance (um) to node positions (n, 2) um;
    ``newton_iterations``: total Newton iterations. With sensitivities requested,
    ``force_sensitivity`` (steps + 1, 6) holds df/dp (nN per unit of p) at every step for the
    constants ``sensitivity_names`` (:data:`nmsd.sensitivity.NAMES`), else it is None.
    """

    advance_um: np.ndarray
    time_s: np.ndarray
    force_nN: np.ndarray
    positions: np.ndarray
    snapshots: dict[float, np.ndarray] = field(default_factory=dict)
    newton_iterations: int = 0
    force_sensitivity: np.ndarray | None = None
    sensitivity_names: tuple[str, ...] = ()

    def force_at(self, advances_um: Sequence[float]) -> np.ndarray:
        """Force (nN) at the given advances (linear between steps)."""
        return np.interp(advances_um, self.advance_um, self.force_nN)

    def sensitivity_at(self, advances_um: Sequence[float]) -> np.ndarray:
        """df/dp (len(advances), 6) at the given advances (linear between steps)."""
        if self.force_sensitivity is None:
            raise InputError("PressResult", "sensitivities", "a press run with them")
        return np.stack(
            [
                np.interp(advances_um, self.advance_um, column)
                for column in self.force_sensitivity.T
            ],
            axis=1,
        )


@dataclass(frozen=True, eq=False)
class PressSetup:
    """Everything but the constants: lattice, pipette (touching at zero advance), held nodes.

    ``mirror``: follow the mirror-symmetric branch (:mod:`nmsd.symmetry`); None lets the
    lattice buckle sideways from round-off. Build it with :func:`press_setup`;
    ``run(params)`` simulates one press.
    """

    lattice: Lattice
    pipette: Pipette
    held: np.ndarray
    speed_um_s: float = 30.0
    travel_um: float = 65.0
    n_steps: int = 65
    mirror: Mirror | None = None

    def run(self, params: NmsdParameters, record_um: Sequence[float] = (), **kw) -> PressResult:
        """Simulate the press with ``params``; ``kw`` overrides speed, travel or n_steps, and
        ``sensitivities=True`` adds the exact df/dp of the force (:mod:`nmsd.sensitivity`).
        """
        options = {
            "speed_um_s": self.speed_um_s,
            "travel_um": self.travel_um,
            "n_steps": self.n_steps,
            **kw,
        }
        return simulate_press(
            self.lattice,
            params,
            self.pipette,
            self.held,
            record_um=record_um,
            mirror=self.mirror,
            **options,
        )

    def with_gap(self, gap_um: float) -> PressSetup:
        """The same press with the mouth ``gap_um`` before touching the lattice (um)."""
        if gap_um < 0:
            raise InputError("PressSetup", "gap_um", ">= 0 (a pipette starting outside)")
        touching = touching_start(self.lattice, self.pipette)
        start = np.asarray(touching.start) - gap_um * np.asarray(self.pipette.direction)
        return replace(self, pipette=replace(self.pipette, start=tuple(start)))


def press_setup(
    lattice: Lattice | None = None,
    width_um: float = TABLE_I_WIDTH_UM,
    tip_angle_deg: float = TABLE_I_TIP_ANGLE_DEG,
    hold_half_width_um: float = HOLD_HALF_WIDTH_UM,
    contact_stiffness: float = CONTACT_STIFFNESS_NN_PER_UM,
    speed_um_s: float = 30.0,
    travel_um: float = 65.0,
    n_steps: int = 65,
    gap_um: float = 0.0,
    symmetric: bool = True,
) -> PressSetup:
    """The press of Table II: pipette on the x axis from 3 o'clock, far side held.

    The mouth starts ``gap_um`` before touching the outermost node on its axis (a travel
    with no lattice contact, e.g. across the zona pellucida, which the lattice omits).
    ``symmetric``: follow the mirror-symmetric branch (:mod:`nmsd.symmetry`; the lattice,
    pipette and holder must be symmetric about the pipette axis).
    """
    gap_um = checks.number("press_setup", "gap_um", gap_um, ge=0, le=1e6)
    hold_half_width_um = checks.number(
        "press_setup", "hold_half_width_um", hold_half_width_um, gt=0, le=1e6
    )
    checks.number("press_setup", "speed_um_s", speed_um_s, ge=1e-9, le=1e9)
    checks.number("press_setup", "travel_um", travel_um, ge=1e-6, le=1e6)
    checks.number("press_setup", "n_steps", n_steps, ge=1, le=MAX_STEPS, integer=True)
    lattice = circular_lattice() if lattice is None else lattice
    far = (2.0 * lattice.radius, 0.0)
    probe = Pipette(width_um, tip_angle_deg, far, (-1.0, 0.0), contact_stiffness)
    touching = touching_start(lattice, probe)
    pipette = replace(touching, start=(touching.start[0] + gap_um, touching.start[1]))
    held = held_far_side(lattice, pipette, hold_half_width_um)
    mirror = mirror_of(lattice, pipette, held) if symmetric else None
    return PressSetup(lattice, pipette, held, speed_um_s, travel_um, n_steps, mirror)


def held_far_side(lattice: Lattice, pipette: Pipette, hold_half_width_um: float) -> np.ndarray:
    """Mask of the rim nodes opposite the pipette within ``hold_half_width_um`` of its axis."""
    hold_half_width_um = checks.number(
        "held_far_side", "hold_half_width_um", hold_half_width_um, gt=0, le=1e6
    )
    a = np.asarray(pipette.direction)
    b = np.array([-a[1], a[0]])
    along = lattice.nodes @ a
    across = np.abs((lattice.nodes - pipette.start) @ b)
    held = lattice.rim & (along > 0) & (across <= hold_half_width_um)
    if not held.any():
        raise InputError(
            "held_far_side", "hold_half_width_um", "a width that holds at least one rim node"
        )
    return held


def touching_start(lattice: Lattice, pipette: Pipette) -> Pipette:
    """The pipette moved back along its axis until its mouth just touches the lattice."""
    a = np.asarray(pipette.direction)
    b = np.array([-a[1], a[0]])
    rel = lattice.nodes - pipette.start
    in_strip = np.abs(rel @ b) <= 0.5 * pipette.width_um
    if not in_strip.any():
        raise InputError(pipette.source, "start", "a pipette axis that meets the lattice")
    shift = float(np.min(rel[in_strip] @ a))
    return replace(pipette, start=tuple(np.asarray(pipette.start) + shift * a))


MAX_STEPS = 1_000_000
"""Most backward-Euler steps one press may ask for."""
STEP_END_DECIMALS = 6  # step ends (um) are rounded to 1e-6 um
SPEED_DIGITS = 6  # the speed is read to 6 significant digits


def simulate_press(
    lattice: Lattice,
    params: NmsdParameters,
    pipette: Pipette,
    held: np.ndarray,
    speed_um_s: float = 30.0,
    travel_um: float = 65.0,
    n_steps: int = 65,
    record_um: Sequence[float] = (),
    initial_positions: np.ndarray | None = None,
    mirror: Mirror | None = None,
    sensitivities: bool = False,
) -> PressResult:
    """Drive the pipette ``travel_um`` at ``speed_um_s`` in ``n_steps`` backward-Euler steps.

    The step ends include every advance in ``record_um``; a step whose Newton iterations
    fail is halved up to 6 times before :class:`NmsdDivergence` is raised.
    Step ends are rounded to 1e-6 um and the speed to 6 significant digits: late in a press
    the lattice snaps through at the mouth's corners, and when it does moves with any change
    of the arithmetic (docs/nmsd.md, "Reproducibility"), so inputs that differ by less than
    that (a travel or a record point times 1 + 1e-9) press the same steps. A snapshot is kept
    under the advance asked for.
    With ``mirror`` the press follows the symmetric branch, solved on the half lattice
    (:mod:`nmsd.symmetry`). ``sensitivities``: also carry the forward sensitivities through
    every (sub)step and return df/dp (:class:`nmsd.sensitivity.PressSensitivity`; starts
    from rest, S_0 = 0).
    """
    speed_um_s = checks.number("simulate_press", "speed_um_s", speed_um_s, ge=1e-9, le=1e9)
    travel_um = checks.number("simulate_press", "travel_um", travel_um, ge=1e-6, le=1e6)
    n_steps = int(
        checks.number("simulate_press", "n_steps", n_steps, ge=1, le=MAX_STEPS, integer=True)
    )
    for value in record_um:
        checks.number("simulate_press", "record_um", value, ge=0)
    x = lattice.nodes.copy() if initial_positions is None else np.array(initial_positions)
    if pipette.contains(x, 0.0).any():
        raise InputError(
            pipette.source, "start", "a pipette that starts outside the cell (no node inside it)"
        )
    speed_um_s = float(f"{speed_um_s:.{SPEED_DIGITS}g}")
    wanted: dict[float, list[float]] = {}  # step end -> the advances asked for there
    for r in record_um:
        if 0 < r <= travel_um:
            wanted.setdefault(float(np.round(r, STEP_END_DECIMALS)), []).append(float(r))
    uniform = np.round(np.linspace(0.0, travel_um, n_steps + 1), STEP_END_DECIMALS)
    grid = np.union1d(uniform, list(wanted))
    stepper = BackwardEulerStepper(lattice, params, pipette, held, mirror=mirror)
    tracker = PressSensitivity(stepper) if sensitivities else None
    dforce = np.zeros((len(grid), len(NAMES))) if sensitivities else None
    v = np.zeros_like(x)
    force = np.zeros(len(grid))
    snapshots = {r: x.copy() for r in wanted.get(0.0, ())}  # asked for < 5e-7 um
    if 0.0 in record_um:
        snapshots[0.0] = x.copy()
    iterations = 0
    for k in range(1, len(grid)):
        x, v, f_contact, its, df = _advance(
            stepper, x, v, grid[k - 1], grid[k], speed_um_s, k, tracker=tracker
        )
        iterations += its
        force[k] = float(f_contact.sum(axis=0) @ np.asarray(pipette.direction))
        if dforce is not None:
            dforce[k] = df
        for r in wanted.get(float(grid[k]), ()):
            snapshots[r] = x.copy()
    names = NAMES if sensitivities else ()
    return PressResult(grid, grid / speed_um_s, force, x, snapshots, iterations, dforce, names)


def _advance(
    stepper: BackwardEulerStepper,
    x: np.ndarray,
    v: np.ndarray,
    s0: float,
    s1: float,
    speed: float,
    step: int,
    depth: int = 0,
    tracker: PressSensitivity | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, np.ndarray | None]:
    """One step from advance s0 to s1, split in halves when Newton fails.

    With a ``tracker`` the sensitivities follow every converged substep; the last element
    returned is df/dp at s1 (None without a tracker).
    """
    dt = (s1 - s0) / speed
    try:
        res = stepper.step(x, v, s1, dt)
        df = None if tracker is None else tracker.update(x, v, res.positions, s1, dt)
        return res.positions, res.velocities, res.contact_force, res.iterations, df
    except NewtonFailure as exc:
        if depth >= MAX_HALVINGS:
            raise NmsdDivergence(step, s1 / speed, str(exc), dt / 2) from None
    mid = 0.5 * (s0 + s1)
    x, v, _, n1, _ = _advance(stepper, x, v, s0, mid, speed, step, depth + 1, tracker)
    x, v, f, n2, df = _advance(stepper, x, v, mid, s1, speed, step, depth + 1, tracker)
    return x, v, f, n1 + n2, df
