"""Case kind ``microchannel_carreau_fit``: viscosity models fitted to a flow curve (Table 2)."""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, field_validator, model_validator

from oocyte_fe.kinds.data_templates import FLOW_CURVE
from oocyte_fe.kinds.microchannel_input_rules import curve_fits
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.plotting import plot_viscosity_fits
from oocyte_fe.microchannel.rheology_fit import ViscosityFit, fit_viscosity
from oocyte_fe.microchannel.tables import read_flow_curve
from oocyte_fe.microchannel.viscosity import viscosity_models
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, DataFile, DataReader, Distinct

PA_S = units.VISCOSITY["Pa_s"]


PositivePaS = Annotated[float, Field(gt=0)]


class CarreauFitInputs(CaseInputs):
    data: Annotated[DataFile, DataReader(read_flow_curve)] = Field(
        description="CSV flow curve: strain_rate_1_s, viscosity_<unit> (Table 2)",
        json_schema_extra=FLOW_CURVE,
    )
    models: list[str] = Field(
        default=["carreau", "carreau_yasuda", "cross", "power_law"],
        min_length=1,
        description="viscosity models to fit (see oocyte-fe kinds)",
    )
    table3_zero_shear_Pa_s: dict[str, PositivePaS] = Field(
        default_factory=dict,
        description="readings of Table 3's zero-shear cell, per model",
        json_schema_extra={"unit": "Pa s"},
    )
    table3_infinite_shear_Pa_s: dict[str, PositivePaS] = Field(
        default_factory=dict,
        description="readings of Table 3's infinite-shear cell, per model",
        json_schema_extra={"unit": "Pa s"},
    )

    rules = (Distinct("models"),)

    @field_validator("models")
    @classmethod
    def _known(cls, value: list[str]) -> list[str]:
        known = viscosity_models()
        for key in value:
            if key not in known:
                raise ValueError(f"viscosity models among {', '.join(sorted(known))}")
        return value

    @model_validator(mode="after")
    def _fits(self) -> CarreauFitInputs:
        """The flow curve holds what each model's fit needs (as ``run`` checks it)."""
        curve_fits(self.data, "data", self.models)
        return self


METRICS = {
    "carreau_r2": "R^2 of the Carreau fit on the viscosity, 1",
    "carreau_r2_log": "R^2 of the Carreau fit on ln viscosity, 1",
    "carreau_rmse": "RMSE of the Carreau fit, kPa s",
    "carreau_eta0": "Carreau zero-shear viscosity, kPa s",
    "carreau_eta_inf": "Carreau infinite-shear viscosity, kPa s",
    "carreau_time_constant": "Carreau time constant, s",
    "carreau_n": "Carreau power-law index, 1",
    "best_r2": "highest R^2 among the fitted models, 1",
}


def _fmt(value: float, err: float) -> str:
    return f"{value:.4g} ± {err:.2g}" if np.isfinite(err) else f"{value:.4g} (not identified)"


def _parameter_table(fits: list[ViscosityFit]) -> str:
    rows = [
        "| model | parameter | value | unit | R² | R² (ln) | RMSE (Pa s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for fit in fits:
        for i, p in enumerate(fit.model.parameters):
            value, err, unit = fit.params[p.key], fit.stderr[p.key], p.unit
            if unit == "kPa s":  # shown in the paper's unit
                value, err, unit = value / PA_S, err / PA_S, "Pa s"
            stats = (
                f"{fit.r2:.5f} | {fit.r2_log:.4f} | {fit.rmse / PA_S:.3g}" if i == 0 else " | | "
            )
            rows.append(
                f"| {fit.model.name if i == 0 else ''} | {p.key} | {_fmt(value, err)} | {unit} "
                f"| {stats} |"
            )
    return "\n".join(rows)


def _table3(fits: list[ViscosityFit], inp: CarreauFitInputs) -> str:
    rows = ["| quantity | Table 3 reading | value (Pa s) |", "|---|---|---|"]
    for label, readings, key in (
        ("zero-shear viscosity", inp.table3_zero_shear_Pa_s, "eta0"),
        ("infinite-shear viscosity", inp.table3_infinite_shear_Pa_s, "eta_inf"),
    ):
        rows += [f"| {label} | {name} | {v:g} |" for name, v in readings.items()]
        for fit in fits:
            if key in fit.params:
                rows.append(
                    f"| {label} | fitted, {fit.model.name} | "
                    f"{_fmt(fit.params[key] / PA_S, fit.stderr[key] / PA_S)} |"
                )
    return "\n".join(rows)


@case_kind("microchannel_carreau_fit", inputs=CarreauFitInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fit viscosity models to a flow curve in log space; compare with Table 3's limits."""
    inp: CarreauFitInputs = ctx.inputs  # type: ignore[assignment]
    curve = read_flow_curve(inp.data)
    ctx.step(f"fitting {len(inp.models)} models to {curve.shear_rate.size} points")
    fits = [
        fit_viscosity(m, curve.shear_rate, curve.viscosity, source=str(inp.data))
        for m in inp.models
    ]
    figure = plot_viscosity_fits(
        curve.shear_rate, curve.viscosity, fits, ctx.output("viscosity_fit.png")
    )
    metrics: dict[str, float] = {"best_r2": max(f.r2 for f in fits)}
    carreau = next((f for f in fits if f.model.key == "carreau"), None)
    if carreau is not None:
        metrics |= {
            "carreau_r2": carreau.r2,
            "carreau_r2_log": carreau.r2_log,
            "carreau_rmse": carreau.rmse,
            **{f"carreau_{k}": v for k, v in carreau.params.items()},
        }
    unidentified = sorted({f"{f.model.key}.{k}" for f in fits for k in f.unidentified})
    notes = (
        "Residuals are ln(eta_model) - ln(eta_data): the viscosity spans 1.3 decades and its "
        "error grows with its size, so log residuals weight every point alike; positive "
        "parameters are fitted as logarithms (one scale for the solver, positivity for free). "
        "Errors are one standard error from the Jacobian at the optimum. "
        f"Not determined by these data: {', '.join(unidentified) or 'none'} "
        f"(the highest rate, {curve.shear_rate.max():g} 1/s, is far below any "
        "infinite-shear plateau)."
    )
    return CaseOutcome(
        metrics=metrics,
        figures=[Figure(figure.name, "Table 2 viscosity and the fitted models (log-log)")],
        sections=[
            ("Fitted parameters", _parameter_table(fits) + "\n\n" + notes),
            ("Beside Table 3's Carreau limits", _table3(fits, inp)),
        ],
    )
