"""The shared press scenario and the mapping between the NMSD lattice and the FE disc.

Both models live in the same cell-centred plane (um): x towards 3 o'clock, y towards
12 o'clock. The NMSD lattice fills the circle of diameter ``D = R_c`` = 115.625 um (Table I of
seed 000); the FE disc has the same outer diameter, a cytoplasm disc of diameter ``R_zp`` =
83.597 um and a zona pellucida (ZP) ring of thickness ``(R_c - R_zp) / 2`` = 16.01 um in between
(``R_zp``, printed as "zona pellucida length", read as the diameter inside the ZP). A material
point has the same reference coordinates in both models, so no further mapping is needed.

The pipette (flat mouth ``d_inj`` wide, flanks at the included angle ``theta_inj``) starts
touching the cell at 3 o'clock and moves along -x at ``speed``; the rim of the far side within
``hold_half_width`` of the x axis is held fixed (both models). The spindle is the material point
``(X, Y)`` of the paper's frame (origin at the puncture point on the outer rim at 3 o'clock,
X inwards), i.e. at ``(D/2 - X, Y)`` here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nmsd.pipette import HOLD_HALF_WIDTH_UM, TABLE_I_TIP_ANGLE_DEG, TABLE_I_WIDTH_UM
from oocyte_fe.checks import numeric_fields
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class PressScenario:
    """Geometry and motion shared by both models (um, s).

    ``cell_diameter_um``: outer diameter (lattice circle, FE outer surface).
    ``cytoplasm_diameter_um``: FE cytoplasm diameter (inside the ZP).
    ``pipette_width_um``, ``tip_angle_deg``: Table I pipette.
    ``speed_um_s``: pipette speed; ``hold_half_width_um``: held far-side rim, |y| <= this.
    ``spindle_paper_um``: spindle (X, Y) from the puncture point, X into the cell.
    """

    cell_diameter_um: float = 115.625
    cytoplasm_diameter_um: float = 83.597
    pipette_width_um: float = TABLE_I_WIDTH_UM
    tip_angle_deg: float = TABLE_I_TIP_ANGLE_DEG
    speed_um_s: float = 30.0
    hold_half_width_um: float = HOLD_HALF_WIDTH_UM
    spindle_paper_um: tuple[float, float] = (15.8718, 18.1392)
    source: str = "PressScenario"

    def __post_init__(self) -> None:
        numeric_fields(self, self.source)
        if not 0 < self.cytoplasm_diameter_um < self.cell_diameter_um:
            raise InputError(
                self.source,
                "cytoplasm_diameter_um",
                f"0 < cytoplasm diameter < cell diameter {self.cell_diameter_um:g} um",
                self.cytoplasm_diameter_um,
            )
        for name in ("pipette_width_um", "speed_um_s", "hold_half_width_um"):
            if not getattr(self, name) > 0:
                raise InputError(self.source, name, "> 0", getattr(self, name))
        if not 0 <= self.tip_angle_deg < 180:
            raise InputError(self.source, "tip_angle_deg", "in [0, 180) deg", self.tip_angle_deg)
        r = float(np.hypot(*self.spindle_world_um))
        if r >= self.radius_um:
            raise InputError(
                self.source, "spindle_paper_um", "a point inside the cell", self.spindle_paper_um
            )

    @property
    def radius_um(self) -> float:
        """Outer radius D/2, um."""
        return 0.5 * self.cell_diameter_um

    @property
    def zona_thickness_um(self) -> float:
        """ZP thickness (D - D_cytoplasm) / 2, um."""
        return 0.5 * (self.cell_diameter_um - self.cytoplasm_diameter_um)

    @property
    def spindle_world_um(self) -> np.ndarray:
        """Spindle reference position in the cell-centred plane, um."""
        x, y = self.spindle_paper_um
        return np.array([self.radius_um - x, y])


def interior_grid(radius_um: float, spacing_um: float, margin_um: float) -> np.ndarray:
    """Points (n, 2) of a square grid of ``spacing_um`` centred on the cell, within
    ``radius_um - margin_um`` of the centre (um): the comparison points of both models."""
    if not spacing_um > 0 or not 0 <= margin_um < radius_um:
        raise InputError("interior_grid", "spacing_um/margin_um", "spacing > 0, 0 <= margin < R")
    reach = radius_um - margin_um
    k = np.arange(-np.floor(reach / spacing_um), np.floor(reach / spacing_um) + 1) * spacing_um
    x, y = np.meshgrid(k, k)
    pts = np.column_stack([x.ravel(), y.ravel()])
    return pts[np.hypot(pts[:, 0], pts[:, 1]) <= reach]
