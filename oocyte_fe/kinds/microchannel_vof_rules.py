"""Cross-field rules of the ``microchannel_vof`` inputs that need more than a comparison: the
time step against each run's duration, the size of each mesh, the pressures and the flow curve
against the case's data files (read with the readers ``run`` uses).

The functions take the inputs (:class:`.microchannel_vof_inputs.VofInputs`) and raise
:class:`~oocyte_fe.errors.InputError` naming an input (for a ``Setup`` rule) or
:class:`~oocyte_fe.runner.schema.RuleBroken` (from a model validator).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from oocyte_fe.errors import InputError
from oocyte_fe.kinds.microchannel_input_rules import (
    PA_S,
    curve_fits,
    eta_inf_below_curve,
    pressures_in_table,
)
from oocyte_fe.microchannel import units
from oocyte_fe.runner.schema import Relation, RuleBroken

HPA = units.PRESSURE["hPa"]
MAX_CELLS = 2_000_000
"""Largest VOF mesh ``validate`` lets through (cells of the 2-D junction): the finest shipped
mesh, 3.125 um, has 64 000 cells; 2 million is 31 times that (a cell size of 0.56 um on the
default junction)."""
CENTRELINE = 1.5
"""The largest speed in the channel over its mean velocity (plane Poiseuille): no cell is
faster, so at ``travel_um`` below ``cell_offset_um / 1.5`` its centre never reaches x = 0."""


def run_pressures(m: Any) -> list[float]:
    """The pressures (hPa) the case runs the VOF at: its own and, with a beside model, those."""
    return list(m.pressures_hPa) + (list(m.beside_pressures_hPa) if m.beside_model else [])


def steps_within_runs(m: Any) -> None:
    """Each run's time step is shorter than the run: ``travel_um`` at the mean velocity U(p)."""
    channel = m.channel.to_internal()
    for p in run_pressures(m):
        end = m.travel_um / float(channel.mean_velocity(p * HPA))
        step = m.time_step_at(p)
        if step >= end:
            raise InputError(
                "inputs",
                "time_step_s",
                f"a time step shorter than the run at {p:g} hPa (travel_um / U = {end:.3g} s; "
                f"its step is {step:.3g} s)",
                m.time_step_s,
            )


def cells_within(field: str, dx: float, n_cells: int) -> None:
    """A mesh of ``n_cells`` (cell size ``dx`` um, input ``field``) of at most :data:`MAX_CELLS`."""
    if n_cells > MAX_CELLS:
        raise InputError(
            "inputs",
            field,
            f"a cell size giving at most {MAX_CELLS / 1e6:g} million cells (the junction on "
            f"{dx:g} um has {n_cells:.3g})",
            dx,
        )


BESIDE = ("beside_pressures_hPa", "beside_dx_um", "beside_correctors", "beside_dt_refinements")
"""The beside model's settings: each ignored without ``beside_model``."""


def beside_named(m: Any) -> None:
    """A beside model has its pressures, and its settings have a model (either alone was
    ignored without a word)."""
    given = [name for name in BESIDE if getattr(m, name)]
    if not m.beside_model and given:
        raise RuleBroken(
            given[0],
            "no beside_* input without a beside_model (it would be ignored): name the model "
            "or leave the input out",
            getattr(m, given[0]),
        )
    if m.beside_model and not m.beside_pressures_hPa:
        raise RuleBroken(
            "beside_pressures_hPa",
            f"at least one pressure for beside_model = {m.beside_model!r} (none: it never runs)",
            [],
        )


def against_data(m: Any) -> None:
    """The pressures run, compared and fitted are rows of ``deformation_data``; the cytoplasm's
    eta_inf (fixed in the Table 2 fit of lambda and n) lies below ``viscosity_data`` and the
    curve can be fitted."""
    beside_named(m)
    pressures_in_table(m.deformation_data, "pressures_hPa", m.pressures_hPa)
    if m.beside_model:
        pressures_in_table(m.deformation_data, "beside_pressures_hPa", m.beside_pressures_hPa)
    pressures_in_table(m.deformation_data, "kelvin_voigt_fit_hPa", m.kelvin_voigt_fit_hPa)
    if len(m.kelvin_voigt_fit_hPa) > 3:
        raise RuleBroken(
            "kelvin_voigt_fit_hPa",
            "two or three pressures (the Kelvin-Voigt estimate fits two parameters; the rest "
            "of the table is predicted)",
            m.kelvin_voigt_fit_hPa,
        )
    eta_inf = m.cytoplasm.eta_inf_Pa_s
    curve = eta_inf_below_curve(m.viscosity_data, "cytoplasm.eta_inf_Pa_s", eta_inf)
    curve_fits(m.viscosity_data, "viscosity_data", ["carreau"], {"eta_inf": eta_inf * PA_S}, curve)


TRAVEL_RULES = (
    Relation(
        "travel_um",
        ">",
        lambda m: m.geometry.cell_offset_um / 1.5,
        "geometry.cell_offset_um / 1.5 (below it the cell's centre does not reach the "
        "junction centre x = 0 even at the centreline speed 1.5 U)",
    ),
    Relation(
        "travel_um",
        "<=",
        lambda m: (
            m.geometry.cell_offset_um
            + m.geometry.downstream_length_um
            + m.geometry.cell_diameter_um / 2
        ),
        "geometry.cell_offset_um + downstream_length_um + cell_diameter_um / 2 (beyond it "
        "even at the mean velocity U the whole cell has left through outlet C)",
    ),
)
"""``travel_um`` brings the cell to the junction and not past the outlet."""

CAP_RULES = (
    Relation(
        "zero_shear_cap_Pa_s",
        ">",
        lambda m: max(m.zp.eta_inf_Pa_s, m.cytoplasm.eta_inf_Pa_s),
        "the largest eta_inf_Pa_s of zp and cytoplasm (a cap on eta0 lies above the "
        "infinite-shear plateau)",
    ),
    Relation(
        "cap_sensitivity_Pa_s",
        ">",
        lambda m: max(m.zp.eta_inf_Pa_s, m.cytoplasm.eta_inf_Pa_s),
        "the largest eta_inf_Pa_s of zp and cytoplasm (a cap on eta0 lies above the "
        "infinite-shear plateau)",
    ),
)
"""The caps on the cell phases' eta0 lie above their eta_inf (``cap_zero_shear`` refuses the
rest at run)."""


def openfoam_dir(value: str | None) -> str | None:
    """An ``openfoam`` input names an existing directory: else the run would quietly take
    another installation (the environment's or the system's), or none."""
    if value is not None and not Path(value).is_dir():
        raise ValueError(
            "an existing OpenFOAM directory (leave openfoam out to use $OOCYTE_FE_OPENFOAM, "
            "$WM_PROJECT_DIR or the system's; without any the case is SKIPPED)"
        )
    return value
