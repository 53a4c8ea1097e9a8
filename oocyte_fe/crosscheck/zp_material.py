"""FE materials from the AFM chain: a ZP creep record -> Prony series -> :class:`Material`.

The ZP creep record (force clamp, CSV of :mod:`afm.curve_io`) is fitted by
:func:`afm.creep.material_from_creep_csv` (Lee-Radok cone compliance ``J(t)``, creep Prony
series, exact conversion to the relaxation series ``G(t)/G0 = 1 - sum g_i (1 - exp(-t/tau_i))``,
instantaneous modulus ``E0 = 2 (1 + nu) G0`` in kPa). The cytoplasm is elastic (seed 001,
Section 3.1: no prominent creep) with the AFM modulus ``E_cyto`` in kPa.
"""

from __future__ import annotations

from pathlib import Path

from afm.creep import material_from_creep_csv
from oocyte_fe.errors import InputError
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.fe.material import Material, Prony


def afm_layer_materials(
    creep_csv: str | Path,
    cytoplasm_E_kPa: float,
    nu: float = 0.5,
    half_angle_deg: float = 10.0,
) -> LayerMaterials:
    """ZP from the creep record (viscoelastic), cytoplasm elastic with ``cytoplasm_E_kPa``."""
    try:
        record = material_from_creep_csv(creep_csv, "zona_pellucida", half_angle_deg, nu)
    except InputError as exc:
        raise InputError(creep_csv, "creep record", str(exc)) from None
    prony = Prony(record.g, record.tau_s, source=str(creep_csv))
    zona = Material(record.E_kPa, nu, prony, name="zona", source=record.source)
    cytoplasm = Material(cytoplasm_E_kPa, nu, name="cytoplasm", source="AFM modulus, elastic")
    return LayerMaterials(zona, cytoplasm)
