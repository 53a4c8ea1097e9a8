"""Case kind ``enucleation_loop``: the closed loop of seed 000 (Sections II.C-D, III.C-D) on
virtual cells: video -> tracker -> NMSD prediction -> PID approach -> cytoplasm loss, against
aspirating at the spindle's initial position and at a fixed offset
(:mod:`oocyte_fe.tracking.enucleation`)."""

from __future__ import annotations

import dataclasses

import numpy as np
from pydantic import Field, model_validator

from nmsd.approach_pid import PidGains
from nmsd.calibration import calibrate
from nmsd.lattice import circular_lattice
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import press_setup
from nmsd.tableII import read_force_displacement
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.nmsd_checks import data_extent_um
from oocyte_fe.kinds.nmsd_inputs import TableIIFile
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Relation, RuleBroken
from oocyte_fe.tracking import enucleation as loop
from oocyte_fe.tracking.plots import plot_loop_distances
from oocyte_fe.tracking.synthetic import CELL_DIAMETER_UM, SequenceSpec

SEED = "seed 000, Section III.D"
TRAVEL_UM = 65.0
"""Travel of the calibration press (the paper's 65 um; Table II ends at 62.375 um)."""
BOX_UM = {f.name: f.default for f in dataclasses.fields(SequenceSpec)}["spindle_length_um"]
"""Spindle length in the video (um): a first box off by more misses the spindle."""


def _unit(unit: str) -> dict:
    return {"unit": unit}


class LoopInputs(CaseInputs):
    """Calibration, virtual cells, video and controller of the loop."""

    data: TableIIFile
    n_cells: int = Field(
        10, ge=1, le=1000, description="virtual cells", json_schema_extra=_unit("1")
    )
    spacings_across: int = Field(
        12, ge=4, description="NMSD grid spacings across the cell", json_schema_extra=_unit("1")
    )
    n_steps: int = Field(
        20, ge=4, description="calibration press steps", json_schema_extra=_unit("1")
    )
    n_starts: int = Field(1, ge=1, description="calibration starts", json_schema_extra=_unit("1"))
    max_evaluations: int = Field(
        12, ge=4, description="presses per calibration start", json_schema_extra=_unit("1")
    )
    dl_c: float = Field(
        0.8, gt=0, description="critical link strain (eq 3)", json_schema_extra=_unit("1")
    )
    param_spread: float = Field(
        0.25,
        ge=0,
        le=2.3,
        description="SD of log k1, k2, d0, d1 between cells (at most ln 10 = 2.3: one SD a "
        "factor of 10)",
        json_schema_extra=_unit("1"),
    )
    start_spread_um: float = Field(
        3.0,
        ge=0,
        description="spindle start spread around the seed's point",
        json_schema_extra=_unit("um"),
    )
    click_error_um: float = Field(
        1.0, ge=0, description="error of the operator's first box", json_schema_extra=_unit("um")
    )
    enter_frames: int = Field(
        80, ge=11, description="frames before the push (tracked)", json_schema_extra=_unit("frames")
    )
    approach_frames: int = Field(
        60, ge=1, description="frames of the push", json_schema_extra=_unit("frames")
    )
    contrast: float = Field(
        0.06, gt=0, description="spindle contrast / background", json_schema_extra=_unit("1")
    )
    n_occluders: int = Field(
        1, ge=0, description="droplets crossing the spindle", json_schema_extra=_unit("1")
    )
    light_drift: float = Field(
        0.3, ge=0, lt=1, description="illumination drift amplitude", json_schema_extra=_unit("1")
    )
    removal_pipette_um: float = Field(
        20.0, gt=0, description="removal pipette inner diameter", json_schema_extra=_unit("um")
    )
    spindle_length_um: float = Field(
        10.0, ge=0, description="spindle length aspirated with it", json_schema_extra=_unit("um")
    )
    kp: float = Field(0.2, ge=0, description="PID gain (eq 10)", json_schema_extra=_unit("1"))
    ki: float = Field(0.3, ge=0, description="PID gain (eq 10)", json_schema_extra=_unit("1"))

    rules = (
        Relation("removal_pipette_um", "<", lambda m: CELL_DIAMETER_UM, "the cell diameter"),
        Relation("spindle_length_um", "<", lambda m: CELL_DIAMETER_UM, "the cell diameter"),
        Relation("start_spread_um", "<", lambda m: CELL_DIAMETER_UM / 2, "the cell radius"),
        Relation(
            "click_error_um",
            "<",
            lambda m: BOX_UM,
            "the spindle's length in the video (a first box that still overlaps the spindle)",
        ),
    )

    @model_validator(mode="after")
    def _data_within_travel(self) -> LoopInputs:
        extent = data_extent_um(self.data)
        if extent > TRAVEL_UM:
            raise RuleBroken(
                "data",
                f"displacement_um at most the calibration press's travel {TRAVEL_UM:g} um",
                extent,
            )
        return self


METRICS = {
    **{f"distance_{m}_um": f"mean tip-to-spindle distance, {m}, um" for m in loop.METHODS},
    **{f"loss_{m}_pct": f"mean cytoplasm loss, {m}, %" for m in loop.METHODS},
    "distance_reduction_vs_initial_pct": "proposed vs initial-position distance, % lower",
    "distance_reduction_vs_offset_pct": "proposed vs fixed-offset distance, % lower",
    "tracking_error_um": "mean |tracked - true| spindle start, um",
    "prediction_shift_um": "mean shift of the predicted removal point due to tracking, um",
    "spindle_displacement_um": "mean true spindle displacement during the push, um",
}


