"""Case kind ``rtdc_elastic_cell``: an elastic cell in channel flow against RT-DC's table.

Validate the channel, flow and cells; for each radius solve the Stokes flow past the force-free
cell once (:func:`oocyte_fe.microchannel.rtdc.flow_in_channel`), load the FE cell of each
modulus with its traction (:func:`~oocyte_fe.microchannel.rtdc.cell_in_channel`), and report
the modulus dclab's LE-2D-FEM-19 reads from the deformation and area against the one put in.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from oocyte_fe.microchannel.plotting import plot_rtdc_moduli
from oocyte_fe.microchannel.rtdc import (
    CellInChannel,
    RtdcSetting,
    cell_in_channel,
    flow_in_channel,
    lut_moduli_kPa,
)
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Distinct, Relation

METRICS = {
    "lut_ratio_min": "smallest E_table / E at each radius's largest modulus inside the table",
    "lut_ratio_max": "largest E_table / E at each radius's largest modulus inside the table",
    "force_balance_error": "largest |F_balance - F_reaction| / |F_reaction| of the unit flows",
    "traction_force_error": "largest |F_traction - F_reaction| / |F_reaction| of the unit flows",
    "speed_faxen_ratio": "cell speed / Faxen's U_max (1 - 2/3 (a/R)^2), smallest radius",
}


MAX_FLOW_TRIANGLES = 1e6
"""Largest flow mesh ``validate`` lets through: the shipped 1 um mesh has 6762 triangles (its
P2 Stokes solve takes seconds), 0.25 um 94 000 (8 s to mesh alone); 1e6 is 150 times the shipped
mesh, and 1e-4 um would need about 1e11."""


def _smallest_flow_size_um(channel_width_um: float) -> float:
    """The flow element size (um) of a mesh of :data:`MAX_FLOW_TRIANGLES` triangles: gmsh puts
    about 3.1 triangles per size^2 in the R x 16 R meridian plane (6762 at 1 um, R = 10.94 um)."""
    R = RtdcSetting(channel_width_um=channel_width_um).channel_radius_um
    return float(np.sqrt(50.0 * R**2 / MAX_FLOW_TRIANGLES))


class RtdcInputs(CaseInputs):
    channel_width_um: float = Field(
        20.0, gt=1, le=1000, description="square channel width", json_schema_extra={"unit": "um"}
    )
    flow_rate_uL_s: float = Field(
        0.04, gt=0, le=10, description="flow rate", json_schema_extra={"unit": "uL/s"}
    )
    viscosity_mPa_s: float = Field(
        15.0, gt=0.1, le=1e4, description="medium viscosity", json_schema_extra={"unit": "mPa s"}
    )
    radii_um: list[Annotated[float, Field(gt=0.5, le=500)]] = Field(
        min_length=1, description="cell radii", json_schema_extra={"unit": "um"}
    )
    moduli_kPa: list[Annotated[float, Field(ge=0.01, le=1e4)]] = Field(
        min_length=1, description="Young's moduli", json_schema_extra={"unit": "kPa"}
    )
    flow_size_um: float = Field(
        1.0, gt=0, le=10, description="flow element size", json_schema_extra={"unit": "um"}
    )
    mesh_fraction: float = Field(
        0.1,
        ge=0.02,
        le=0.5,
        description="cell element size / radius",
        json_schema_extra={"unit": "1"},
    )

    rules = (
        Distinct("radii_um"),
        Distinct("moduli_kPa"),
        Relation(
            "flow_size_um",
            ">=",
            lambda m: _smallest_flow_size_um(m.channel_width_um),
            "the size of a flow mesh of 1 million triangles (about 50 R^2 / flow_size_um^2 "
            "in the R x 16 R meridian plane, R the channel's equivalent radius)",
        ),
    )

    @model_validator(mode="after")
    def _fits(self) -> RtdcInputs:
        R = RtdcSetting(channel_width_um=self.channel_width_um).channel_radius_um
        if max(self.radii_um) >= 0.95 * R:
            raise ValueError(f"radii_um below 0.95 of the equivalent channel radius ({R:.3g} um)")
        if self.flow_size_um > min(self.radii_um) / 2:
            raise ValueError("flow_size_um at most half the smallest radius")
        return self


def _table(cells: list[CellInChannel], lut: dict[int, float]) -> str:
    rows = [
        "| a (um) | E (kPa) | U (mm/s) | deformation | area (um^2) | E_table (kPa) | E_table / E |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in cells:
        rows.append(
            f"| {c.radius_um:g} | {c.E_kPa:g} | {c.flow.speed_um_s * 1e-3:.4g} | "
            f"{c.deformation:.4g} | {c.area_um2:.4g} | {lut[id(c)]:.4g} | "
            f"{lut[id(c)] / c.E_kPa:.4f} |"
        )
    return "\n".join(rows)


@case_kind("rtdc_elastic_cell", inputs=RtdcInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """One-way coupled elastic cells in a channel against dclab's LE-2D-FEM-19."""
    inp: RtdcInputs = ctx.inputs  # type: ignore[assignment]
    setting = RtdcSetting(inp.channel_width_um, inp.flow_rate_uL_s, inp.viscosity_mPa_s)
    cells, flows = [], []
    for a in inp.radii_um:
        ctx.step(f"Stokes flow past the {a:g} um cell")
        flow = flow_in_channel(a, setting, inp.flow_size_um)
        flows.append(flow)
        for E in inp.moduli_kPa:
            ctx.step(f"FE cell a = {a:g} um, E = {E:g} kPa")
            cells.append(cell_in_channel(flow, E, ctx.output("."), setting, inp.mesh_fraction))
    ctx.step("reading the moduli from dclab's LE-2D-FEM-19")
    lut = dict(zip(map(id, cells), lut_moduli_kPa(cells, setting), strict=True))
    ratios = []
    for a in inp.radii_um:
        inside = [c for c in cells if c.radius_um == a and np.isfinite(lut[id(c)])]
        if inside:
            stiff = max(inside, key=lambda c: c.E_kPa)
            ratios.append(lut[id(stiff)] / stiff.E_kPa)
    balance = max(
        abs(f.force_balance_nN[k] / f.force_reaction_nN[k] - 1) for f in flows for k in (0, 1)
    )
    traction = max(
        abs(f.force_traction_nN[k] / f.force_reaction_nN[k] - 1) for f in flows for k in (0, 1)
    )
    small = flows[int(np.argmin(inp.radii_um))]
    R = setting.channel_radius_um
    metrics = {
        "lut_ratio_min": min(ratios) if ratios else float("nan"),
        "lut_ratio_max": max(ratios) if ratios else float("nan"),
        "force_balance_error": balance,
        "traction_force_error": traction,
        "speed_faxen_ratio": small.speed_um_s
        / (2 * small.mean_velocity_um_s * (1 - 2 / 3 * (min(inp.radii_um) / R) ** 2)),
    }
    rows = [(c.radius_um, c.E_kPa, c.deformation, lut[id(c)]) for c in cells]
    figure = plot_rtdc_moduli(rows, ctx.output("rtdc_moduli.png"))
    failed = [c for c in cells if not c.experiment.success]
    notes = (
        f"Channel: a cylinder of radius {setting.channel_radius_um:.4g} um (1.094 half-widths "
        f"of the {inp.channel_width_um:g} um square channel), {inp.flow_rate_uL_s:g} uL/s, "
        f"{inp.viscosity_mPa_s:g} mPa s. One-way coupling: the flow past the undeformed, "
        "force-free cell loads the free FE cell (incompressible neo-Hookean); E_table is "
        "what dclab's LE-2D-FEM-19 (fully coupled, linear elastic) reads from the FE's "
        "deformation and area (NaN: outside the table). The two should meet as the "
        "deformation vanishes."
        + (f" FE runs that did not finish: {len(failed)}." if failed else "")
    )
    return CaseOutcome(
        metrics=metrics,
        figures=[Figure(figure.name, "E read by the RT-DC table / E put in, against deformation")],
        sections=[("Cells in the channel", _table(cells, lut) + "\n\n" + notes)],
    )
