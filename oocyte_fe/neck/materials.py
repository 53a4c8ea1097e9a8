"""The oocyte's materials through the AFM chain: the ``afm_creep_prony`` case is re-run into a
sub-folder of this case's results and its material files are read by the FE core.

The neck case names the AFM case folder (``material_case``); nothing is copied by hand, so a
change of the AFM inputs (creep record, Prony fit) reaches the FE model on the next run, and the
neck case runs on its own (it does not need the AFM case's earlier results).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace
from pathlib import Path

from oocyte_fe.fe.material import Material, Prony, read_material_file
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import CaseContext

ZP_FILE = "material_zp.toml"
CYTOPLASM_FILE = "material_cytoplasm.toml"


@dataclass(frozen=True)
class OocyteMaterials:
    """ZP and cytoplasm as the FE core reads them, and the files they came from."""

    zona: Material
    cytoplasm: Material
    zona_file: Path
    cytoplasm_file: Path

    def with_moduli(
        self, zona_E_kPa: float | None = None, cytoplasm_E_kPa: float | None = None
    ) -> OocyteMaterials:
        """The same materials with the instantaneous moduli replaced where given (a sweep or a
        sensitivity over the AFM scatter); the Prony terms are kept."""
        zona = self.zona if zona_E_kPa is None else replace(self.zona, E_kPa=zona_E_kPa)
        cyto = (
            self.cytoplasm
            if cytoplasm_E_kPa is None
            else replace(self.cytoplasm, E_kPa=cytoplasm_E_kPa)
        )
        return replace(self, zona=zona, cytoplasm=cyto)

    def regions(self, viscoelastic: bool = True, zona_E_kPa: float | None = None) -> dict:
        """``{"zona": ..., "cytoplasm": ...}``; ``viscoelastic=False`` drops the Prony terms
        (instantaneous moduli kept), ``zona_E_kPa`` replaces the ZP's instantaneous modulus."""
        zona, cyto = self.zona, self.cytoplasm
        if zona_E_kPa is not None:
            zona = replace(zona, E_kPa=zona_E_kPa)
        if not viscoelastic:
            zona, cyto = replace(zona, prony=Prony()), replace(cyto, prony=Prony())
        return {"zona": zona, "cytoplasm": cyto}


def materials_from_afm_case(
    case_dir: Path, out_dir: Path, log: logging.Logger, quick: bool = False
) -> OocyteMaterials:
    """Run the AFM case in ``case_dir`` into ``out_dir`` and read its material files."""
    case = load_case(case_dir, quick=quick)
    out_dir.mkdir(parents=True, exist_ok=True)
    ctx = CaseContext(case.name, case.directory, out_dir, case.inputs, quick, log)
    case.kind.run(ctx)
    zp, cy = out_dir / ZP_FILE, out_dir / CYTOPLASM_FILE
    return OocyteMaterials(read_material_file(zp), read_material_file(cy), zp, cy)
