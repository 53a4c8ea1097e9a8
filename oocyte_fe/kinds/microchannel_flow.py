"""Case kind ``microchannel_flow``: Reynolds operating points, exact and FE channel flow."""

from __future__ import annotations

import math

import numpy as np

from oocyte_fe.kinds.microchannel_flow_inputs import FlowInputs
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

PA_PER_M = 1e-9  # 1 Pa/m = 1e-3 kPa / 1e6 um


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
    "(G = Dp / L), um/s; NaN where its wall rate lies outside the measured rates",
    "power_law_mean_velocity_ref": "mean velocity of the power-law fluid at the reference "
    "pressure (G = Dp / L), um/s; NaN where its wall rate lies outside the measured rates",
}


def _fluid_table(
    channel: Channel,
    fluids: dict[str, Rheology],
    pressures: np.ndarray,
    rates: tuple[float, float] | None,
    extrapolate: bool,
    where: str,
) -> str:
    """Flow rate Q (nL/s), mean velocity U = Q / (pi R^2) (mm/s) and wall shear rate (1/s) of
    each fluid in the channel at each pressure, with ``G = Dp / L`` (Rabinowitsch-Mooney);
    Q and U withheld where the wall rate lies outside ``rates`` (unless ``extrapolate``)."""
    hpa = units.PRESSURE["hPa"]
    head = " | ".join(f"{f}: Q (nL/s) | {f}: U (mm/s) | {f}: wall rate (1/s)" for f in fluids)
    rows = [f"| pressure (hPa) | G (Pa/m) | {head} |", "|---" * (2 + 3 * len(fluids)) + "|"]
    outside = 0
    for p in pressures:
        g = float(channel.pressure_gradient(p))
        cells = []
        for rheology in fluids.values():
            flow = fully_developed_flow(rheology, "pipe", channel.radius, g)
            beyond = not _within(flow.wall_shear_rate, rates)
            outside += beyond
            if beyond and not extrapolate:
                cells += ["-", "-"]
            else:
                mark = "*" if beyond else ""
                cells += [
                    f"{flow.flow_rate * 1e-6:.4g}{mark}",
                    f"{flow.mean_velocity * 1e-3:.4g}{mark}",
                ]
            cells.append(f"{flow.wall_shear_rate:.3g}")
        rows.append(f"| {p / hpa:g} | {g / PA_PER_M:.4g} | {' | '.join(cells)} |")
    text = (
        "\n\nEach fluid as if it filled the whole driven path: the pressure gradient "
        f"G = Dp / L with the effective hydraulic length L = {channel.hydraulic_length * 1e-3:.4g}"
        " mm calibrated by the medium, in the pipe of the channel's radius "
        f"{channel.radius:g} um; Q from Rabinowitsch-Mooney (exact for the fluid's flow curve), "
        f"U = Q / (pi R^2). The fluids from {where}. "
    )
    if rates is None:
        return (
            "\n".join(rows)
            + text
            + (
                "The rates their flow curve was measured at are not given (`shear_rate_range_1_s` "
                "or a `rheology_file`): no figure is checked against them, and a wall rate beyond "
                "them would be the model's extrapolation."
            )
        )
    span = f"{rates[0]:.3g}-{rates[1]:.3g} 1/s"
    if not outside:
        return "\n".join(rows) + text + f"Every wall rate lies within the measured {span}."
    if extrapolate:
        said = "marked * and shown, as asked (`extrapolate = true`): the model's extrapolation."
    else:
        said = (
            "withheld (-): a viscosity model fitted there says nothing about the flow at "
            "those rates (`extrapolate = true` shows the model's extrapolation, marked)."
        )
    return (
        "\n".join(rows)
        + text
        + (
            f"The flow curve was measured at {span}; {outside} of {len(pressures) * len(fluids)} "
            f"flows have a wall rate outside it, {said}"
        )
    )


def _within(rate: float, rates: tuple[float, float] | None) -> bool:
    """``rate`` (1/s) lies in the measured ``rates`` (to 1e-9 of each end), or none are known."""
    return rates is None or rates[0] * (1 - 1e-9) <= rate <= rates[1] * (1 + 1e-9)


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
    carreau, power, rates, where = inp.fluids(source)
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
    rm_newton, rm_power, profiles = 0.0, 0.0, {}
    for geometry in ("pipe", "slit"):
        size = channel.radius
        g_medium = channel.pressure_ref / channel.hydraulic_length
        exact = PoiseuilleFlow(geometry, size, g_medium, channel.viscosity)
        flow = fully_developed_flow(medium, geometry, size, g_medium)
        rm_newton = max(rm_newton, abs(flow.flow_rate / exact.flow_rate - 1.0))
        pl = fully_developed_flow(power, geometry, size, g)
        closed = power_law_flow_rate(
            geometry, size, pl.wall_shear_stress, power.params["consistency"], power.params["n"]
        )
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
    fluid_points = _fluid_table(channel, fluids, pressures, rates, inp.extrapolate, where)
    g_ref = float(channel.pressure_gradient(channel.pressure_ref))
    at_ref = {}
    for key, fluid in (("carreau", carreau), ("power_law", power)):
        flow = fully_developed_flow(fluid, "pipe", channel.radius, g_ref)
        shown = inp.extrapolate or _within(flow.wall_shear_rate, rates)
        at_ref[key] = flow.mean_velocity if shown else math.nan

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
