"""Case kind ``microchannel_flow``: Reynolds operating points, exact and FE channel flow."""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
from pydantic import Field

from oocyte_fe.kinds.microchannel_input_rules import laminar_pressures
from oocyte_fe.kinds.microchannel_inputs import CarreauInputs, ChannelInputs
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.duct_fe import radial_mesh, rectangle_mesh, solve_duct_flow
from oocyte_fe.microchannel.plotting import plot_convergence, plot_duct_velocity, plot_profiles
from oocyte_fe.microchannel.poiseuille import (
    PoiseuilleFlow,
    power_law_flow_rate,
    rectangular_duct_flow_rate,
)
from oocyte_fe.microchannel.rabinowitsch import fully_developed_flow
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Increasing, Setup

PA_PER_M = 1e-9  # 1 Pa/m = 1e-3 kPa / 1e6 um


PositiveFloat = Annotated[float, Field(gt=0)]
CellCount = Annotated[int, Field(ge=2, le=400)]


class FlowInputs(CaseInputs):
    channel: ChannelInputs = Field(description="the channel and its medium")
    pressures_hPa: list[PositiveFloat] = Field(
        min_length=1,
        description="driving pressures (Table 4)",
        json_schema_extra={"unit": "hPa"},
    )
    carreau: CarreauInputs = Field(description="cytoplasm rheology for the non-Newtonian flows")
    power_law_consistency_Pa_s_n: float = Field(
        gt=0,
        description="consistency K for the closed-form power-law check",
        json_schema_extra={"unit": "Pa s^n"},
    )
    power_law_n: float = Field(
        gt=0, le=1.5, description="power-law index", json_schema_extra={"unit": "1"}
    )
    pressure_gradient_Pa_m: float = Field(
        gt=0,
        description="pressure gradient G for the non-Newtonian flows",
        json_schema_extra={"unit": "Pa/m"},
    )
    duct_width_um: float = Field(
        gt=0, description="rectangular duct width", json_schema_extra={"unit": "um"}
    )
    duct_height_um: float = Field(
        gt=0, description="rectangular duct height", json_schema_extra={"unit": "um"}
    )
    rectangle_cells: list[CellCount] = Field(
        min_length=1,
        description="FE cells on the duct's short side, one mesh each",
        json_schema_extra={"unit": "1"},
    )
    radial_cells: list[CellCount] = Field(
        min_length=1,
        description="FE cells on the pipe radius, one mesh each",
        json_schema_extra={"unit": "1"},
    )
    continuation_steps: int = Field(
        default=4,
        ge=1,
        le=20,
        description="viscosity continuation steps of the non-Newtonian solve",
        json_schema_extra={"unit": "1"},
    )

    rules = (
        Increasing("rectangle_cells"),
        Increasing("radial_cells"),
        Setup(
            lambda m: laminar_pressures(
                m.channel.reynolds_ref, m.channel.pressure_ref_hPa, "pressures_hPa", m.pressures_hPa
            )
        ),
    )


METRICS = {
    "mean_velocity_ref": "mean velocity at the reference pressure from Re, um/s",
    "hydraulic_length": "effective Poiseuille length implied by Re at the reference, um",
    "reynolds_max": "Re at the highest driving pressure, 1",
    "wall_shear_rate_ref": "Newtonian wall shear rate at the reference pressure, 1/s",
    "rm_newtonian_error": "max relative error of Rabinowitsch-Mooney vs Poiseuille (pipe, slit), 1",
    "rm_power_law_error": "max relative error of Rabinowitsch-Mooney vs power-law closed form, 1",
    "fe_rectangle_error": "Newtonian rectangular duct: |Q_FE/Q_series - 1| on the finest mesh, 1",
    "fe_carreau_pipe_error": "Carreau pipe (axisymmetric FE): |Q_FE/Q_exact - 1|, finest mesh, 1",
    "fe_carreau_pipe_order": "observed convergence order of the Carreau pipe flow rate, 1",
    "carreau_wall_number": "Carreau number lambda * wall shear rate of the pipe test, 1",
    "carreau_mean_velocity_ref": "mean velocity of the Carreau fluid at the reference pressure "
    "(G = Dp / L), um/s",
    "power_law_mean_velocity_ref": "mean velocity of the power-law fluid at the reference "
    "pressure (G = Dp / L), um/s",
}


