"""The fitted-rheology file (TOML): the viscosity models of a flow-curve fit and the shear
rates they were fitted at.

Written by the case kind ``microchannel_carreau_fit`` (``fitted_rheology.toml``), read by
``microchannel_flow`` (``rheology_file``), so a channel flow runs on the fit of a lab's own
rheometer data without copying numbers by hand. Format (units Pa s, s, 1/s)::

    # oocyte-fe fitted rheology; units: Pa s, Pa s^n, s, 1/s
    [data]
    file = "table2_viscosity.csv"   # the flow curve fitted
    shear_rate_min_1_s = 0.00052    # the rates it was measured at
    shear_rate_max_1_s = 0.052
    [carreau]                        # one table per fitted model
    eta0_Pa_s = 1434.0
    eta_inf_Pa_s = 1.368
    time_constant_s = 661.3
    n = 0.04713
    r2 = 0.9994

A model's parameters are named by their key and unit (``eta0_Pa_s``, ``consistency_Pa_s_n``,
``time_constant_s``, ``n``: the names of a case's ``[inputs.carreau]``). A viscosity model
says nothing about shear rates outside ``[shear_rate_min_1_s, shear_rate_max_1_s]``: a
flow whose wall rate lies there is the model's extrapolation.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import tomli_w

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.viscosity import Parameter, Rheology, viscosity_models

HEADER = (
    "# oocyte-fe fitted rheology; units: Pa s, Pa s^n, s, 1/s\n"
    "# written by microchannel_carreau_fit; read by microchannel_flow (rheology_file)\n"
)
FILE_UNITS = {"kPa s": ("Pa_s", units.VISCOSITY["Pa_s"]), "kPa s^n": ("Pa_s_n", 1e-3)}
"""Internal unit -> (the file's name suffix, internal value of 1 file unit): 1 Pa s^n =
1e-3 kPa s^n; seconds and pure numbers are written as they are."""


RATE = "shear_rate_per_s"


def file_name(p: Parameter) -> str:
    """The file's name of parameter ``p``: its key and unit (``eta0_Pa_s``, ``n``)."""
    if p.unit in FILE_UNITS:
        return f"{p.key}_{FILE_UNITS[p.unit][0]}"
    return p.key if p.unit == "1" else f"{p.key}_{p.unit}"


def _scale(p: Parameter) -> float:
    return FILE_UNITS[p.unit][1] if p.unit in FILE_UNITS else 1.0


@dataclass(frozen=True)
class FittedRheology:
    """The models of a fitted-rheology file (internal units) and the fitted rates (1/s)."""

    models: Mapping[str, Rheology]
    shear_rate_range: tuple[float, float]
    data: str
    file: str

    def model(self, key: str, field: str) -> Rheology:
        """The fitted ``key`` model; a file without it is an :class:`InputError` naming
        ``field`` of the case and the models the file has."""
        if key not in self.models:
            raise InputError(
                self.file,
                field,
                f"a [{key}] table (the file has {', '.join(sorted(self.models)) or 'none'}: "
                f"fit '{key}' in microchannel_carreau_fit's models)",
            )
        return self.models[key]


def rheology_toml(
    fits: Mapping[str, Rheology],
    r2: Mapping[str, float],
    data: str,
    shear_rate_range: tuple[float, float],
) -> str:
    """The file's text; floats at full precision, so reading it gives the fit exactly."""
    body: dict[str, dict[str, object]] = {
        "data": {
            "file": data,
            "shear_rate_min_1_s": float(shear_rate_range[0]),
            "shear_rate_max_1_s": float(shear_rate_range[1]),
        }
    }
    for key, rheology in fits.items():
        table: dict[str, object] = {
            file_name(p): float(rheology.params[p.key]) / _scale(p)
            for p in rheology.model.parameters
        }
        table["r2"] = float(r2[key])
        body[key] = table
    return HEADER + tomli_w.dumps(body)


def read_rheology_file(path: str | Path) -> FittedRheology:
    """Read and check a fitted-rheology file; every fault names the file and the field."""
    file = str(path)
    raw = checks.read_toml(path)
    data = checks.toml_table(
        file, raw, "data", {"file", "shear_rate_min_1_s", "shear_rate_max_1_s"}
    )
    lo = checks.quantity(file, "data.shear_rate_min_1_s", data.get("shear_rate_min_1_s"), RATE)
    hi = checks.quantity(file, "data.shear_rate_max_1_s", data.get("shear_rate_max_1_s"), RATE)
    if not lo < hi:
        raise InputError(file, "data.shear_rate_max_1_s", f"above shear_rate_min_1_s ({lo:g})", hi)
    known = viscosity_models()
    models: dict[str, Rheology] = {}
    for key, table in raw.items():
        if key == "data":
            continue
        if key not in known or not isinstance(table, dict):
            raise InputError(file, key, f"a model table among {', '.join(sorted(known))}")
        names = {file_name(p): p for p in known[key].parameters}
        unknown = sorted(set(table) - set(names) - {"r2"})
        if unknown:
            raise InputError(file, f"{key}.{unknown[0]}", f"one of {sorted(names)} or r2")
        params = {}
        for name, p in names.items():
            if name not in table:
                raise InputError(file, f"{key}.{name}", "this parameter (it is required)")
            value = checks.number(file, f"{key}.{name}", table[name], gt=0)
            params[p.key] = value * _scale(p)
        models[key] = Rheology.of(key, source=f"{file}: [{key}]", **params)
    return FittedRheology(models, (lo, hi), str(data.get("file", "")), file)
