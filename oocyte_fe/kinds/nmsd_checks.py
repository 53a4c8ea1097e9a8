"""What the NMSD input models read at validation, apart from their fields: the library setups
(the lattice, pipette and hold ``run`` builds) and the Table II file's extent, each built once
per geometry or file (a sweep's probes vary other inputs)."""

from __future__ import annotations

import functools
import math
import typing
from pathlib import Path
from typing import Any, Literal

from nmsd.calibration import CONSTANTS
from nmsd.constants_file import read_constants
from nmsd.lattice import circular_lattice
from nmsd.press import press_setup
from nmsd.spindle import Approach, approach_setup
from nmsd.tableII import read_force_displacement
from oocyte_fe.crosscheck.scenario import PressScenario
from oocyte_fe.errors import InputError
from oocyte_fe.fe.obstacles import largest_edge_radius
from oocyte_fe.runner.schema import RuleBroken

LIBRARY_ARGS = (
    ("diameter_um", "cell_diameter_um"),
    ("width_um", "pipette_width_um"),
    ("contact_stiffness", "contact_stiffness_nN_per_um"),
)
"""Library argument -> case input, for the errors of the setups run at validation."""


@functools.lru_cache(maxsize=16)
def _press_geometry(*args: object) -> None:
    """:func:`press_setup` on a fresh lattice, built once per geometry; the mirror pairs are
    left to ``run`` (costly)."""
    diameter, spacings, *rest = args
    press_setup(circular_lattice(diameter, spacings), *rest, symmetric=False)  # type: ignore[arg-type]


@functools.lru_cache(maxsize=16)
def _approach_geometry(diameter: float, spacings: int, *rest: object) -> Approach:
    """:func:`approach_setup` on a fresh lattice, built once per geometry."""
    return approach_setup(circular_lattice(diameter, spacings), *rest)  # type: ignore[arg-type]


def press_at_validation(m: Any) -> None:
    """The press ``run`` builds from a :class:`~.nmsd_inputs.PressInputs`."""
    _press_geometry(
        m.cell_diameter_um,
        m.spacings_across,
        m.pipette_width_um,
        m.tip_angle_deg,
        m.hold_half_width_um,
        m.contact_stiffness_nN_per_um,
        m.speed_um_s,
        m.travel_um,
        m.n_steps,
        m.gap_um,
    )


def approach_at_validation(m: Any) -> Approach:
    """The approach ``run`` builds from a :class:`~.nmsd_inputs.SpindleInputs`."""
    return _approach_geometry(
        m.cell_diameter_um,
        m.spacings_across,
        tuple(m.spindle_initial_um),
        m.pipette_width_um,
        m.tip_angle_deg,
        m.hold_half_width_um,
        m.contact_stiffness_nN_per_um,
    )


def approach_travel_um(m: Any) -> float:
    """Pipette travel of the spindle approach (mouth clear of the lattice to the spindle's
    initial position), um; ``inf`` when the setup itself fails (its own rule reports it)."""
    try:
        return approach_at_validation(m).travel_um
    except InputError:
        return math.inf


@functools.lru_cache(maxsize=16)
def _displacements(path: Path, stamp: tuple[int, int]) -> tuple[float, ...]:
    return tuple(float(d) for d in read_force_displacement(path).displacement_um)


def data_displacements_um(path: Path | None) -> tuple[float, ...]:
    """The ``displacement`` column of a Table II file, um; empty when it cannot be read (the
    reader run at validation names the file, column and row: :class:`DataReader`)."""
    if path is None:
        return ()
    try:
        stat = Path(path).stat()
        return _displacements(Path(path), (stat.st_mtime_ns, stat.st_size))
    except (InputError, OSError):
        return ()


def data_extent_um(path: Path | None) -> float:
    """Largest displacement of a Table II file, um; ``-inf`` when it cannot be read."""
    return max(data_displacements_um(path), default=-math.inf)


def enough_points(m: Any) -> None:
    """At least as many displacements past the contact (above ``gap_um``) as the calibration
    frees constants: the most of the families in ``models`` (``nmsd``: k1, k2, d0, d1; the
    spindle kind calibrates ``nmsd``) plus ``calibrate_extra``. With fewer, some combination
    of constants is not determined at all (before contact the force is 0 whatever they are)."""
    free = max(len(CONSTANTS[f]) for f in getattr(m, "models", ["nmsd"])) + len(m.calibrate_extra)
    displacements = data_displacements_um(m.data)
    past = sum(1 for d in displacements if d > m.gap_um)
    if displacements and past < free:
        raise InputError(
            m.data,
            "data",
            f"at least {free} displacements above gap_um = {m.gap_um:g} um, one per constant "
            "calibrated (with fewer, some constant is not determined at all)",
            got=past,
        )


