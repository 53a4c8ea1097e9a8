"""Case kind ``microchannel_carreau_fit``: viscosity models fitted to a flow curve (Table 2)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import Field, field_validator, model_validator

from oocyte_fe.kinds.data_templates import FLOW_CURVE
from oocyte_fe.kinds.microchannel_input_rules import curve_fits, eta_inf_below_curve
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.plotting import plot_viscosity_fits
from oocyte_fe.microchannel.rheology_file import rheology_toml
from oocyte_fe.microchannel.rheology_fit import ViscosityFit, fit_viscosity
from oocyte_fe.microchannel.tables import read_flow_curve
from oocyte_fe.microchannel.viscosity import ETA_INF, viscosity_models
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, DataFile, DataReader, Distinct

PA_S = units.VISCOSITY["Pa_s"]


PositivePaS = Annotated[float, Field(gt=0)]


class CarreauFitInputs(CaseInputs):
    data: Annotated[DataFile, DataReader(read_flow_curve)] = Field(
        description="CSV/TSV flow curve: strain_rate_1_s (or Shear Rate [1/s]), "
        "viscosity_<unit> (Pa_s, mPa_s, cP, kPa_s; or Viscosity [Pa s]); e.g. Table 2",
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
    fixed_eta_inf_Pa_s: float | None = Field(
        default=None,
        gt=0,
        description="infinite-shear viscosity kept fixed in the models that have one (data "
        "taken only at low rates cannot set it); none: fitted",
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

    def fixed(self, model: str) -> dict[str, float]:
        """The parameters ``model``'s fit keeps fixed (internal units)."""
        if self.fixed_eta_inf_Pa_s is None or ETA_INF.key not in viscosity_models()[model].keys:
            return {}
        return {ETA_INF.key: self.fixed_eta_inf_Pa_s * PA_S}

    @model_validator(mode="after")
    def _fits(self) -> CarreauFitInputs:
        """A fixed eta_inf lies below the flow curve, and the curve holds what each model's fit
        needs (as ``run`` checks it)."""
        curve = None
        if self.fixed_eta_inf_Pa_s is not None:
            curve = eta_inf_below_curve(self.data, "fixed_eta_inf_Pa_s", self.fixed_eta_inf_Pa_s)
        for model in self.models:
            curve_fits(self.data, "data", [model], self.fixed(model), curve)
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


SHOWN_IN_PA = {"kPa s": "Pa s", "kPa s^n": "Pa s^n"}
"""Internal viscosity units and the unit the report shows them in (1 kPa s^n = 1000 Pa s^n)."""


def _fmt(value: float, err: float, fixed: bool = False) -> str:
    if fixed:
        return f"{value:.4g} (fixed)"
    return f"{value:.4g} ± {err:.2g}" if np.isfinite(err) else f"{value:.4g} (not identified)"


