"""An elastic cell in channel flow, one-way coupled, against the RT-DC look-up table.

The anchor for elastic cells in channel flow: real-time deformability cytometry (RT-DC). A
cell of radius ``a`` and Young's modulus ``E`` (incompressible neo-Hookean; linear in the
small-deformation limit) is carried through a channel by a flow ``Q`` of viscosity ``mu``.
One-way coupling: the Stokes flow past the undeformed, force-free cell
(:mod:`.sphere_in_tube`) gives the traction on its surface; the traction, written as the FE
experiment's traction table, loads the free cell (``support = "inertia_relief"``) in the FE
driver; the deformed outline gives the deformation ``d = 1 - circularity`` and the projected
area ``A`` (:func:`oocyte_fe.experiment.analysis.contour_deformation`).

The look-up table LE-2D-FEM-19 of ``dclab`` (Mokbel et al. 2017; fully coupled, linear elastic,
axisymmetric) maps ``(A, d)`` to ``E`` for a 20 um square channel at 0.04 uL/s and 15 mPa s,
modelled as a cylinder of the equivalent radius ``1.094 W / 2`` (Mietke et al. 2015, S3): our
reading is that channel radius with the same flow rate. In the small-deformation limit, where
the cell's deformation does not change the flow, the one-way answer should meet it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import contour_deformation
from oocyte_fe.experiment.driver import ExperimentResult
from oocyte_fe.experiment.loads import write_traction_table
from oocyte_fe.microchannel.sphere_in_tube import FlowPastCell, SphereInTube, flow_past_cell

EQUIVALENT_RADIUS = 1.094
"""Radius of the cylinder equivalent to a square channel, in half-widths (Mietke 2015, S3)."""


@dataclass(frozen=True)
class RtdcSetting:
    """The channel and the flow: width [um], flow rate [uL/s], viscosity [mPa s] (the LUT's
    own setting by default)."""

    channel_width_um: float = 20.0
    flow_rate_uL_s: float = 0.04
    viscosity_mPa_s: float = 15.0

    def __post_init__(self) -> None:
        for name in ("channel_width_um", "flow_rate_uL_s", "viscosity_mPa_s"):
            checks.positive("RtdcSetting", name, getattr(self, name))

    @property
    def channel_radius_um(self) -> float:
        return EQUIVALENT_RADIUS * self.channel_width_um / 2.0

    @property
    def flow_rate_um3_s(self) -> float:
        return self.flow_rate_uL_s * 1e9  # uL -> um^3

    @property
    def viscosity_kPa_s(self) -> float:
        return self.viscosity_mPa_s * 1e-6  # mPa s -> kPa s


@dataclass(frozen=True)
class CellInChannel:
    """One cell: the flow, the FE experiment and what RT-DC would measure (deformation and
    projected area [um^2])."""

    flow: FlowPastCell
    experiment: ExperimentResult
    E_kPa: float
    deformation: float
    area_um2: float

    @property
    def radius_um(self) -> float:
        return self.flow.geometry.sphere_radius_um


def flow_in_channel(
    radius_um: float, setting: RtdcSetting = RtdcSetting(), size_um: float = 1.0
) -> FlowPastCell:
    """Stokes flow past the undeformed, force-free cell of ``radius_um`` in the channel."""
    R = setting.channel_radius_um
    if not (np.isfinite(radius_um) and 0 < radius_um < 0.95 * R):
        raise InputError("flow_in_channel", "radius_um", f"in (0, {0.95 * R:.3g}) um", radius_um)
    geom = SphereInTube(R, radius_um, 8 * R, size_um, size_um / 8)
    return flow_past_cell(geom, setting.viscosity_kPa_s, setting.flow_rate_um3_s)


def cell_in_channel(
    flow: FlowPastCell,
    E_kPa: float,
    folder: Path,
    setting: RtdcSetting = RtdcSetting(),
    mesh_fraction: float = 0.1,
) -> CellInChannel:
    """The FE cell of modulus ``E_kPa`` (elements ``mesh_fraction`` of its radius) loaded by
    ``flow``'s traction (a table written into ``folder``)."""
    a = flow.geometry.sphere_radius_um
    table = write_traction_table(
        Path(folder) / f"traction_a{a:g}um.csv",
        flow.points_um.T,
        flow.traction_kPa.T,
        "traction of the flow on the cell (x = r, y = z)",
    )
    exp = Experiment.model_validate(
        {
            "cell": {
                "outer_diameter_um": 2 * a,
                "mesh_size_um": mesh_fraction * a,
                "materials": {"cytoplasm": {"E_kPa": E_kPa, "nu": 0.5}},
            },
            "loads": {"flow": {"type": "traction", "table": str(table)}},
            "support": "inertia_relief",
            "time": {"duration_s": 1.0, "frames": 2},
        }
    )
    result = run_experiment(exp)
    deformation, area = contour_deformation(result)
    if not result.success:
        deformation = float("nan")
    return CellInChannel(flow, result, E_kPa, deformation, area)


def lut_moduli_kPa(cells: list[CellInChannel], setting: RtdcSetting) -> NDArray:
    """Young's moduli [kPa] that dclab's LE-2D-FEM-19 table gives for the cells' ``(A, d)``
    in ``setting`` (no pixelation correction; one interpolation for all); NaN outside the
    table or for a cell whose FE run did not finish."""
    import warnings

    from dclab.features.emodulus import get_emodulus

    with warnings.catch_warnings():  # outside the table: NaN, said by the caller
        warnings.simplefilter("ignore")
        return np.asarray(
            get_emodulus(
                deform=np.array([c.deformation for c in cells]),
                area_um=np.array([c.area_um2 for c in cells]),
                medium=setting.viscosity_mPa_s,
                channel_width=setting.channel_width_um,
                flow_rate=setting.flow_rate_uL_s,
                px_um=0.0,
                temperature=None,
                visc_model=None,
                lut_data="LE-2D-FEM-19",
            )
        )
