"""Input blocks shared by the ``microchannel_*`` case kinds (no kind is registered here).

Each field carries its unit in its name; :meth:`to_internal` converts to um, nN, kPa, s.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.channel import Channel
from oocyte_fe.microchannel.viscosity import Rheology


class ChannelInputs(BaseModel):
    """The device of seed 001, Section 2.4: circular channel, medium, measured Re."""

    model_config = ConfigDict(extra="forbid")
    diameter_um: float = Field(gt=0, description="channel diameter, um")
    density_kg_m3: float = Field(gt=0, description="medium density, kg/m^3")
    viscosity_Pa_s: float = Field(gt=0, description="medium viscosity, Pa s")
    reynolds_ref: float = Field(gt=0, lt=2000, description="Re measured at pressure_ref_hPa")
    pressure_ref_hPa: float = Field(gt=0, description="driving pressure of the Re measurement")

    def to_internal(self) -> Channel:
        return Channel(
            diameter=self.diameter_um,
            density=self.density_kg_m3 * units.DENSITY["kg_m3"],
            viscosity=self.viscosity_Pa_s * units.VISCOSITY["Pa_s"],
            reynolds_ref=self.reynolds_ref,
            pressure_ref=self.pressure_ref_hPa * units.PRESSURE["hPa"],
        )


class CarreauInputs(BaseModel):
    """Carreau parameters in the paper's units (Pa s, s)."""

    model_config = ConfigDict(extra="forbid")
    eta0_Pa_s: float = Field(gt=0, description="zero-shear viscosity, Pa s")
    eta_inf_Pa_s: float = Field(gt=0, description="infinite-shear viscosity, Pa s")
    time_constant_s: float = Field(gt=0, description="Carreau time constant, s")
    n: float = Field(gt=0, le=1.5, description="power-law index")

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
