"""The NMSD constants file (TOML): a calibration's constants and the lattice they belong to.

Written by the case kind ``nmsd_calibration`` (``nmsd_constants.toml``), read by
``nmsd_spindle_offset`` (``constants_file``), so a spindle offset is predicted from constants
calibrated once, without calibrating again. Format (units nN, um, s)::

    # oocyte-fe NMSD constants; units: nN, um, s
    [nmsd]
    k1_nN = 3.0                      # linear link coefficient (eq 3)
    k2_nN = 8000.0                   # cubic link coefficient
    dl_c = 0.8                       # critical link strain (eqs 4-5)
    d0_nN_s_per_um = 14.6            # velocity damping (eq 6)
    d1_nN_s_per_um2 = 0.55           # displacement-velocity damping
    node_mass_nN_s2_per_um = 1.3e-9  # rho pi d^3 / 6 / nodes
    damping = "nodal"
    [lattice]                        # the constants hold on this lattice only
    cell_diameter_um = 100.0
    spacings_across = 17
    [calibration]
    data = "nmsd_force_displacement_tableII.csv"
    rmse_uN = 2.6

The spring and damper constants act per link or node of the lattice (eq 3-6), so they mean
nothing on another lattice: a case that reads the file must press the same cell diameter and
number of spacings.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import tomli_w

from nmsd.calibration import CONSTANTS, CalibrationResult, fit_metrics, model_forces
from nmsd.identifiability import identifiability
from nmsd.parameters import NmsdParameters
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement
from oocyte_fe import checks
from oocyte_fe.errors import InputError

HEADER = "# oocyte-fe NMSD constants; units: nN, um, s\n"
NAMES = {
    "k1": "k1_nN",
    "k2": "k2_nN",
    "dl_c": "dl_c",
    "d0": "d0_nN_s_per_um",
    "d1": "d1_nN_s_per_um2",
    "node_mass": "node_mass_nN_s2_per_um",
}
"""Constant -> its name in the file (the unit in the name)."""
OPTIONAL = ("area_stiffness", "zona_stiffness_ratio", "zona_inner_radius_um")
"""Constants written only where they differ from the paper's model (their defaults)."""


@dataclass(frozen=True)
class NmsdConstants:
    """The constants of a file, the lattice they hold on and where they were calibrated."""

    params: NmsdParameters
    cell_diameter_um: float
    spacings_across: int
    data: str
    rmse_uN: float
    file: str


def constants_toml(
    params: NmsdParameters,
    cell_diameter_um: float,
    spacings_across: int,
    data: str,
    rmse_uN: float,
) -> str:
    """The file's text; floats at full precision, so reading gives the constants exactly."""
    nmsd: dict[str, object] = {NAMES[k]: float(getattr(params, k)) for k in NAMES}
    nmsd["damping"] = params.damping
    default = NmsdParameters()
    nmsd |= {
        k: float(getattr(params, k)) for k in OPTIONAL if getattr(params, k) != getattr(default, k)
    }
    body = {
        "nmsd": nmsd,
        "lattice": {
            "cell_diameter_um": float(cell_diameter_um),
            "spacings_across": int(spacings_across),
        },
        "calibration": {"data": data, "rmse_uN": float(rmse_uN)},
    }
    return HEADER + tomli_w.dumps(body)


def read_constants(path: str | Path) -> NmsdConstants:
    """Read and check an NMSD constants file; every fault names the file and the field."""
    file = str(path)
    raw = checks.read_toml(path)
    unknown = sorted(set(raw) - {"nmsd", "lattice", "calibration"})
    if unknown:
        raise InputError(file, unknown[0], "only the tables [nmsd], [lattice], [calibration]")
    nmsd = checks.toml_table(file, raw, "nmsd", {*NAMES.values(), "damping", *OPTIONAL})
    values: dict[str, object] = {}
    for key, name in NAMES.items():
        if name not in nmsd:
            raise InputError(file, f"nmsd.{name}", "this constant (it is required)")
        values[key] = checks.number(file, f"nmsd.{name}", nmsd[name])
    values |= {k: checks.number(file, f"nmsd.{k}", nmsd[k]) for k in OPTIONAL if k in nmsd}
    damping = nmsd.get("damping", "nodal")
    params = NmsdParameters(**values, damping=damping, source=f"{file}: [nmsd]")
    lattice = checks.toml_table(file, raw, "lattice", {"cell_diameter_um", "spacings_across"})
    for name in ("cell_diameter_um", "spacings_across"):
        if name not in lattice:
            raise InputError(file, f"lattice.{name}", "this value (the constants' lattice)")
    diameter = checks.quantity(
        file, "lattice.cell_diameter_um", lattice["cell_diameter_um"], "length_um"
    )
    spacings = checks.integer(file, "lattice.spacings_across", lattice["spacings_across"], 2, 1000)
    calibration = checks.toml_table(file, raw, "calibration", {"data", "rmse_uN"}, False)
    rmse = calibration.get("rmse_uN")
    rmse = float("nan") if rmse is None else checks.number(file, "calibration.rmse_uN", rmse, ge=0)
    return NmsdConstants(
        params, diameter, spacings, str(calibration.get("data", "")), float(rmse), file
    )


def with_constants(
    setup: PressSetup, constants: NmsdConstants, data: ForceDisplacement
) -> CalibrationResult:
    """The file's constants as they are, pressed once on ``data`` to report their fit
    (RMSE, R^2, and how far ``data`` determines each constant, :mod:`nmsd.identifiability`);
    nothing is fitted (``evaluations`` 1)."""
    tic = time.perf_counter()
    force = model_forces(setup, constants.params, data)
    ident = identifiability([(setup, data)], constants.params, CONSTANTS["nmsd"])
    return CalibrationResult(
        model="nmsd",
        params=constants.params,
        metrics=fit_metrics(force, data.force_nN),
        force_nN=force,
        evaluations=1,
        seconds=time.perf_counter() - tic,
        success=True,
        message=f"constants read from {constants.file}, not fitted",
        identifiability=ident,
    )
