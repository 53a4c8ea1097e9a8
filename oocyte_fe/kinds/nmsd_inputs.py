"""Inputs of the NMSD case kinds (``nmsd_calibration``, ``nmsd_spindle_offset``), apart from
their runs: the press, calibration and spindle inputs and their checks at validation."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from nmsd.calibration import MODELS
from nmsd.constants_file import read_constants
from nmsd.pipette import (
    CONTACT_STIFFNESS_NN_PER_UM,
    HOLD_HALF_WIDTH_UM,
    TABLE_I_TIP_ANGLE_DEG,
    TABLE_I_WIDTH_UM,
)
from nmsd.tableII import read_force_displacement
from oocyte_fe.kinds.data_templates import NMSD_CONSTANTS, TABLE_II
from oocyte_fe.kinds.nmsd_checks import (
    LIBRARY_ARGS,
    approach_at_validation,
    approach_travel_um,
    data_extent_um,
    data_inside_cell,
    enough_points,
    press_at_validation,
    same_lattice,
)
from oocyte_fe.runner.schema import (
    CaseInputs,
    DataFile,
    DataReader,
    Distinct,
    Relation,
    Setup,
)

TableIIFile = Annotated[
    DataFile,
    DataReader(read_force_displacement),
    Field(
        description="force-displacement CSV: displacement_um, force_experiment_uN and optionally "
        "force_simulation_uN (also nm/mm/m and nN/mN/N; compression positive)",
        json_schema_extra=TABLE_II,
    ),
]
CellDiameter = Annotated[
    float,
    Field(
        gt=0, le=1e4, description="oocyte diameter (Table I R_c)", json_schema_extra={"unit": "um"}
    ),
]
SpacingsAcross = Annotated[
    int,
    Field(
        ge=2,
        le=101,
        description="grid spacings across the diameter",
        json_schema_extra={"unit": "1"},
    ),
]
PipetteWidth = Annotated[
    float,
    Field(
        gt=0,
        description="injection pipette width (Table I d_inj)",
        json_schema_extra={"unit": "um"},
    ),
]
TipAngle = Annotated[
    float,
    Field(
        ge=0,
        lt=180,
        description="injection pipette tip angle (Table I theta_inj)",
        json_schema_extra={"unit": "deg"},
    ),
]
HoldHalfWidth = Annotated[
    float,
    Field(gt=0, description="holding pipette mouth half-width", json_schema_extra={"unit": "um"}),
]
ContactStiffness = Annotated[
    float,
    Field(
        gt=0,
        description="penalty stiffness of the pipette contact",
        json_schema_extra={"unit": "nN/um"},
    ),
]
CriticalStrain = Annotated[
    float, Field(gt=0, description="critical link strain of eq 3", json_schema_extra={"unit": "1"})
]
Damping = Annotated[
    Literal["nodal", "link"],
    Field(description="eq 6 per node (as printed) or per link (Voigt, Fig. 3)"),
]
Speed = Annotated[
    float, Field(gt=0, le=1e6, description="pipette speed", json_schema_extra={"unit": "um/s"})
]
Travel = Annotated[
    float, Field(gt=0, description="pipette travel", json_schema_extra={"unit": "um"})
]
Steps = Annotated[
    int,
    Field(
        ge=1,
        le=100_000,
        description="backward-Euler steps over the travel",
        json_schema_extra={"unit": "1"},
    ),
]
Starts = Annotated[
    int, Field(ge=1, le=100, description="calibration starts", json_schema_extra={"unit": "1"})
]
Evaluations = Annotated[
    int,
    Field(
        ge=4,
        le=100_000,
        description="press simulations per calibration start",
        json_schema_extra={"unit": "1"},
    ),
]
"""The NMSD press inputs, declared once: :class:`PressInputs` and ``nmsd_vs_fe``'s
:class:`~oocyte_fe.kinds.crosscheck_inputs.CrosscheckInputs` (its names prefixed ``nmsd_``
where the FE has its own) use these, each with its own default."""


class PressInputs(CaseInputs):
    """Lattice, pipette and calibration settings shared by both kinds."""

    data: TableIIFile
    cell_diameter_um: CellDiameter = 115.625
    spacings_across: SpacingsAcross = 17
    pipette_width_um: PipetteWidth = TABLE_I_WIDTH_UM
    tip_angle_deg: TipAngle = TABLE_I_TIP_ANGLE_DEG
    hold_half_width_um: HoldHalfWidth = HOLD_HALF_WIDTH_UM
    contact_stiffness_nN_per_um: ContactStiffness = CONTACT_STIFFNESS_NN_PER_UM
    gap_um: float = Field(
        0.0,
        ge=0,
        description="pipette travel before touching the lattice",
        json_schema_extra={"unit": "um"},
    )
    dl_c: CriticalStrain = 0.8
    damping: Damping = "nodal"
    speed_um_s: Speed = 30.0
    travel_um: Travel = 65.0
    n_steps: Steps = 40
    symmetric: bool = Field(
        True,
        description="press on the mirror-symmetric branch (the free lattice buckles sideways "
        "from round-off; docs/nmsd.md); false: the free press",
    )
    calibrate_extra: list[Literal["dl_c", "gap_um"]] = Field(
        default_factory=list, description="also calibrate dl_c and/or the contact gap (bounded)"
    )
    n_starts: Starts = 2
    max_evaluations: Evaluations = 60

    rules = (
        Relation("pipette_width_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation(
            "hold_half_width_um", "<", lambda m: m.cell_diameter_um / 2, "cell_diameter_um / 2"
        ),
        Relation(
            "travel_um", "<", lambda m: m.cell_diameter_um - m.gap_um, "cell_diameter_um - gap_um"
        ),
        Setup(data_inside_cell),
        Relation(
            "travel_um",
            ">=",
            lambda m: data_extent_um(m.data),
            "the largest displacement_um of data (the press must reach every point it is "
            "fitted to)",
        ),
        Setup(press_at_validation, LIBRARY_ARGS),
        Distinct("calibrate_extra"),
        Setup(enough_points),
    )


class CalibrationInputs(PressInputs):
    models: list[Literal[MODELS]] = Field(  # type: ignore[valid-type]
        default_factory=lambda: list(MODELS),
        min_length=1,
        description=f"models calibrated, among {', '.join(MODELS)}",
    )
    rate_speeds_um_s: list[Annotated[float, Field(gt=0, le=1e6)]] = Field(
        default_factory=lambda: [10.0, 30.0, 90.0],
        description="pipette speeds of the rate check",
        json_schema_extra={"unit": "um/s"},
    )
    snapshot_um: list[Annotated[float, Field(ge=0)]] = Field(
        default_factory=lambda: [15.0, 30.0, 45.0],
        description="pipette displacements of the lattice snapshots",
        json_schema_extra={"unit": "um"},
    )

    rules = (
        *PressInputs.rules,
        Relation("snapshot_um", "<=", lambda m: m.travel_um, "travel_um", measure="max"),
        Distinct("models"),
        Distinct("rate_speeds_um_s"),
        Distinct("snapshot_um"),
    )


class SpindleInputs(PressInputs):
    constants_file: Annotated[DataFile, DataReader(read_constants)] | None = Field(
        default=None,
        description="nmsd_constants.toml of an nmsd_calibration run (copied into the case "
        "folder): its constants are used as they are (the data file is then only pressed "
        "once, to report their fit); none: calibrated on the data file",
        json_schema_extra=NMSD_CONSTANTS,
    )
    spindle_initial_um: tuple[float, float] = Field(
        (15.8718, 18.1392),
        description="spindle position (x, y) before the approach",
        json_schema_extra={"unit": "um"},
    )
    paper_offset_um: tuple[float, float] = Field(
        (25.6972, 49.127),
        description="the paper's predicted offset (x, y), for comparison",
        json_schema_extra={"unit": "um"},
    )
    approach_step_um: float = Field(
        0.5,
        gt=0,
        description="pipette displacement per simulated step of the approach",
        json_schema_extra={"unit": "um"},
    )
    kp: float = Field(
        0.2, ge=0, description="PID proportional gain", json_schema_extra={"unit": "1"}
    )
    ki: float = Field(0.3, ge=0, description="PID integral gain", json_schema_extra={"unit": "1"})
    kd: float = Field(0.0, ge=0, description="PID derivative gain", json_schema_extra={"unit": "1"})
    period_s: float = Field(
        0.01, ge=1e-4, description="controller period", json_schema_extra={"unit": "s"}
    )
    actuator_lag_s: float = Field(
        0.02, ge=0, description="first-order actuator lag", json_schema_extra={"unit": "s"}
    )
    resolution_um: float = Field(
        0.04, ge=0, description="positioning resolution", json_schema_extra={"unit": "um"}
    )
    removal_pipette_um: float = Field(
        20.0,
        gt=0,
        description="inner diameter of the removal pipette",
        json_schema_extra={"unit": "um"},
    )
    spindle_length_um: float = Field(
        10.0,
        ge=0,
        description="spindle extent aspirated with it",
        json_schema_extra={"unit": "um"},
    )

    rules = (
        *PressInputs.rules,
        Relation(
            "spindle_initial_um",
            "<",
            lambda m: m.cell_diameter_um,
            "cell_diameter_um (from the puncture point)",
            measure="norm",
        ),
        Relation("removal_pipette_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Relation("spindle_length_um", "<", lambda m: m.cell_diameter_um, "cell_diameter_um"),
        Setup(approach_at_validation, LIBRARY_ARGS),
        Relation(
            "approach_step_um",
            "<=",
            approach_travel_um,
            "the approach's travel (mouth clear of the lattice to spindle_initial_um)",
        ),
        Relation(
            "resolution_um",
            "<",
            lambda m: m.removal_pipette_um / 2,
            "removal_pipette_um / 2 (a coarser step can leave the spindle outside the bore)",
        ),
        Setup(same_lattice),
    )
