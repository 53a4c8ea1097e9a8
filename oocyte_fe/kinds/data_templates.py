"""What a kind's data-file inputs look like: columns and example rows for ``oocyte-fe new``.

Each constant is the ``json_schema_extra`` of a data-file input (see
:mod:`oocyte_fe.runner.scaffold`): the exact column names (units in the names) that the
input's reader expects, and one or two example rows, taken from the shipped case data (named)
or marked synthetic, so that the template ``oocyte-fe new`` writes is read without error.
"""

from __future__ import annotations

import math
from typing import Any

TABLE_II: dict[str, Any] = {
    "columns": ["displacement_um", "force_experiment_uN", "force_simulation_uN"],
    # the reader wants at least 3 rows (nmsd.tableII.MIN_ROWS), validate one per NMSD constant
    "example_rows": [
        [28.125, 3.45531, 3.46787],
        [41.25, 10.44089, 10.75634],
        [53.25, 13.48404, 13.38373],
        [62.375, 55.32843, 55.38837],
    ],
    "example_source": "seed 000 Table II (cases/nmsd_calibration_tableII); "
    "force_simulation_uN is optional",
}
"""Read by :func:`nmsd.tableII.read_force_displacement`."""

CREEP: dict[str, Any] = {
    "columns": ["time_s", "force_nN", "indentation_um"],
    # the reader wants at least 10 samples: 11, creeping as 2.2 + 0.7 (1 - exp(-t / 1.5 s)) um
    "example_rows": [
        [round(0.6 * i, 4), 5.0, round(2.2 + 0.7 * (1.0 - math.exp(-0.4 * i)), 4)]
        for i in range(11)
    ],
    "example_source": "SYNTHETIC (11 samples of a 5 nN clamp creeping from 2.2 um towards "
    "2.9 um, like cases/afm_creep_prony); a force column force_nN/pN/uN and indentation_um/nm, "
    "or a height column with metadata (afm.curve_io)",
}
"""Read by :func:`afm.curve_io.read_creep` (the creep-table form)."""

FLOW_CURVE: dict[str, Any] = {
    "columns": ["strain_rate_1_s", "viscosity_Pa_s"],
    # six rows, not two: a fit of carreau_yasuda's 5 parameters needs more points than that
    "example_rows": [
        [0.00172, 969.1],
        [0.00456, 467.8],
        [0.0107, 215.0],
        [0.021, 125.8],
        [0.0238, 102.8],
        [0.0524, 44.1],
    ],
    "example_source": "6 of the 11 rows of seed 001 Table 2 (cases/microchannel_carreau_fit); "
    "viscosity_<unit> "
    "takes the units of oocyte_fe.microchannel.units",
}
"""Read by :func:`oocyte_fe.microchannel.tables.read_flow_curve`."""

DEFORMATION: dict[str, Any] = {
    "columns": ["pressure_hPa", "ratio_experiment", "ratio_simulation"],
    "example_rows": [[600, 0.912, 0.934], [900, 0.908, 0.922]],
    "example_source": "seed 001 Table 4 (cases/microchannel_deformation); pressure_<unit> "
    "takes the units of oocyte_fe.microchannel.units",
}
"""Read by :func:`oocyte_fe.microchannel.tables.read_deformation_table`."""

KNOWN_MODULI: dict[str, Any] = {
    "columns": ["file", "E_kPa"],
    "example_rows": [["curves/zp/zp_01.csv", 4.72580727154525]],
    "example_source": "SYNTHETIC (cases/afm_fit_files/known_moduli.csv); file relative to "
    "the case folder",
}
"""Read by the ``afm_fit_files`` kind (``file``, ``E_kPa``)."""


def material_template(name: str, E_kPa: float, g: list[float], tau_s: list[float]) -> str:
    """A material file (format of :mod:`afm.material_file`) for a template."""
    return (
        "# oocyte-fe material file; units: kPa, s\n"
        f'[material]\nname = "{name}"\nsource = "example written by oocyte-fe new"\n'
        f"E_kPa = {E_kPa}\nnu = 0.5\n[prony]\ng = {g}\ntau_s = {tau_s}\n"
    )


