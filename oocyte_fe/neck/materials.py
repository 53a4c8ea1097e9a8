"""The oocyte's materials through the AFM chain: the ``afm_creep_prony`` case is re-run into a
sub-folder of this case's results and its material files are read by the FE core.

The neck case names the AFM case folder (``material_case``); nothing is copied by hand, so a
change of the AFM inputs (creep record, Prony fit) reaches the FE model on the next run, and the
neck case runs on its own (it does not need the AFM case's earlier results).
"""

from __future__ import annotations

import logging
from pathlib import Path

from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.fe.material import read_material_file
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import CaseContext

ZP_FILE = "material_zp.toml"
CYTOPLASM_FILE = "material_cytoplasm.toml"


def materials_from_afm_case(
    case_dir: Path, out_dir: Path, log: logging.Logger, quick: bool = False
) -> LayerMaterials:
    """Run the AFM case in ``case_dir`` into ``out_dir`` and read its material files."""
    case = load_case(case_dir, quick=quick)
    out_dir.mkdir(parents=True, exist_ok=True)
    ctx = CaseContext(case.name, case.directory, out_dir, case.inputs, quick, log)
    case.kind.run(ctx)
    zp, cy = out_dir / ZP_FILE, out_dir / CYTOPLASM_FILE
    return LayerMaterials(read_material_file(zp), read_material_file(cy))
