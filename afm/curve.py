"""A force curve (approach segment) in the internal units, validated where it enters.

Convention: ``piezo_um`` is the piezo (scanner) travel towards the sample, increasing during
the approach; ``force_nN`` the cantilever force, positive when pressing on the sample. The
tip-sample separation follows from the cantilever deflection ``force / k``::

    tip position  x = piezo - F/k                          [um]
    indentation   delta = x - contact_point = piezo - contact_point - F/k

A recorded column of either sign (a JPK-style height decreases towards the sample) is turned
into this convention where it is read (:func:`approach_segment`, afmformats' files in
:mod:`afm.instrument_io`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from oocyte_fe.checks import QUANTITIES, float_array, increasing, number, positive
from oocyte_fe.errors import InputError

MIN_POINTS = 10
MAX_JITTER_FRACTION = 0.02
"""Largest step back of the piezo/height (as a fraction of its travel) taken as sensor jitter."""


@dataclass(frozen=True)
class ForceCurve:
    """Approach force curve: piezo travel [um], force [nN], spring constant k [nN/um].

    (k in N/m times 1000 is k in nN/um.) ``source`` names the file it came from, for errors.
    ``height_channel`` names the recorded column the piezo travel came from (for instrument
    files ``height (measured)``, ``height (piezo)`` or ``tip position``; ``piezo`` for text
    tables); ``map_position_um`` is the (x, y) position of the curve on a force map and
    ``curve_index`` its index in the file (``None`` for single curves).

    ``time_s`` (optional) must be finite and increase row by row
    (:func:`oocyte_fe.checks.increasing`): a decreasing or NaN time is refused, naming the row.

    The travel is kept as recorded: a measured height jitters, so steps back of up to
    :data:`MAX_JITTER_FRACTION` of the travel are accepted (no step of the fit needs the data
    sorted); a larger step back means approach and retract are mixed and is refused.
    """

    piezo_um: np.ndarray
    force_nN: np.ndarray
    spring_constant_nN_per_um: float
    source: str = "<input>"
    group: str = ""
    time_s: np.ndarray | None = field(default=None, compare=False)
    height_channel: str = "piezo"
    map_position_um: tuple[float, float] | None = None
    curve_index: int | None = None

    def __post_init__(self) -> None:
        src = self.source
        piezo = float_array(src, "piezo_um", self.piezo_um)
        force = float_array(src, "force_nN", self.force_nN)
        if piezo.ndim != 1 or force.shape != piezo.shape:
            raise InputError(src, "force_nN", "one force per piezo position (1-D columns)")
        if piezo.size < MIN_POINTS:
            raise InputError(src, "piezo_um", f"at least {MIN_POINTS} points", piezo.size)
        for name, values in (("piezo_um", piezo), ("force_nN", force)):
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:  # rows as checks.increasing counts them: 1 = below the header
                row = int(bad[0])
                raise InputError(
                    src,
                    name,
                    f"finite numbers (NaN/inf at data row {row + 1}: {float(values[row])!r})",
                )
        travel = float(piezo[-1] - piezo[0])
        step_back = np.maximum.accumulate(piezo) - piezo
        if not travel > 0 or float(step_back.max()) > MAX_JITTER_FRACTION * travel:
            row = int(np.argmax(step_back)) if travel > 0 else None
            raise InputError(
                src,
                "piezo_um",
                "a monotonic approach (travel towards the sample; steps back up to "
                f"{100 * MAX_JITTER_FRACTION:g} % of the travel are taken as sensor jitter)",
                None
                if row is None
                else f"a step back of {step_back[row]:.3g} um at data row {row + 1}",
            )
        if self.time_s is not None:
            time = increasing(src, "time_s", self.time_s)
            if time.shape != piezo.shape:
                raise InputError(src, "time_s", "one time per piezo position", time.size)
            object.__setattr__(self, "time_s", time)
        k = positive(
            src,
            "spring_constant",
            self.spring_constant_nN_per_um,
            expected="a positive spring constant in nN/um",
        )
        object.__setattr__(self, "piezo_um", piezo)
        object.__setattr__(self, "force_nN", force)
        object.__setattr__(self, "spring_constant_nN_per_um", k)

    @property
    def tip_position_um(self) -> np.ndarray:
        """x = piezo - F/k, um: the tip position once the cantilever deflection is removed."""
        return self.piezo_um - self.force_nN / self.spring_constant_nN_per_um

    def with_force(self, force_nN: np.ndarray) -> ForceCurve:
        """The same curve with another force column (for example baseline-corrected)."""
        return replace(self, force_nN=force_nN)

    def slice(self, start: int, stop: int) -> ForceCurve:
        """Points ``start:stop`` as a new curve."""
        time = None if self.time_s is None else self.time_s[start:stop]
        return replace(
            self,
            piezo_um=self.piezo_um[start:stop],
            force_nN=self.force_nN[start:stop],
            time_s=time,
        )


def spring_constant_nN_per_um(k_N_per_m: float, where: str = "<input>") -> float:
    """Convert a spring constant from N/m (instrument convention) to nN/um (x 1000).

    Bounds: those of ``stiffness_nN_per_um`` in :data:`oocyte_fe.checks.QUANTITIES` over 1000,
    [1e-12, 1e9] N/m (the case schema's bound of the unit N/m).
    """
    low, high, _ = QUANTITIES["stiffness_nN_per_um"]
    k = number(
        where,
        "spring_constant_N_per_m",
        k_N_per_m,
        ge=low / 1e3,
        le=high / 1e3,
        expected=f"a positive spring constant in [{low / 1e3:g}, {high / 1e3:g}] N/m",
    )
    return 1e3 * k


def force_from_deflection(
    deflection_V: np.ndarray, sensitivity_nm_per_V: float, k_N_per_m: float, where: str = "<input>"
) -> np.ndarray:
    """F = V * s * k: deflection [V] times sensitivity [nm/V] times spring constant [N/m] -> nN.

    (nm times N/m is nN.)
    """
    s = positive(
        where,
        "sensitivity_nm_per_V",
        sensitivity_nm_per_V,
        expected="a positive sensitivity in nm/V",
    )
    k = spring_constant_nN_per_um(k_N_per_m, where) / 1e3
    with np.errstate(all="ignore"):
        force = float_array(where, "deflection_V", deflection_V) * s * k
    if not np.all(np.isfinite(force)):
        raise InputError(where, "deflection_V", "forces V * s * k within floating point range")
    return force


def approach_end(towards_um: np.ndarray) -> int:
    """End (exclusive) of the approach in a travel towards the sample: all points, or, when
    the travel turns back by more than :data:`MAX_JITTER_FRACTION` of its span, the points
    before the turn (the farthest travel, where the retract starts)."""
    span = float(np.ptp(towards_um))
    step_back = np.maximum.accumulate(towards_um) - towards_um
    if span > 0 and float(step_back.max()) > MAX_JITTER_FRACTION * span:
        return int(np.argmax(towards_um))
    return towards_um.size


def approach_segment(
    travel: np.ndarray, force_nN: np.ndarray, source: str, column: str
) -> tuple[np.ndarray, int]:
    """The travel towards the sample and the end (exclusive) of the approach of a recorded
    column whose sign convention is not known (a text table's piezo or height column).

    Rows are in time order. The approach runs from the first row to the farthest travel
    from it, ``turn = argmax |travel - travel[0]|``; its direction gives the sign::

        s = sign(travel[turn] - travel[0]),   towards = s * travel            [um]

    so a piezo extension (increasing towards the sample) and a JPK-style height (decreasing
    towards it) both become a travel increasing towards the sample, and the tip travel from
    the curve's first point (``contact_from_start_um``) keeps its meaning. Rows after the
    turn (a retract) are left out (:func:`approach_end`). The approach must end where the
    force rises: when the median force of its last ``m = max(3, n/50)`` rows lies below that of
    its first ``m`` rows by more than a quarter of its force range, the rows hold a retract
    only (travel away from the sample, force falling) and are refused with
    :class:`InputError`.
    """
    offset = travel - travel[0]
    turn = int(np.argmax(np.abs(offset)))
    towards = travel if offset[turn] >= 0 else -travel
    end = approach_end(towards)
    force = force_nN[:end]
    m = max(3, end // 50)
    if end > m:
        first, last = float(np.median(force[:m])), float(np.median(force[-m:]))
        if first - last > 0.25 * float(np.ptp(force)):
            raise InputError(
                source,
                column,
                "an approach (rows in time order, the force rising as the tip nears the "
                "sample); these rows are a retract only (travel away from the sample, the "
                "force falling): give the approach, or approach then retract",
                f"force {first:.3g} nN at the first rows falling to {last:.3g} nN at row {end}",
            )
    return towards, end