ZONA_MATERIAL: dict[str, Any] = {
    "suffix": ".toml",
    "example_text": material_template("zona_pellucida", 7.01, [0.3, 0.2], [0.2, 1.5]),
    "example_source": "the synthetic ZP series of cases/afm_creep_prony (E0 = 7.01 kPa, seed 001)",
}
"""Read by :func:`oocyte_fe.fe.material.read_material_file`."""

CYTOPLASM_MATERIAL: dict[str, Any] = {
    "suffix": ".toml",
    "example_text": material_template("cytoplasm", 1.55, [], []),
    "example_source": "elastic, E = 1.55 kPa (seed 001 Table 1, as cases/afm_creep_prony)",
}
"""Read by :func:`oocyte_fe.fe.material.read_material_file`."""

FITTED_RHEOLOGY: dict[str, Any] = {
    "suffix": ".toml",
    "example_text": (
        "# oocyte-fe fitted rheology; units: Pa s, Pa s^n, s, 1/s\n"
        "# written by microchannel_carreau_fit; read by microchannel_flow (rheology_file)\n"
        '[data]\nfile = "table2_viscosity.csv"\n'
        "shear_rate_min_1_s = 0.00172\nshear_rate_max_1_s = 0.0524\n\n"
        "[carreau]\neta0_Pa_s = 1434.0\neta_inf_Pa_s = 1.368\ntime_constant_s = 661.3\n"
        "n = 0.04713\n\n"
        "[power_law]\nconsistency_Pa_s_n = 4.132\nn = 0.1319\n"
    ),
    "example_source": "the fluids of cases/microchannel_flow (Table 2's fits, seed 001, at its "
    "rates 0.00172-0.0524 1/s); a microchannel_carreau_fit run writes this file",
}
"""Read by :func:`oocyte_fe.kinds.microchannel_flow_inputs.read_fluids`."""

NMSD_CONSTANTS: dict[str, Any] = {
    "suffix": ".toml",
    "example_text": (
        "# oocyte-fe NMSD constants; units: nN, um, s\n"
        "[nmsd]\nk1_nN = 3.0\nk2_nN = 8000.0\ndl_c = 0.8\nd0_nN_s_per_um = 14.6\n"
        "d1_nN_s_per_um2 = 0.55\nnode_mass_nN_s2_per_um = 3.5038207453450298e-09\n"
        'damping = "nodal"\n\n'
        "[lattice]\ncell_diameter_um = 115.625\nspacings_across = 17\n"
    ),
    "example_source": "SYNTHETIC constants (k1 3 nN, k2 8000 nN, d0 14.6 nN s/um, d1 0.55 "
    "nN s/um^2, like docs/nmsd.md) on the default lattice (115.625 um, 17 spacings, dl_c 0.8); "
    "an nmsd_calibration run writes this file with its own constants",
}
"""Read by :func:`nmsd.constants_file.read_constants`."""


def _cone_curve(e_kpa: float, half_angle_deg: float, k_nn_per_um: float, contact_um: float) -> str:
    """A synthetic approach (piezo_um, force_nN) on a Sneddon cone, nu = 0.5: the force
    ``F = c d^2``, ``c = 2 E tan(alpha) / (pi (1 - nu^2))``, with the indentation ``d = z - z0
    - F / k`` (the cantilever's deflection taken off the piezo travel), 0 before contact."""
    c = 2.0 * e_kpa * math.tan(math.radians(half_angle_deg)) / (math.pi * 0.75)
    rows = [f"# spring_constant_N_per_m = {k_nn_per_um * 1e-3:g}", "piezo_um,force_nN"]
    for i in range(201):
        z = 0.03 * i
        travel = max(z - contact_um, 0.0)
        d = (-k_nn_per_um + math.sqrt(k_nn_per_um**2 + 4 * c * k_nn_per_um * travel)) / (2 * c)
        rows.append(f"{z:.2f},{c * d * d:.6g}")
    return "\n".join(rows) + "\n"


AFM_CURVES_FOLDER: dict[str, Any] = {
    "example_folder": {"example_cone_1.55kPa.csv": _cone_curve(1.55, 10.0, 70.0, 2.0)},
    "example_source": "SYNTHETIC, one approach on a 10 deg Sneddon cone into E = 1.55 kPa "
    "(nu = 0.5, contact at 2 um, k = 0.07 N/m: a cytoplasm of seed 001), exact, no noise",
}
"""The example of ``afm_fit_files``' folder input ``curves``."""