def _fluid_table(channel: Channel, fluids: dict[str, Rheology], pressures: np.ndarray) -> str:
    """Flow rate Q (nL/s), mean velocity U = Q / (pi R^2) (mm/s) and wall shear rate (1/s) of
    each fluid in the channel at each pressure, with ``G = Dp / L`` (Rabinowitsch-Mooney)."""
    hpa = units.PRESSURE["hPa"]
    head = " | ".join(f"{f}: Q (nL/s) | {f}: U (mm/s) | {f}: wall rate (1/s)" for f in fluids)
    rows = [f"| pressure (hPa) | G (Pa/m) | {head} |", "|---" * (2 + 3 * len(fluids)) + "|"]
    for p in pressures:
        g = float(channel.pressure_gradient(p))
        cells = []
        for rheology in fluids.values():
            flow = fully_developed_flow(rheology, "pipe", channel.radius, g)
            cells += [f"{flow.flow_rate * 1e-6:.4g}", f"{flow.mean_velocity * 1e-3:.4g}"]
            cells.append(f"{flow.wall_shear_rate:.3g}")
        rows.append(f"| {p / hpa:g} | {g / PA_PER_M:.4g} | {' | '.join(cells)} |")
    return "\n".join(rows) + (
        "\n\nEach fluid as if it filled the whole driven path: the pressure gradient "
        f"G = Dp / L with the effective hydraulic length L = {channel.hydraulic_length * 1e-3:.4g}"
        " mm calibrated by the medium, in the pipe of the channel's radius "
        f"{channel.radius:g} um; Q from Rabinowitsch-Mooney (exact for the fluid's flow curve), "
        "U = Q / (pi R^2). A wall rate beyond the rates a flow curve was measured at is its "
        "model's extrapolation."
    )


def _order(h: np.ndarray, err: np.ndarray) -> float:
    return float(np.polyfit(np.log(h[-2:]), np.log(err[-2:]), 1)[0]) if h.size > 1 else math.nan


