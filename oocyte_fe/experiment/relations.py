"""Relations between an experiment's tools and its cell that no one table can check.

Each check raises :class:`~oocyte_fe.runner.schema.RuleBroken` naming the input it refuses
(``field``, relative to the model that calls it), so that ``validate`` reports the file and
the field in one line:

* :func:`presses`: a tool driven by a displacement path must press the cell at some time (its
  largest advance beyond its ``gap_um``), by at least a floor the mesh resolves (an advance in
  metres, 3e-7, is refused); the message says how far short it stops;
* :func:`clear_at_start`: a tool starts clear of the cell or touching it (its advance at t = 0
  at most its gap), never inside it;
* :func:`resolvable`: a tool's length (a sphere's radius, a pipette's radii) at least a floor the
  mesh resolves (a radius typed in metres, 3e-6, is refused);
* :func:`opposed`: two tools on opposite sides (top / bottom, left / right) advance together:
  their travels into the cell (advance less gap; a holding pipette carries the surface it holds,
  gap 0) must sum below the cell's diameter at every time, or the gap between them would close;
* :func:`presses_throughout`: tools that support the cell alone (no holding pipette, no fixed
  seal) press it at every time after t = 0;
* :func:`neck_fits` and :func:`neck_advance`: a necked pipette whose bore takes the cell (with
  its clearance) and whose neck is narrower than the cell (otherwise the cell passes without
  touching it: no aspiration through a neck), and an advance that brings the cell onto the
  taper but keeps it inside the modelled glass;
* :func:`window_meets_section`: a pressure's polar window that selects part of the surface.

The same functions check the ``fe_experiment`` description and the ``fe_neck_aspiration``
inputs (which build a necked-pipette experiment when they run).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from oocyte_fe.experiment.paths import PathSpec
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.runner.schema import RuleBroken

OPPOSITE = {"top": "bottom", "bottom": "top", "left": "right", "right": "left"}


@dataclass(frozen=True)
class Travel:
    """A tool's advance into the cell: its path less its clearance ``gap_um`` [um]."""

    field: str
    side: str
    path: PathSpec | None
    gap_um: float = 0.0

    def at(self, t: NDArray) -> NDArray:
        """``w(t) - gap`` [um] at the times ``t`` (a path is held after its last time)."""
        w = (
            np.zeros_like(t)
            if self.path is None
            else np.interp(t, self.path.time_s, self.path.value)
        )
        return w - self.gap_um

    @property
    def times(self) -> NDArray:
        return np.asarray([0.0] if self.path is None else self.path.time_s, dtype=float)


def _knots(*travels: Travel) -> NDArray:
    """Every time where one of the piecewise-linear travels may turn (their sum's extrema)."""
    return np.unique(np.concatenate([t.times for t in travels]))


def _short(travel: Travel, deepest: float) -> str:
    if deepest < 0:
        return f"it stops {-deepest:g} um short of the cell"
    return "it only reaches the cell's surface, never presses it"


METRES_BELOW_UM = 1e-3
"""A length below this many um is named as a likely value in metres (3e-6 for 3 um)."""


def _metres(value_um: float) -> str:
    if 0 < value_um < METRES_BELOW_UM:
        return f"; {value_um:g} um looks like metres ({value_um * 1e6:g} um?)"
    return ""


def presses(travel: Travel, floor_um: float = 0.0, floor_why: str = "") -> None:
    """RuleBroken unless the tool's largest advance exceeds its gap (it presses the cell), by
    at least ``floor_um`` (``floor_why`` says where it comes from: the mesh's finest element)."""
    deepest = float(np.max(travel.at(travel.times)))
    if deepest <= 0:
        raise RuleBroken(
            travel.field,
            "a path that presses the tool into the cell (an advance beyond gap_um = "
            f"{travel.gap_um:g} um): its largest advance is {deepest + travel.gap_um:g} um, so "
            + _short(travel, deepest)
            + (
                " (a dish the cell rests on: a holding_pipette)"
                if deepest == -travel.gap_um
                else ""
            ),
            travel.path.value if travel.path else None,
        )
    if deepest < floor_um:
        raise RuleBroken(
            travel.field,
            f"a largest advance into the cell (beyond gap_um = {travel.gap_um:g} um) of at "
            f"least {floor_um:g} um ({floor_why}): it presses only {deepest:g} um"
            + _metres(deepest),
            travel.path.value if travel.path else None,
        )


def clear_at_start(travel: Travel, gap_name: str = "gap_um") -> None:
    """RuleBroken if the tool starts inside the cell: its advance at t = 0 beyond its gap."""
    start = float(travel.at(np.zeros(1))[0])
    if start > 0:
        raise RuleBroken(
            travel.field,
            f"an advance at t = 0 of at most {gap_name} = {travel.gap_um:g} um (the tool "
            f"starts clear of the cell or touching it): it starts {start:g} um inside the cell",
            travel.path.value if travel.path else None,
        )


def resolvable(field: str, value_um: float, floor_um: float, floor_why: str) -> None:
    """RuleBroken if a tool's length is below ``floor_um`` (a length the mesh resolves)."""
    if value_um < floor_um:
        raise RuleBroken(
            field, f"at least {floor_um:g} um ({floor_why})" + _metres(value_um), value_um
        )