def data_inside_cell(m: Any) -> None:
    """Every Table II displacement within the press the cell allows (``cell_diameter_um -
    gap_um``): a row beyond it names ``data``, not the travel that cannot reach it."""
    extent, room = data_extent_um(m.data), m.cell_diameter_um - m.gap_um
    if extent >= room:
        raise InputError(
            m.data,
            "data",
            f"displacement_um below cell_diameter_um - gap_um = {room:g} um in every row "
            "(a press cannot go through the cell)",
            got=extent,
        )


ZonaRatioReading = Literal["afm_relaxed", "afm_instantaneous"]
READINGS = typing.get_args(ZonaRatioReading)
CELLS_ACROSS = 1000
FINEST = f"cell_diameter_um / {CELLS_ACROSS} (at most ~1e6 elements or grid points)"
"""``nmsd_vs_fe``'s finest FE element and comparison grid: a thousandth of the cell."""


def press_scenario(m: Any, source: str = "PressScenario") -> PressScenario:
    """The press scenario of a crosscheck case's inputs (``source``: named in refusals); its
    ``Setup`` rule builds it at ``validate``, the kind at ``run``."""
    return PressScenario(
        m.cell_diameter_um,
        m.cytoplasm_diameter_um,
        m.pipette_width_um,
        m.tip_angle_deg,
        m.speed_um_s,
        m.hold_half_width_um,
        tuple(m.spindle_paper_um),
        source=source,
    )


def edge_radius_limit(m: Any) -> float:
    """The largest FE pipette edge radius that fits the wedge's mouth, um."""
    return largest_edge_radius(m.pipette_width_um, m.tip_angle_deg)


def radius(m: Any) -> float:
    """Half the cell's diameter, um."""
    return m.cell_diameter_um / 2


def ratio_or_reading(value: object) -> object:
    """``nmsd_zona_stiffness_ratio`` before its union is tried: one message for a bad value
    (pydantic's would name its own union members)."""
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if (isinstance(value, str) and value not in READINGS) or (number and not value > 0):
        raise ValueError(f"a number > 0 or one of {', '.join(map(repr, READINGS))}")
    return value


def second_speed_given(m: Any) -> Any:
    """``calibrate_both_speeds`` needs the second speed ``check_speed_um_s`` (0 turns it off)."""
    if m.calibrate_both_speeds and not m.check_speed_um_s:
        raise RuleBroken(
            "check_speed_um_s",
            "a second speed > 0 with calibrate_both_speeds = true (0 turns the check off)",
            m.check_speed_um_s,
        )
    return m


def arrows_on_frames(m: Any) -> Any:
    """``nmsd_vs_fe``'s arrow plots are drawn at FE output frames: an ``arrow_advances_um``
    value between frames was left out of the figures without a word."""
    import numpy as np

    from oocyte_fe.crosscheck.fe_press import output_frames

    if max(m.arrow_advances_um, default=0.0) > m.travel_um or m.fe_step_um > m.travel_um:
        return m  # the simpler rules name these
    n = output_frames(m.travel_um, m.fe_step_um)
    frames = np.linspace(0.0, m.travel_um, n + 1)[1:]
    off = [a for a in m.arrow_advances_um if not np.any(np.isclose(frames, a))]
    if off:
        raise RuleBroken(
            "arrow_advances_um",
            f"advances on the FE's output frames (travel_um / {n} = {m.travel_um / n:g} um "
            "apart, fe_step_um rounded to fit the travel)",
            off,
        )
    return m


def same_lattice(m: Any) -> None:
    """The constants of ``constants_file`` hold on its lattice: the case presses the same
    cell diameter and spacings, with the same critical strain and damping reading (an
    unreadable file is left to its reader, which names the fault)."""
    if m.constants_file is None:
        return
    try:
        c = read_constants(m.constants_file)
    except InputError:
        return
    for field, theirs in (
        ("cell_diameter_um", c.cell_diameter_um),
        ("spacings_across", c.spacings_across),
        ("dl_c", c.params.dl_c),
        ("damping", c.params.damping),
    ):
        ours = getattr(m, field)
        if ours != theirs:
            raise RuleBroken(
                field,
                f"{theirs!r}, as in constants_file {m.constants_file.name} (its constants "
                "belong to the lattice and press they were calibrated on)",
                ours,
            )