@case_kind("microchannel_flow", inputs=FlowInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Channel operating points from Re; Newtonian/power-law/Carreau flow, exact and FE."""
    inp: FlowInputs = ctx.inputs  # type: ignore[assignment]
    source = str(ctx.case_dir / "case.toml")
    channel = inp.channel.to_internal()
    hpa = units.PRESSURE["hPa"]
    pressures = channel.check_pressures(
        np.array(inp.pressures_hPa) * hpa, source, "inputs.pressures_hPa"
    )
    carreau = inp.carreau.to_internal(source)
    medium = Rheology.of("newtonian", mu=channel.viscosity)
    g = inp.pressure_gradient_Pa_m * PA_PER_M

    ctx.step("operating points")
    rows = [
        "| pressure (hPa) | mean velocity (m/s) | Re | wall shear rate (1/s) | "
        "entrance length (mm) | laminar |",
        "|---|---|---|---|---|---|",
    ]
    for p in pressures:
        re = float(channel.reynolds(p))
        rows.append(
            f"| {p / hpa:g} | {float(channel.mean_velocity(p)) * 1e-6:.4g} | {re:.1f} | "
            f"{float(channel.wall_shear_rate(p)):.4g} | {0.06 * re * channel.diameter * 1e-3:.3g} "
            f"| {'yes' if re < 2000 else 'NO'} |"
        )
    operating = "\n".join(rows) + (
        f"\n\nEffective hydraulic length L = Dp R^2 / (8 mu U) = "
        f"{channel.hydraulic_length * 1e-3:.4g} mm (from Re = {channel.reynolds_ref:g} at "
        f"{channel.pressure_ref / hpa:g} hPa, U taken as the mean velocity)."
    )

    ctx.step("Rabinowitsch-Mooney against closed forms")
    k = inp.power_law_consistency_Pa_s_n * units.VISCOSITY["Pa_s"]
    power = Rheology.of("power_law", source=source, consistency=k, n=inp.power_law_n)
    rm_newton, rm_power, profiles = 0.0, 0.0, {}
    for geometry in ("pipe", "slit"):
        size = channel.radius
        g_medium = channel.pressure_ref / channel.hydraulic_length
        exact = PoiseuilleFlow(geometry, size, g_medium, channel.viscosity)
        flow = fully_developed_flow(medium, geometry, size, g_medium)
        rm_newton = max(rm_newton, abs(flow.flow_rate / exact.flow_rate - 1.0))
        pl = fully_developed_flow(power, geometry, size, g)
        closed = power_law_flow_rate(geometry, size, pl.wall_shear_stress, k, inp.power_law_n)
        rm_power = max(rm_power, abs(pl.flow_rate / closed - 1.0))
        x = np.linspace(0.0, size, 41)
        cflow = fully_developed_flow(carreau, geometry, size, g)
        profiles[f"{geometry}, Newtonian"] = (x / size, exact.velocity(x) / exact.mean_velocity)
        profiles[f"{geometry}, Carreau (exact)"] = (
            x / size,
            cflow.velocity(x) / cflow.mean_velocity,
        )

    ctx.step("the fluids at each pressure")
    fluids = {"Carreau": carreau, "power law": power}
    fluid_points = _fluid_table(channel, fluids, pressures)
    at_ref = {
        key: fully_developed_flow(
            fluid, "pipe", channel.radius, float(channel.pressure_gradient(channel.pressure_ref))
        ).mean_velocity
        for key, fluid in (("carreau", carreau), ("power_law", power))
    }

    ctx.step("FE: Newtonian rectangular duct")
    w, h = inp.duct_width_um, inp.duct_height_um
    g_rect = g
    q_series = rectangular_duct_flow_rate(w, h, g_rect, channel.viscosity)
    rect_err = []
    for cells in inp.rectangle_cells:
        fe = solve_duct_flow(rectangle_mesh(w, h, cells), medium, g_rect)
        rect_err.append(abs(fe.flow_rate / q_series - 1.0))

    ctx.step("FE: Carreau pipe (axisymmetric)")
    exact_pipe = fully_developed_flow(carreau, "pipe", channel.radius, g)
    pipe_err = []
    for cells in inp.radial_cells:
        fe_pipe = solve_duct_flow(
            radial_mesh(channel.radius, cells),
            carreau,
            g,
            axisymmetric=True,
            steps=inp.continuation_steps,
        )
        pipe_err.append(abs(fe_pipe.flow_rate / exact_pipe.flow_rate - 1.0))
    r = np.linspace(0.0, channel.radius, 9)
    profiles["pipe, Carreau (FE)"] = (
        r / channel.radius,
        fe_pipe.basis.interpolator(fe_pipe.u)(r[None, :]) / fe_pipe.mean_velocity,
    )

    ctx.step("FE: Carreau rectangular duct (field plot)")
    fe_rect = solve_duct_flow(
        rectangle_mesh(w, h, inp.rectangle_cells[-1]), carreau, g, steps=inp.continuation_steps
    )
    rect_h = np.array([1.0 / c for c in inp.rectangle_cells])
    pipe_h = np.array([1.0 / c for c in inp.radial_cells])
    figures = [
        Figure(
            plot_profiles(profiles, "r/R (pipe), y/h (slit)", ctx.output("profiles.png")).name,
            "Velocity profiles over their mean velocity: Newtonian medium and the Carreau "
            f"cytoplasm at G = {inp.pressure_gradient_Pa_m:g} Pa/m, exact and FE",
        ),
        Figure(
            plot_convergence(
                {
                    "Newtonian rectangle vs series": (rect_h, np.array(rect_err)),
                    "Carreau pipe vs Rabinowitsch-Mooney": (pipe_h, np.array(pipe_err)),
                },
                ctx.output("convergence.png"),
            ).name,
            "Mesh convergence of the FE flow rate (P2)",
        ),
        Figure(
            plot_duct_velocity(
                fe_rect,
                ctx.output("duct_velocity.png"),
                f"Carreau flow, {w:g} x {h:g} µm duct, Q = {fe_rect.flow_rate:.4g} µm³/s",
            ).name,
            "FE velocity of the Carreau fluid in the rectangular duct (pyvista, off-screen)",
        ),
    ]
    conv_rows = ["| mesh | cells | relative error |", "|---|---|---|"]
    conv_rows += [
        f"| rectangle (Newtonian) | {c} | {e:.3e} |"
        for c, e in zip(inp.rectangle_cells, rect_err, strict=True)
    ]
    conv_rows += [
        f"| pipe radius (Carreau) | {c} | {e:.3e} |"
        for c, e in zip(inp.radial_cells, pipe_err, strict=True)
    ]
    metrics = {
        "mean_velocity_ref": channel.velocity_ref,
        "hydraulic_length": channel.hydraulic_length,
        "reynolds_max": float(channel.reynolds(pressures.max())),
        "wall_shear_rate_ref": float(channel.wall_shear_rate(channel.pressure_ref)),
        "rm_newtonian_error": rm_newton,
        "rm_power_law_error": rm_power,
        "fe_rectangle_error": rect_err[-1],
        "fe_carreau_pipe_error": pipe_err[-1],
        "fe_carreau_pipe_order": _order(pipe_h, np.array(pipe_err)),
        "carreau_wall_number": carreau.params["time_constant"] * exact_pipe.wall_shear_rate,
        **{f"{key}_mean_velocity_ref": u for key, u in at_ref.items()},
    }
    return CaseOutcome(
        metrics=metrics,
        figures=figures,
        sections=[
            ("Operating points (Poiseuille, calibrated by Re at the reference)", operating),
            ("The Carreau and power-law fluids at each pressure", fluid_points),
            ("FE mesh convergence", "\n".join(conv_rows)),
        ],
    )
