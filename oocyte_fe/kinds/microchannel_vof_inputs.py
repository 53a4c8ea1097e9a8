"""Inputs of the case kind ``microchannel_vof`` (its schema, apart from its run and metrics)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import Field, PositiveFloat, PositiveInt, field_validator, model_validator

from oocyte_fe.errors import InputError
from oocyte_fe.kinds.data_templates import DEFORMATION, FLOW_CURVE
from oocyte_fe.kinds.microchannel_inputs import ChannelInputs
from oocyte_fe.kinds.microchannel_vof_parts import (
    CellPhaseInputs,
    GeometryInputs,
    IsoAdvectorInputs,
    _f,
)
from oocyte_fe.kinds.microchannel_vof_rules import (
    CAP_RULES,
    TRAVEL_RULES,
    against_data,
    cells_within,
    openfoam_dir,
    steps_within_runs,
)
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.tables import read_deformation_table, read_flow_curve
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.schema import CaseInputs, DataReader, Distinct, Refining, Relation, Setup

if TYPE_CHECKING:
    from oocyte_fe.microchannel.vof.band_traction import Fluids

PA_S = units.VISCOSITY["Pa_s"]
KG_M3 = units.DENSITY["kg_m3"]
HPA = units.PRESSURE["hPa"]


Model = Literal["liquid_cell_isoadvector", "three_phase_mules"]


class VofInputs(CaseInputs):
    deformation_data: Annotated[DataFile, DataReader(read_deformation_table)] = Field(
        description="CSV: pressure_<unit>, ratio_experiment, ratio_simulation (Table 4)",
        json_schema_extra=DEFORMATION,
    )
    viscosity_data: Annotated[DataFile, DataReader(read_flow_curve)] = Field(
        description="CSV flow curve (Table 2) for the Carreau lambda and n",
        json_schema_extra=FLOW_CURVE,
    )
    channel: ChannelInputs = Field(description="the device (calibrates U(p))")
    zp: CellPhaseInputs = Field(description="zona pellucida phase (Table 3)")
    cytoplasm: CellPhaseInputs = Field(description="cytoplasm phase (Table 3)")
    geometry: GeometryInputs = Field(
        default_factory=GeometryInputs, description="junction dimensions (defaults: the reading)"
    )
    model: Model = _f(
        "liquid_cell_isoadvector",
        "flow model: the cell as one liquid on interIsoFoam (isoAdvector), or medium, ZP and "
        "cytoplasm on multiphaseInterFoam (MULES, the seed's reading)",
        "name",
    )
    cell_curve: Literal["cytoplasm", "zp"] = _f(
        "cytoplasm", "liquid cell: whose Carreau curve and density the whole cell takes", "name"
    )
    isoadvector: IsoAdvectorInputs = Field(
        default_factory=IsoAdvectorInputs, description="interIsoFoam's alpha controls"
    )
    zp_bound: bool = _f(
        False, "liquid cell: one more run with the ZP's curve for the whole cell", "1"
    )
    recompute_passes: int = _f(
        0,
        "liquid cell: deform-recompute passes at most (at the first pressure, or at every one "
        "with recompute_pressures = 'all'), the flow run again past the AFM-elastic cell's "
        "deformed shape (0: one-way only)",
        "1",
        ge=0,
        le=20,
    )
    recompute_pressures: Literal["first", "all"] = _f(
        "first", "which pressures the deform-recompute passes run at", "name"
    )
    recompute_relaxation: float = _f(
        1.0,
        "the passes' under-relaxation: the next flow's cell shape takes this weight of the FE's "
        "outline and the rest of the last shape (1: the plain pass)",
        "1",
        gt=0,
        le=1,
    )
    recompute_load: Literal["dead", "follower"] = _f(
        "dead",
        "how the passes' FE cell takes the flow's traction: a dead load on the undeformed "
        "outline, or its normal part as a follower pressure on the deformed one",
        "name",
    )
    beside_model: Model | None = _f(
        None, "a second model run beside the first (reported, not the headline)", "name"
    )
    beside_pressures_hPa: list[float] = _f([], "pressures of the beside model", "hPa")
    beside_dx_um: float | None = _f(None, "cell size of the beside model (none: dx_um)", "um", gt=0)
    beside_correctors: int | None = _f(
        None, "pressure correctors of the beside model (none: correctors)", "1", ge=1
    )
    beside_dt_refinements: int = _f(
        0, "beside model: extra runs at dt/2, ... (its first pressure)", "1", ge=0, le=3
    )
    pressures_hPa: list[float] = _f(
        [300.0], "driving pressures run by the VOF", "hPa", min_length=1
    )
    zero_shear_cap_Pa_s: float = _f(46.0, "cap on both cell phases' eta0", "Pa s", gt=0)
    cap_sensitivity_Pa_s: float | None = _f(
        None, "second cap, run at the first pressure", "Pa s", gt=0
    )
    b_ratio: float = _f(1.0, "mean velocity of inlet B over that of inlet A", "1", gt=0)
    dx_um: float = _f(10.0, "cell size", "um", gt=0)
    mesh_check_dx_um: tuple[PositiveFloat, ...] = _f(
        (),
        "finer meshes run at the first pressure (at every pressure with mesh_check_pressures "
        "= 'all'; one number or a list, each finer than the one before; three meshes or "
        "more: the observed order and the h -> 0 limit)",
        "um",
    )
    mesh_check_correctors: tuple[PositiveInt, ...] = _f(
        (),
        "pressure correctors on the finer meshes: one count for all, or one per mesh "
        "(none: correctors)",
        "1",
    )
    mesh_check_pressures: Literal["first", "all"] = _f(
        "first",
        "which pressures run on the finer meshes: the first (a mesh study), or all of them "
        "(each pressure's h -> 0 limit and a Table 4 row of the limits; three meshes or more)",
        "name",
    )
    time_step_s: float = _f(1e-6, "time step (fixed) at the first pressure", "s", gt=0)
    time_step_scaling: Literal["fixed", "inverse_pressure"] = _f(
        "fixed",
        "fixed: time_step_s at every pressure; inverse_pressure: time_step_s x (first "
        "pressure / p), so that the Courant number is alike at every pressure (the cell's "
        "speed grows about in proportion to p)",
        "name",
    )
    max_time_step_s: float | None = _f(
        None,
        "largest step of any run (the scaled step grows at low pressure, and with it the "
        "viscous number nu dt / dx^2; none: no bound)",
        "s",
        gt=0,
    )
    dt_refinements: int = _f(
        0,
        "extra runs at dt/2, dt/4, ... (first pressure, dx_um); 2 or more: the dt -> 0 limit",
        "1",
        ge=0,
        le=3,
    )
    travel_um: float = _f(
        600.0, "run until the cell has moved this far at the mean velocity", "um", gt=0
    )
    writes: int = _f(20, "number of written times", "1", ge=2)
    outer_correctors: int = _f(1, "PIMPLE outer correctors", "1", ge=1)
    momentum_predictor: bool = _f(
        False,
        "liquid cell: solve the momentum equation before the pressure correctors (without it "
        "the viscous cell's momentum is not conserved; the three-phase model keeps none)",
        "1",
    )
    correctors: int = _f(3, "pressure correctors", "1", ge=1)
    pressure_rel_tol: float = _f(
        0.0, "GAMG relative tolerance of the correctors before the last", "1", ge=0, lt=1
    )
    ranks: int = _f(1, "MPI ranks per run (decomposePar + mpirun)", "1", ge=1)
    concurrent: int = _f(1, "runs at the same time (local Dask cluster of threads)", "1", ge=1)
    scheduler: str | None = _f(
        None,
        "Dask scheduler address (a cluster); none: a local cluster; the CLI's --scheduler wins",
        "address",
    )
    nice: int = _f(0, "niceness of the OpenFOAM processes", "1", ge=0, le=19)
    openfoam: str | None = _f(None, "OpenFOAM directory (else env var / WM_PROJECT_DIR)", "path")
    modulus_kPa: float = _f(1.55, "Kelvin-Voigt estimate: cell modulus (AFM)", "kPa", gt=0)
    kelvin_voigt_fit_hPa: list[float] = _f(
        [200.0, 500.0, 900.0],
        "Kelvin-Voigt estimate: pressures it is fitted on (two or three of the table's)",
        "hPa",
        min_length=2,
    )
    max_volume_error: float = _f(1e-3, "check: |phase volume change| of the cell phases", "1", gt=0)
    max_mesh_change_pct: float = _f(2.0, "check: ratio change between the two meshes", "%", gt=0)
    max_courant: float = _f(
        1.0, "check: largest Courant number of any run (an unstable episode)", "1", gt=0
    )

    rules = (
        Distinct("pressures_hPa"),
        Distinct("beside_pressures_hPa"),
        Distinct("kelvin_voigt_fit_hPa"),
        Relation("mesh_check_dx_um", "<", lambda m: m.dx_um, "dx_um", measure="max"),
        Refining("mesh_check_dx_um"),
        Setup(lambda m: m.mesh_checks),
        Setup(lambda m: m.all_pressures_need_three_meshes()),
        Setup(lambda m: m.lattices()),
        *TRAVEL_RULES,
        Setup(steps_within_runs),
        *CAP_RULES,
    )

    @field_validator("openfoam")
    @classmethod
    def _an_installation(cls, value: str | None) -> str | None:
        return openfoam_dir(value)

    @model_validator(mode="after")
    def _against_data(self) -> VofInputs:
        against_data(self)
        return self

    @field_validator("mesh_check_dx_um", "mesh_check_correctors", mode="before")
    @classmethod
    def _one_or_a_list(cls, value: Any) -> Any:
        return (value,) if isinstance(value, int | float) and not isinstance(value, bool) else value

    def time_step_at(self, pressure_hPa: float) -> float:
        """The fixed time step of the runs at ``pressure_hPa`` (s; ``time_step_scaling``, at
        most ``max_time_step_s``)."""
        step = self.time_step_s
        if self.time_step_scaling == "inverse_pressure":
            step *= self.pressures_hPa[0] / pressure_hPa
        return step if self.max_time_step_s is None else min(step, self.max_time_step_s)

    @property
    def mesh_checks(self) -> list[tuple[float, int]]:
        """The finer meshes (of the first pressure, or of every pressure with
        ``mesh_check_pressures = "all"``) and their pressure correctors."""
        n, meshes = self.mesh_check_correctors, self.mesh_check_dx_um
        if len(n) > 1 and len(n) != len(meshes):
            raise InputError(
                "inputs",
                "mesh_check_correctors",
                f"one count, or one per mesh of mesh_check_dx_um ({len(meshes)})",
                list(n),
            )
        counts = n if len(n) > 1 else (n[0] if n else self.correctors,) * len(meshes)
        return list(zip(meshes, counts, strict=True))

    def all_pressures_need_three_meshes(self) -> None:
        """``mesh_check_pressures = "all"`` fits each pressure's limit: three meshes at least."""
        if self.mesh_check_pressures == "all" and len(self.mesh_check_dx_um) < 2:
            raise InputError(
                "inputs",
                "mesh_check_dx_um",
                "two finer meshes or more with mesh_check_pressures = 'all' (three meshes "
                "give each pressure's order and h -> 0 limit)",
                list(self.mesh_check_dx_um),
            )

    def lattices(self) -> None:
        """Every mesh's lattice must fit the geometry (its lengths multiples of dx)."""
        geometry = self.geometry.to_geometry()
        for field, sizes in (
            ("dx_um", [self.dx_um]),
            ("mesh_check_dx_um", self.mesh_check_dx_um),
            (
                "beside_dx_um",
                [self.beside_dx_um] if self.beside_model and self.beside_dx_um else [],
            ),
        ):
            for dx in sizes:
                try:
                    layout = geometry.layout(dx, 1.0, 1.0)
                except InputError as exc:
                    raise InputError("inputs", field, exc.expected, dx) from None
                cells_within(field, dx, layout.n_cells)

    @property
    def fluids(self) -> Fluids:
        """The liquid cell's density (its ``cell_curve`` phase's), the medium's density and
        viscosity, in the internal units (the traction of :mod:`.vof.band_traction`)."""
        from oocyte_fe.microchannel.vof.band_traction import Fluids

        phase = self.cytoplasm if self.cell_curve == "cytoplasm" else self.zp
        return Fluids(
            phase.density_kg_m3 * KG_M3,
            self.channel.density_kg_m3 * KG_M3,
            self.channel.viscosity_Pa_s * PA_S,
        )
