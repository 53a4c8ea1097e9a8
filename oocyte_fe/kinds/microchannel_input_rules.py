"""Rules between the inputs of the ``microchannel_*`` kinds and their data files, checked at
``validate`` with the readers ``run`` uses (no kind is registered here).

Each raises :class:`~oocyte_fe.runner.schema.RuleBroken` naming the input, so the message is
``case.toml: inputs.<field>: expected ...``. A data file that cannot be read is left alone here:
the data-file check of :func:`oocyte_fe.runner.casefile.load_case` names its own fault.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import TypeVar

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.channel import LAMINAR_LIMIT
from oocyte_fe.microchannel.rheology_fit import check_fit_data
from oocyte_fe.microchannel.tables import FlowCurve, read_deformation_table, read_flow_curve
from oocyte_fe.runner.schema import RuleBroken

HPA = units.PRESSURE["hPa"]
PA_S = units.VISCOSITY["Pa_s"]
T = TypeVar("T")


def _read(reader: Callable[[Path], T], path: Path) -> T | None:
    try:
        return reader(path)
    except InputError:
        return None  # the data-file check reports it, naming the file's own fault


def pressures_in_table(path: Path, field: str, pressures_hPa: Iterable[float]) -> None:
    """Every pressure of ``field`` is a row of the deformation table at ``path`` (the table the
    case compares its ratios with, or fits on)."""
    table = _read(read_deformation_table, path)
    if table is None:
        return
    listed = table.pressure / HPA
    for p in pressures_hPa:
        if not np.any(np.isclose(listed, p, rtol=1e-9, atol=1e-12)):
            raise RuleBroken(
                field,
                f"pressures among those of {path.name}, the table the case compares with "
                f"({', '.join(f'{v:g}' for v in listed)} hPa)",
                p,
            )


def eta_inf_below_curve(path: Path, field: str, eta_inf_Pa_s: float) -> FlowCurve | None:
    """The infinite-shear viscosity the Carreau fit of the flow curve at ``path`` keeps fixed
    lies below the curve's lowest viscosity: a shear-thinning Carreau curve never falls below
    its eta_inf, so a fit through data below it has no meaning (its load factor goes to 0).
    Returns the curve (``None`` if unreadable)."""
    curve = _read(read_flow_curve, path)
    if curve is not None:
        lowest = float(curve.viscosity.min()) / PA_S
        if eta_inf_Pa_s >= lowest:
            raise RuleBroken(
                field,
                f"an infinite-shear viscosity below the lowest viscosity of {path.name} "
                f"({lowest:g} Pa s: a shear-thinning Carreau curve never falls below eta_inf)",
                eta_inf_Pa_s,
            )
    return curve


def curve_fits(
    path: Path,
    field: str,
    models: Iterable[str],
    fixed: Mapping[str, float] | None = None,
    curve: FlowCurve | None = None,
) -> None:
    """The flow curve at ``path`` holds what a fit of each of ``models`` needs (the checks of
    :func:`~oocyte_fe.microchannel.rheology_fit.check_fit_data`: enough distinct shear rates for
    the free parameters, viscosities that vary); ``fixed`` in internal units."""
    curve = curve if curve is not None else _read(read_flow_curve, path)
    if curve is None:
        return
    for model in models:
        try:
            check_fit_data(model, curve.shear_rate, curve.viscosity, fixed=fixed, source=path.name)
        except InputError as exc:
            got = exc.got
            if exc.field == "viscosity" and isinstance(got, float):
                got = f"{got / PA_S:g} Pa s"  # the file's unit, not the internal kPa s
            raise RuleBroken(
                field,
                f"a flow curve {model} can be fitted to ({path.name}: {exc.field}: {exc.expected})",
                got,
            ) from None


def laminar_pressures(
    reynolds_ref: float, pressure_ref_hPa: float, field: str, pressures_hPa: Iterable[float]
) -> None:
    """Every pressure of ``field`` (hPa, as written) drives the channel below Re = 2000, where
    the calibration ``U = Dp R^2 / (8 mu L)`` (Poiseuille) holds: ``Re`` is proportional to the
    pressure, ``Re(p) = Re_ref p / p_ref`` (:class:`~oocyte_fe.microchannel.channel.Channel`),
    so the limit is ``p < 2000 p_ref / Re_ref``."""
    limit_hpa = LAMINAR_LIMIT * pressure_ref_hPa / reynolds_ref
    worst = max(pressures_hPa)
    if worst >= limit_hpa:
        raise InputError(
            "case.toml",
            field,
            f"pressures below {limit_hpa:.5g} hPa, where Re reaches {LAMINAR_LIMIT:g} (laminar "
            f"Poiseuille; Re = {reynolds_ref:g} at channel.pressure_ref_hPa = "
            f"{pressure_ref_hPa:g} hPa, Re proportional to the pressure)",
            f"{worst:g} hPa (Re {reynolds_ref * worst / pressure_ref_hPa:.5g})",
        )