def opposed(travels: list[Travel], diameter_um: float) -> None:
    """RuleBroken if two tools on opposite sides together travel the cell's diameter."""
    for i, a in enumerate(travels):
        for b in travels[i + 1 :]:
            if OPPOSITE[a.side] != b.side or (a.path is None and b.path is None):
                continue
            t = _knots(a, b)
            total = a.at(t) + b.at(t)
            k = int(np.argmax(total))
            if total[k] >= diameter_um:
                first, other = (a, b) if a.at(t[k : k + 1])[0] >= b.at(t[k : k + 1])[0] else (b, a)
                raise RuleBroken(
                    first.field,
                    f"travels of opposed tools, {first.field} and {other.field} (advance less "
                    f"gap), summing below the cell's diameter {diameter_um:g} um: at t = "
                    f"{t[k]:g} s they sum to {total[k]:g} um (the gap between the tools would "
                    "close)",
                    first.path.value if first.path else None,
                )


def presses_throughout(travel: Travel) -> str | None:
    """Why a supporting tool lets the cell go at some time after t = 0, or ``None``: its
    travel must be >= 0 at t = 0 and > 0 at every later knot (piecewise linear: then > 0 on
    the whole of (0, end])."""
    t = travel.times
    w = travel.at(t)
    if w[0] < 0:
        return f"{travel.field} is {-w[0]:g} um clear of the cell at t = 0 s"
    later = np.flatnonzero(w[1:] <= 0)
    if later.size:
        k = int(later[0]) + 1
        return f"{travel.field} is {-w[k]:g} um clear of the cell at t = {t[k]:g} s"
    return None


def neck_fits(
    cell_diameter_um: float,
    bore_diameter_um: float,
    neck_diameter_um: float,
    clearance_um: float,
    prefix: str = "",
) -> None:
    """RuleBroken unless the bore takes the cell with its clearance and the neck is narrower
    than the cell (fields ``bore_diameter_um``, ``neck_diameter_um`` after ``prefix``)."""
    if not cell_diameter_um + 2 * clearance_um < bore_diameter_um:
        raise RuleBroken(
            f"{prefix}bore_diameter_um",
            f"a bore wider than the cell's diameter + 2 clearance_um = "
            f"{cell_diameter_um + 2 * clearance_um:g} um (the cell starts in the bore)",
            bore_diameter_um,
        )
    if not neck_diameter_um < cell_diameter_um:
        raise RuleBroken(
            f"{prefix}neck_diameter_um",
            f"a neck narrower than the cell's diameter {cell_diameter_um:g} um (a wider neck "
            "lets the cell through untouched: no aspiration through a neck)",
            neck_diameter_um,
        )


def neck_advance(
    cell_radius_um: float, pipette: NeckedPipette, clearance_um: float, travel: Travel
) -> None:
    """RuleBroken unless the cell's advance into the necked pipette (``travel``: the rear
    cap's path plus the pipette's own) brings it onto the taper (beyond ``clearance_um``) and
    keeps it inside the modelled glass: the rear pole, carried to ``-R + w``, plus the length
    ``4 R^3 / (3 R_n^2)`` of a neck-wide cylinder of the cell's volume within the neck's end
    (once the rear pole is in the neck, the cell ahead of it is at least that long)."""
    deepest = float(np.max(travel.at(travel.times)))
    if deepest <= clearance_um:
        raise RuleBroken(
            travel.field,
            f"an advance beyond clearance_um = {clearance_um:g} um (the cell must reach the "
            f"taper): the largest advance is {deepest:g} um, it stops "
            f"{clearance_um - deepest:g} um short of the glass",
            travel.path.value if travel.path else None,
        )
    placed = pipette.touching(cell_radius_um, clearance_um)
    end = placed.z_neck_um + placed.neck_length_um
    length = 4.0 * cell_radius_um**3 / (3.0 * placed.neck_radius_um**2)
    most = end + cell_radius_um - length
    if deepest > most:
        raise RuleBroken(
            travel.field,
            f"an advance of at most {most:.4g} um (the cell's rear pole, {cell_radius_um:g} um "
            f"behind its centre, plus {length:.4g} um of cell in the neck within the neck's "
            f"end {end:.4g} um ahead: the modelled glass)",
            deepest,
        )


def window_meets_section(field: str, window_deg: list[float], axisymmetric: bool) -> None:
    """RuleBroken if a polar window selects no surface: the axisymmetric section's polar
    angles run from 0 to 180 deg only (x >= 0); plane strain covers -180 to 180 deg."""
    lo, hi = window_deg
    if axisymmetric and hi <= 0.0:
        raise RuleBroken(
            field,
            "a window that meets the polar angles of the axisymmetric section, 0 to 180 deg "
            "(x >= 0; this one selects no surface, so the load would do nothing)",
            list(window_deg),
        )


def window_shows_cell(
    field: str, window_um: list[float], radius_um: float, reach_um: float
) -> None:
    """RuleBroken if a section window ``[x_min, x_max, y_min, y_max]`` um misses the cell: it
    must overlap the cell's extent, ``|x| < R`` and ``|y| < R + reach`` (the cell centred at
    the origin, moved along the axis at most as far as the tools travel, ``reach``)."""
    x0, x1, y0, y1 = window_um
    r, far = radius_um, radius_um + reach_um
    if x1 <= -r or x0 >= r or y1 <= -far or y0 >= far:
        raise RuleBroken(
            field,
            f"a window that shows part of the cell: x within ({-r:g}, {r:g}) um and y within "
            f"({-far:g}, {far:g}) um (the cell about the origin, and as far as the tools move)",
            list(window_um),
        )
