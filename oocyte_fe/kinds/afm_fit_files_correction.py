"""The ``correction`` option of ``afm_fit_files``: the inputs turned into an
:mod:`afm.corrections` option (checked against the tip, nu and the fit range), the corrected
columns of ``fits.csv`` and the report's words on what was applied."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING

from afm.corrected_batch import BondedLayer, Correction, ShelledOocyte
from afm.fit_files import FitFilesResult
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_fit_files_args import tip_geometry

if TYPE_CHECKING:  # the inputs module checks a case with correction()
    from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs

CORRECTION_COLUMNS = {
    "E_corrected_kPa": "the modulus corrected for the sample's shape (option correction), kPa",
    "correction": "the correction applied, or why the curve's modulus could not be corrected",
}


def correction(inp: FitFilesInputs, where: Path) -> Correction | None:
    """The correction of ``inp.correction``, refused (:class:`InputError`) where it does not
    apply: another tip, nu other than 0.5, nanite's analysis or no ``max_indentation_um``, a
    ZP as thick as the cell's radius, a depth, probe or cell outside the table or the
    formula's range."""
    spec = inp.correction
    if spec is None:
        return None
    if inp.analysis != "default":
        raise InputError(where, "inputs.analysis", '"default" with a correction (a fit range)')
    option: Correction
    if spec.type == "shelled_oocyte":
        h, radius = spec.zona_thickness_um, spec.cell_radius_um
        if h >= radius:
            raise InputError(
                where,
                "inputs.correction.zona_thickness_um",
                f"a ZP thinner than the cell's radius (zona_thickness_um < cell_radius_um = "
                f"{radius:g} um)",
                h,
            )
        option = ShelledOocyte(h, spec.cytoplasm_modulus_kPa, radius)
    else:
        option = BondedLayer(spec.layer_thickness_um, spec.type)
    geometry = tip_geometry(inp, where)
    option.check(
        inp.model, geometry, inp.nu, inp.max_indentation_um, str(where), "inputs.correction"
    )
    return option


def add_correction_columns(path: Path, result: FitFilesResult) -> None:
    """``E_corrected_kPa`` and ``correction`` beside ``E_kPa`` in ``fits.csv`` (row by row)."""
    if result.correction is None or result.corrected is None:
        return
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    header = list(rows[0]) if rows else []
    at = header.index("E_kPa") + 1 if "E_kPa" in header else len(header)
    header[at:at] = list(CORRECTION_COLUMNS)
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, header)
        writer.writeheader()
        for row, value in zip(rows, result.corrected, strict=True):
            values = {"E_corrected_kPa": "", "correction": value}
            if isinstance(value, float):
                values = {"E_corrected_kPa": f"{value:.6g}", "correction": result.correction.name}
            writer.writerow(row | values)


def correction_text(result: FitFilesResult) -> str:
    """What the report says of the correction applied (moduli per group are corrected)."""
    c = result.correction
    if c is None:
        return "none: the moduli are those of the half-space model fitted"
    refused = sum(1 for v in result.corrected or () if isinstance(v, str) and v)
    return (
        f"{c.text}. The group means, SDs and material files use the corrected moduli; "
        f"`fits.csv` has the apparent (`E_kPa`) and corrected (`E_corrected_kPa`) modulus of "
        f"every curve; {refused} fitted curves could not be corrected (the reason in the "
        "`correction` column). docs/afm.md, 'Moduli corrected for the sample's shape'."
    )
