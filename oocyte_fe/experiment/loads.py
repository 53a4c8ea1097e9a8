"""Loads on the cell's outer surface: a pressure, or a traction table (e.g. a flow's).

``[inputs.loads.<name>]`` declares a load by its ``type``:

* ``pressure``: a follower pressure ``pressure_Pa(t)`` [Pa] on the outer surface, optionally
  within a polar window ``window_deg = [lo, hi]`` (deg from +y towards +x, in the current
  configuration); positive pushes inwards.
* ``traction``: a table of nominal tractions on the outline of the undeformed cell, a CSV file
  with the columns ``x_um, y_um, tx_Pa, ty_Pa`` (``#`` comments allowed), scaled by
  ``scale(t)`` (default: a ramp from 0 to 1 over the experiment). Between the table's points
  the traction is interpolated linearly in the polar angle ``theta = atan2(x, y)`` (periodic on
  the full disc of ``plane_strain``). It is a dead load on the reference surface (the one-way
  reading of a flow's traction on the undeformed cell): ``f = scale(t) T(Theta) dA``. With
  ``follower = true`` (plane strain) its normal part ``p = -T . N`` (``N`` the outline's
  outward normal at the row) becomes a follower pressure on the current surface, by the
  current polar angle ``theta`` of each point (about the cell's centre, which the pins
  hold): ``f = scale(t) p(theta) n da``; the tangential part stays dead. The flow's pressure
  then acts on the deformed outline, as it does on the cell it was computed around.

A free cell (no tool holds it; ``support = "inertia_relief"``) is held by its own inertia: the
resultant ``F`` and moment ``M`` (about the centre) of the dead loads accelerate it as a rigid
body, and the body force ``b = -rho a`` of that acceleration balances them exactly::

    b(X) = -(F / V) - (M / I) e_z x X,    V = int dV,  I = int |X|^2 dV   (plane strain)

(axisymmetric: ``b_z = -F_z / V``). The resultant of dead loads does not change as the cell
deforms, their moment about the deformed cell does: in plane strain the moment left is
balanced at every Newton iterate by a further body force of the rotation mode
(:class:`oocyte_fe.fe.loads.TorqueRelief`), so that no pin carries a couple; with a
follower traction also its resultant, which changes as the cell deforms (the relief's
``translation``). Three (one) vertex components pinned near the centre then only remove the
rigid motion; their reaction is the imbalance left by the follower pressures' change of
direction (none with a follower traction in plane strain), reported as ``hold_reaction_nN``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Discriminator, Field, Tag, model_validator

from oocyte_fe.errors import InputError
from oocyte_fe.experiment.paths import PathSpec
from oocyte_fe.io.columns import read_columns
from oocyte_fe.runner.schema import CaseInputs, DataFile

COLUMNS = ("x_um", "y_um", "tx_Pa", "ty_Pa")
MAX_GAP_DEG = 45.0  # the largest polar gap between a traction table's points


class PressureLoad(CaseInputs):
    """A follower pressure on the outer surface (or a polar window of it)."""

    type: Literal["pressure"]
    pressure_Pa: PathSpec = Field(description="pressure against time; positive pushes inwards")
    window_deg: list[Annotated[float, Field(ge=-180, le=180)]] | None = Field(
        None,
        min_length=2,
        max_length=2,
        description="[lo, hi] polar window, deg from +y towards +x (default: all around)",
        json_schema_extra={"unit": "deg"},
    )

    @model_validator(mode="after")
    def _window(self) -> PressureLoad:
        if self.window_deg is not None and self.window_deg[0] >= self.window_deg[1]:
            raise ValueError("window_deg: [lo, hi] with lo < hi")
        return self


class TractionLoad(CaseInputs):
    """A table of tractions on the undeformed outline (a dead load), scaled in time."""

    type: Literal["traction"]
    table: DataFile = Field(description="CSV: x_um, y_um, tx_Pa, ty_Pa on the outline")
    scale: PathSpec | None = Field(None, description="multiplier against time (default 0 -> 1)")
    follower: bool = Field(
        False, description="the normal part a follower pressure by current polar angle"
    )


LOAD_TYPES = {"pressure": PressureLoad, "traction": TractionLoad}


def _load_type(value: object) -> str | None:
    kind = value.get("type") if isinstance(value, dict) else getattr(value, "type", None)
    return kind if kind in LOAD_TYPES else None


Load = Annotated[
    Annotated[PressureLoad, Tag("pressure")] | Annotated[TractionLoad, Tag("traction")],
    Discriminator(
        _load_type,
        custom_error_type="load_type",
        custom_error_message="a table with type = 'pressure' or 'traction'",
    ),
]
"""A load table, told apart by its ``type``."""


def polar_deg(x: NDArray) -> NDArray:
    """Polar angle [deg] from +y towards +x of points ``x`` (2, ...)."""
    return np.degrees(np.arctan2(x[0], x[1]))


def read_traction_table(path: Path, radius_um: float, axisymmetric: bool) -> NDArray:
    """The table's rows (theta_deg, tx_kPa, ty_kPa), sorted by angle; checked to lie on the
    outline (within 2 % of the radius) and to cover it with gaps of at most 45 deg."""
    cols = read_columns(path)  # finite numbers, every fault named with its line
    if any(c not in cols for c in COLUMNS):
        raise InputError(path, "columns", ", ".join(COLUMNS), got=", ".join(cols))
    if cols["x_um"].size < 8:
        raise InputError(path, "rows", "at least 8 rows of finite numbers")
    xy = np.array([cols["x_um"], cols["y_um"]])
    r = np.hypot(*xy)
    if np.any(np.abs(r - radius_um) > 0.02 * radius_um) or (
        axisymmetric and np.any(xy[0] < -0.02 * radius_um)
    ):
        k = int(np.argmax(np.abs(r - radius_um)))
        raise InputError(
            path,
            "x_um, y_um",
            f"points on the cell's outline (radius {radius_um:g} um, within 2 %"
            f"{'; x >= 0 in axisymmetry' if axisymmetric else ''})",
            got=f"({xy[0, k]:g}, {xy[1, k]:g})",
        )
    theta = polar_deg(xy)
    order = np.argsort(theta)
    theta = theta[order]
    if axisymmetric:  # the end gaps, mirrored about the axis, count twice
        ends = [2.0 * theta[0], 2.0 * (180.0 - theta[-1])]
    else:
        ends = [theta[0] + 360.0 - theta[-1]]
    gaps = np.concatenate([np.diff(theta), ends])
    if np.any(np.diff(theta) <= 0) or gaps.max() > MAX_GAP_DEG:
        raise InputError(
            path, "rows", f"distinct points around the outline, gaps <= {MAX_GAP_DEG:g} deg"
        )
    tx, ty = cols["tx_Pa"][order], cols["ty_Pa"][order]
    return np.array([theta, 1e-3 * tx, 1e-3 * ty]).T  # Pa -> kPa


def write_traction_table(path: Path, points_um: NDArray, traction_kPa: NDArray, about: str) -> Path:
    """A traction table ``path`` for a ``traction`` load: points (n, 2) [um] on the outline
    and tractions (n, 2) [kPa, written in Pa], with the comment ``about``."""
    rows = np.column_stack([points_um, 1e3 * np.asarray(traction_kPa)])  # kPa -> Pa
    body = "\n".join(",".join(f"{v:.10g}" for v in row) for row in rows)
    path.write_text(f"# {about}\n" + ",".join(COLUMNS) + "\n" + body + "\n")
    return path


class TractionField:
    """``T(X)`` [kPa] at reference points, linear in the polar angle between table rows."""

    def __init__(self, rows: NDArray, axisymmetric: bool) -> None:
        self.rows = rows
        self.period = None if axisymmetric else 360.0

    def __call__(self, X: NDArray) -> NDArray:
        theta = polar_deg(X)
        t, tx, ty = self.rows.T
        return np.array([np.interp(theta, t, c, period=self.period) for c in (tx, ty)])
