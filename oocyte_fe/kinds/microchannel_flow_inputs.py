"""Inputs of the case kind ``microchannel_flow``: the channel, its pressures, the two fluids
(by hand or from a fitted-rheology file) and the FE meshes."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

from pydantic import Field, model_validator

from oocyte_fe.kinds.data_templates import FITTED_RHEOLOGY
from oocyte_fe.kinds.microchannel_input_rules import laminar_pressures
from oocyte_fe.kinds.microchannel_inputs import CarreauInputs, ChannelInputs
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.rheology_file import FittedRheology, read_rheology_file
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.runner.schema import CaseInputs, DataFile, DataReader, Increasing, RuleBroken, Setup

PositiveFloat = Annotated[float, Field(gt=0)]
CellCount = Annotated[int, Field(ge=2, le=400)]
HAND = ("carreau", "power_law_consistency_Pa_s_n", "power_law_n")
"""The fluids' inputs given by hand, when no ``rheology_file`` gives them."""


def read_fluids(path: Path) -> FittedRheology:
    """A fitted-rheology file holding the two fluids this kind flows: carreau, power_law."""
    fitted = read_rheology_file(path)
    for key in ("carreau", "power_law"):
        fitted.model(key, key)
    return fitted


class FlowInputs(CaseInputs):
    channel: ChannelInputs = Field(description="the channel and its medium")
    pressures_hPa: list[PositiveFloat] = Field(
        min_length=1,
        description="driving pressures (Table 4)",
        json_schema_extra={"unit": "hPa"},
    )
    rheology_file: Annotated[DataFile, DataReader(read_fluids)] | None = Field(
        default=None,
        description="fitted_rheology.toml of a microchannel_carreau_fit run (copied into the "
        "case folder): its carreau and power_law fits and the shear rates they were fitted "
        "at; none: carreau, power_law_* and shear_rate_range_1_s by hand",
        json_schema_extra=FITTED_RHEOLOGY,
    )
    carreau: CarreauInputs | None = Field(
        default=None,
        description="cytoplasm rheology for the non-Newtonian flows, a table [inputs.carreau] "
        "(eta0_Pa_s, eta_inf_Pa_s, time_constant_s, n); or give rheology_file",
    )
    power_law_consistency_Pa_s_n: float | None = Field(
        default=None,
        gt=0,
        description="consistency K for the closed-form power-law check (or rheology_file)",
        json_schema_extra={"unit": "Pa s^n"},
    )
    power_law_n: float | None = Field(
        default=None, gt=0, le=1.5, description="power-law index", json_schema_extra={"unit": "1"}
    )
    shear_rate_range_1_s: tuple[PositiveFloat, PositiveFloat] | None = Field(
        default=None,
        description="the shear rates the fluids' flow curve was measured at (lowest, highest); "
        "a fluid whose wall rate lies outside is withheld from the table of the fluids at each "
        "pressure (an extrapolation of its model); none: not known, shown and said so",
        json_schema_extra={"unit": "1/s"},
    )
    extrapolate: bool = Field(
        default=False,
        description="show the fluids' flow at wall rates outside shear_rate_range_1_s too, "
        "marked as extrapolated",
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

    @model_validator(mode="after")
    def _fluids_from_one_source(self) -> FlowInputs:
        """The fluids come from ``rheology_file`` or from the inputs by hand, never both; by
        hand, all three are given; the rate range is ordered."""
        given = [name for name in HAND if getattr(self, name) is not None]
        if self.rheology_file is not None:
            if self.shear_rate_range_1_s is not None:
                given.append("shear_rate_range_1_s")
            if given:
                raise RuleBroken(
                    given[0],
                    "not given with rheology_file (the file holds the fits and their rates)",
                    getattr(self, given[0]),
                )
        elif len(given) < len(HAND):
            missing = next(name for name in HAND if name not in given)
            raise RuleBroken(missing, "a value (or a rheology_file giving the fluids)")
        rates = self.shear_rate_range_1_s
        if rates is not None and not rates[0] < rates[1]:
            raise RuleBroken(
                "shear_rate_range_1_s", "the lowest rate first, below the highest", rates
            )
        return self

    def fluids(self, source: str) -> tuple[Rheology, Rheology, tuple[float, float] | None, str]:
        """(Carreau, power law, the fitted rates in 1/s or None, where they come from)."""
        if self.rheology_file is not None:
            fitted = read_fluids(self.rheology_file)
            where = f"{self.rheology_file.name} (fitted to {fitted.data or 'its flow curve'})"
            return (
                fitted.models["carreau"],
                fitted.models["power_law"],
                fitted.shear_rate_range,
                where,
            )
        assert self.carreau is not None and self.power_law_consistency_Pa_s_n is not None
        power = Rheology.of(
            "power_law",
            source=source,
            consistency=self.power_law_consistency_Pa_s_n * units.VISCOSITY["Pa_s"],
            n=self.power_law_n,
        )
        return self.carreau.to_internal(source), power, self.shear_rate_range_1_s, "case.toml"