def _parameter_table(fits: list[ViscosityFit]) -> str:
    rows = [
        "| model | parameter | value | unit | R² | R² (ln) | RMSE (Pa s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for fit in fits:
        for i, p in enumerate(fit.model.parameters):
            value, err, unit = fit.params[p.key], fit.stderr[p.key], p.unit
            if unit in SHOWN_IN_PA:  # every viscosity in Pa s, the unit of the papers' tables
                value, err, unit = value / PA_S, err / PA_S, SHOWN_IN_PA[unit]
            stats = (
                f"{fit.r2:.5f} | {fit.r2_log:.4f} | {fit.rmse / PA_S:.3g}" if i == 0 else " | | "
            )
            rows.append(
                f"| {fit.model.name if i == 0 else ''} | {p.key} "
                f"| {_fmt(value, err, p.key in fit.fixed)} | {unit} | {stats} |"
            )
    return "\n".join(rows)


def _notes(fits: list[ViscosityFit], shear_rate: np.ndarray, viscosity: np.ndarray) -> str:
    """The fit's method and what the data leave undetermined, from these data:
    ``log10(max eta / min eta)`` decades of viscosity, each unidentified parameter with its
    reason where it is known (at a bound of its range; eta_inf above the highest rate)."""
    decades = float(np.log10(viscosity.max() / viscosity.min()))
    unidentified = []
    for fit in fits:
        for key in fit.unidentified:
            p = fit.model.parameter(key)
            label = f"{fit.model.key}.{key}"
            if key in fit.at_bound:
                bound = p.lower if fit.params[key] < np.sqrt(p.lower * p.upper) else p.upper
                unit = "" if p.unit == "1" else f" {p.unit}"
                label += f" (at the bound {bound:g}{unit} of its range)"
            unidentified.append(label)
    fixed = sorted(
        {f"{f.model.key}.{k} = {f.params[k] / PA_S:g} Pa s" for f in fits for k in f.fixed}
    )
    beyond = (
        f" eta_inf: the data, up to {shear_rate.max():g} 1/s, do not reach the infinite-shear "
        "plateau."
        if any(ETA_INF.key in f.unidentified for f in fits)
        else ""
    )
    return (
        f"Residuals are ln(eta_model) - ln(eta_data): the viscosity spans {decades:.3g} decades "
        "and its error grows with its size, so log residuals weight every point alike; positive "
        "parameters are fitted as logarithms (one scale for the solver, positivity for free). "
        "Errors are one standard error from the Jacobian at the optimum. "
        + (f"Fixed (not fitted): {', '.join(fixed)}. " if fixed else "")
        + "Not determined by these data (infinite error: a direction of the fit the data do "
        f"not see, or a bound of the parameter's range): {', '.join(unidentified) or 'none'}."
        + beyond
        + (
            " A model's other errors hold with its parameters at a bound kept there."
            if any(f.at_bound for f in fits)
            else ""
        )
    )


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
                    f"{_fmt(fit.params[key] / PA_S, fit.stderr[key] / PA_S, key in fit.fixed)} |"
                )
    return "\n".join(rows)


@case_kind("microchannel_carreau_fit", inputs=CarreauFitInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fit viscosity models to a flow curve in log space; compare with Table 3's limits."""
    inp: CarreauFitInputs = ctx.inputs  # type: ignore[assignment]
    curve = read_flow_curve(inp.data)
    ctx.step(f"fitting {len(inp.models)} models to {curve.shear_rate.size} points")
    fits = [
        fit_viscosity(
            m, curve.shear_rate, curve.viscosity, fixed=inp.fixed(m), source=str(inp.data)
        )
        for m in inp.models
    ]
    name = Path(inp.data).name
    figure = plot_viscosity_fits(
        curve.shear_rate, curve.viscosity, fits, ctx.output("viscosity_fit.png"), name
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
    sections = [
        (
            "Fitted parameters",
            _parameter_table(fits) + "\n\n" + _notes(fits, curve.shear_rate, curve.viscosity),
        )
    ]
    rates = (float(curve.shear_rate.min()), float(curve.shear_rate.max()))
    fitted = ctx.output("fitted_rheology.toml")
    fitted.write_text(
        rheology_toml(
            {f.model.key: f.rheology for f in fits}, {f.model.key: f.r2 for f in fits}, name, rates
        )
    )
    sections.append(
        (
            "Fitted rheology file",
            f"`{fitted.name}`: every fitted model's parameters (Pa s, s) and the rates of "
            f"{name} ({rates[0]:.3g}-{rates[1]:.3g} 1/s); a `microchannel_flow` case reads it "
            "as `rheology_file` (copied into its folder) and withholds the flow of a fluid "
            "whose wall shear rate lies outside those rates.",
        )
    )
    if inp.table3_zero_shear_Pa_s or inp.table3_infinite_shear_Pa_s:
        sections.append(("Beside Table 3's Carreau limits", _table3(fits, inp)))
    return CaseOutcome(
        metrics=metrics,
        figures=[Figure(figure.name, f"Viscosity of {name} and the fitted models (log-log)")],
        sections=sections,
    )
