"""The sub-tables of the ``afm_fit_files`` inputs: the calibration of a file pattern, the
viscoelastic ramp fit and the correction for the sample's shape (a table told apart by its
``type``). The inputs themselves: :mod:`~oocyte_fe.kinds.afm_fit_files_inputs`."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Discriminator, Field, Tag

from afm.ramp_files import RampOptions
from oocyte_fe.kinds.afm_fit_files_check import unused_options
from oocyte_fe.runner.schema import CaseInputs, Setup


class Calibration(CaseInputs):
    """Cantilever calibration for the files of one pattern (overrides the files' own)."""

    spring_constant_N_per_m: float | None = Field(
        None, gt=0, description="spring constant", json_schema_extra={"unit": "N/m"}
    )
    sensitivity_nm_per_V: float | None = Field(
        None,
        gt=0,
        description="deflection sensitivity (for deflection recorded in volts)",
        json_schema_extra={"unit": "nm/V"},
    )


class Viscoelastic(CaseInputs):
    """The viscoelastic fit of every ramp in time (Ting's method, afm.viscoelastic)."""

    rules = (Setup(unused_options),)

    relaxation: Literal["prony", "power_law", "sls"] = Field(
        "prony",
        description="relaxation modulus: Prony series, power law E0 (t/t0)^-beta, or the "
        "standard linear solid (sls)",
    )
    terms: int = Field(
        2,
        ge=1,
        le=4,
        description="exponential terms of the Prony series",
        json_schema_extra={"unit": "1"},
    )
    t0_s: float = Field(
        1.0, gt=0, description="reference time t0 of the power law", json_schema_extra={"unit": "s"}
    )
    use_retract: bool = Field(True, description="fit the retract too, where the file has one")
    joint_speeds: bool = Field(
        True,
        description="fit a group's curves together (one modulus; speeds a decade apart resolve "
        "both short and long times); the group's material comes from that fit",
    )

    def options(self) -> RampOptions:
        """The options of :func:`afm.ramp_files.fit_ramp_files`."""
        return RampOptions(
            self.relaxation, self.terms, self.t0_s, self.use_retract, self.joint_speeds
        )


class ShelledOocyteCorrection(CaseInputs):
    """E_ZP from each sphere fit through the FE table of afm.corrections (docs/afm.md)."""

    type: Literal["shelled_oocyte"]
    zona_thickness_um: float = Field(
        gt=0, le=1e3, description="ZP thickness h", json_schema_extra={"unit": "um"}
    )
    cytoplasm_modulus_kPa: float = Field(
        gt=0,
        le=1e6,
        description="the cytoplasm's Young's modulus",
        json_schema_extra={"unit": "kPa"},
    )
    cell_radius_um: float = Field(
        gt=0, le=1e4, description="the cell's outer radius R", json_schema_extra={"unit": "um"}
    )


class BondedLayerCorrection(CaseInputs):
    """A layer bonded to a rigid support: Dimitriadis et al. 2002 (sphere), Garcia and Garcia
    2018 (cone), nu = 0.5 (afm.bottom_effect)."""

    type: Literal["dimitriadis_bonded", "garcia_bonded"]
    layer_thickness_um: float = Field(
        gt=0, le=1e4, description="layer thickness h", json_schema_extra={"unit": "um"}
    )


def _correction_type(value: object) -> str | None:
    kind = value.get("type") if isinstance(value, dict) else getattr(value, "type", None)
    return {
        "shelled_oocyte": "shell",
        "dimitriadis_bonded": "bonded",
        "garcia_bonded": "bonded",
    }.get(kind)


CorrectionInputs = Annotated[
    Annotated[ShelledOocyteCorrection, Tag("shell")]
    | Annotated[BondedLayerCorrection, Tag("bonded")],
    Discriminator(
        _correction_type,
        custom_error_type="correction_type",
        custom_error_message="a table with type = shelled_oocyte, dimitriadis_bonded or "
        "garcia_bonded",
    ),
]
"""A correction table, told apart by its ``type``."""