def _run_cell(ctx: CaseContext, cell: loop.VirtualCell, *args: object) -> loop.CellOutcome:
    """:func:`loop.run_cell`; a tracked start outside the lattice (the tracker lost the
    spindle) names ``click_error_um``, a true start outside it ``start_spread_um``."""
    inp: LoopInputs = ctx.inputs  # type: ignore[assignment]
    try:
        return loop.run_cell(cell, *args, inp.click_error_um)  # type: ignore[arg-type]
    except InputError as exc:
        if exc.field != "spindle_initial_um":
            raise
        true = np.allclose(np.asarray(exc.got, dtype=float), cell.initial_um)
        raise InputError(
            ctx.case_dir / "case.toml",
            "inputs." + ("start_spread_um" if true else "click_error_um"),
            f"a spindle start inside the cell's lattice: in virtual cell {cell.seed} the "
            + ("true start" if true else "tracked start (the tracker lost the spindle)")
            + f" {exc.expected.removeprefix('a point ')}",
            got=exc.got,
        ) from None


@case_kind("enucleation_loop", inputs=LoopInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Video -> MFAKCF -> NMSD removal point -> PID -> loss, vs initial position / fixed offset."""
    inp: LoopInputs = ctx.inputs  # type: ignore[assignment]
    data = read_force_displacement(inp.data)  # read at validation: names file, column, row
    lattice = circular_lattice(CELL_DIAMETER_UM, inp.spacings_across)
    setup = press_setup(lattice, n_steps=inp.n_steps, travel_um=TRAVEL_UM)
    base = NmsdParameters(dl_c=inp.dl_c, node_mass=node_mass_for(CELL_DIAMETER_UM, lattice.n_nodes))
    ctx.step("calibrating on Table II")
    cal = calibrate(setup, data, "nmsd", base, inp.n_starts, max_evaluations=inp.max_evaluations)
    offset = loop.nominal_offset(lattice, cal.params)
    video = SequenceSpec(
        name="loop",
        seed=500,
        n_frames=inp.enter_frames + inp.approach_frames + 20,
        enter_frames=inp.enter_frames,
        approach_frames=inp.approach_frames,
        contrast=inp.contrast,
        n_occluders=inp.n_occluders,
        light_drift=inp.light_drift,
    )
    gains = PidGains(inp.kp, inp.ki)
    outcomes = []
    for cell in loop.virtual_cells(cal.params, inp.n_cells, inp.param_spread, inp.start_spread_um):
        ctx.step(f"cell {cell.seed}")
        outcomes.append(_run_cell(ctx, cell, lattice, cal.params, offset, video, gains))
    dist = {m: float(np.mean([o.distance(m) for o in outcomes])) for m in loop.METHODS}
    loss = {
        m: float(
            np.mean([loop.loss_pct(o.distance(m), inp.spindle_length_um, inp.removal_pipette_um)
                     for o in outcomes])
        )
        for m in loop.METHODS
    }  # fmt: skip
    red_init = 100 * (1 - dist["proposed"] / dist["initial_position"])
    red_off = 100 * (1 - dist["proposed"] / dist["fixed_offset"])
    metrics = {
        **{f"distance_{m}_um": v for m, v in dist.items()},
        **{f"loss_{m}_pct": v for m, v in loss.items()},
        "distance_reduction_vs_initial_pct": red_init,
        "distance_reduction_vs_offset_pct": red_off,
        "tracking_error_um": float(np.mean([o.tracking_error_um for o in outcomes])),
        "prediction_shift_um": float(np.mean([o.prediction_shift_um for o in outcomes])),
        "spindle_displacement_um": float(
            np.mean([np.linalg.norm(o.true_final - o.true_initial) for o in outcomes])
        ),
    }
    rows = "\n".join(
        f"| {i} | {o.tracking_error_um:.2f} | {o.prediction_shift_um:.2f} | "
        f"{np.linalg.norm(o.true_final - o.true_initial):.2f} | "
        + " | ".join(f"{o.distance(m):.2f}" for m in loop.METHODS)
        + " |"
        for i, o in enumerate(outcomes)
    )
    head = "| cell | tracking error | prediction shift | spindle moved | " + " | ".join(
        f"distance {m}" for m in loop.METHODS
    )
    checks = [
        Check("cytoplasm loss, proposed", loss["proposed"], loss["proposed"] < loss["fixed_offset"],
              "< fixed-offset method", 4.5, SEED + " (4.5 % vs 6.9 %)", "%"),
    ]  # fmt: skip
    plot_loop_distances(
        ctx.output("distances.png"), {m: [o.distance(m) for o in outcomes] for m in loop.METHODS}
    )
    return CaseOutcome(
        metrics=metrics,
        figures=[Figure("distances.png", "final tip-to-spindle distance per removal method")],
        sections=[
            ("Per cell (um)", head + " |\n|" + "---|" * (4 + len(loop.METHODS)) + "\n" + rows),
            ("Calibration used (Table II only)", str(cal.params)),
            (
                "Fixed offset (the nominal cell's predicted displacement), um",
                f"({offset[0]:.2f}, {offset[1]:.2f})",
            ),
        ],
        checks=checks,
    )
