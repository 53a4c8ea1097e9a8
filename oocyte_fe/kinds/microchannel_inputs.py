"""Input blocks shared by the ``microchannel_*`` case kinds (no kind is registered here).

Each field carries its unit in its name; :meth:`to_internal` converts to um, nN, kPa, s.
"""

from __future__ import annotations

from pydantic import Field

from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.runner.schema import CaseInputs, Relation

ETA_INF_BELOW_ETA0 = Relation(
    "eta_inf_Pa_s",
    "<=",
    lambda m: m.eta0_Pa_s,
    "eta0_Pa_s (the infinite-shear plateau lies at or below the zero-shear one)",
)
"""A shear-thinning curve's plateaus: the rule of every Carreau-type viscosity block."""


class ChannelInputs(CaseInputs):
    """The device of seed 001, Section 2.4: circular channel, medium, measured Re."""

    diameter_um: float = Field(
        gt=0, description="channel diameter", json_schema_extra={"unit": "um"}
    )
    density_kg_m3: float = Field(
        gt=0, description="medium density", json_schema_extra={"unit": "kg/m^3"}
    )
    viscosity_Pa_s: float = Field(
        gt=0, description="medium viscosity", json_schema_extra={"unit": "Pa s"}
    )
    reynolds_ref: float = Field(
        gt=0,
        lt=2000,
        description="Reynolds number measured at pressure_ref_hPa",
        json_schema_extra={"unit": "1"},
    )
    pressure_ref_hPa: float = Field(
        gt=0,
        description="driving pressure of the Re measurement",
        json_schema_extra={"unit": "hPa"},
    )

    def to_internal(self) -> Channel:
        return Channel(
            diameter=self.diameter_um,
            density=self.density_kg_m3 * units.DENSITY["kg_m3"],
            viscosity=self.viscosity_Pa_s * units.VISCOSITY["Pa_s"],
            reynolds_ref=self.reynolds_ref,
            pressure_ref=self.pressure_ref_hPa * units.PRESSURE["hPa"],
        )


class CarreauInputs(CaseInputs):
    """Carreau parameters in the paper's units (Pa s, s)."""

    eta0_Pa_s: float = Field(
        gt=0, description="zero-shear viscosity", json_schema_extra={"unit": "Pa s"}
    )
    eta_inf_Pa_s: float = Field(
        gt=0, description="infinite-shear viscosity", json_schema_extra={"unit": "Pa s"}
    )
    time_constant_s: float = Field(
        gt=0, description="Carreau time constant", json_schema_extra={"unit": "s"}
    )
    n: float = Field(gt=0, le=1.5, description="power-law index", json_schema_extra={"unit": "1"})

    rules = (ETA_INF_BELOW_ETA0,)

    def to_internal(self, source: str) -> Rheology:
        pa_s = units.VISCOSITY["Pa_s"]
        return Rheology.of(
            "carreau",
            source=source,
            eta0=self.eta0_Pa_s * pa_s,
            eta_inf=self.eta_inf_Pa_s * pa_s,
            time_constant=self.time_constant_s,
            n=self.n,
        )
