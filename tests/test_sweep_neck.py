"""cases/sweep_neck_deformation --quick on a 2-worker local Dask cluster (about 1 min)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from oocyte_fe.runner.run import plan, run_cases

CASE = Path(__file__).resolve().parents[1] / "cases" / "sweep_neck_deformation"


@pytest.mark.slow
def test_neck_sweep_quick(tmp_path: Path) -> None:
    [result] = run_cases(plan([CASE], quick=True), tmp_path, quick=True, workers=2)
    assert result.status == "PASS", result.reason
    m = json.loads((tmp_path / CASE.name / "metrics.json").read_text())["metrics"]
    assert m["n_ok"] == 2 and m["n_failed"] == 0  # both samples: the ordering below needs them
    # geometry: in the 150 um neck the 180 um cell's equator moves in by (90 - 75) = 15 um,
    # less the penalty penetration (well under 1 um) -- whatever the moduli and friction
    assert m["radial_inward_max_um.mean"] == pytest.approx(15.0, abs=1.0)
    with (tmp_path / CASE.name / "samples.csv").open() as fh:
        rows = [r for r in csv.DictReader(fh) if r["status"] == "PASS"]
    # a stiffer ZP needs more suction to pass: the samples are ordered by E_ZP that way
    rows.sort(key=lambda r: float(r["input.zona_E_kPa"]))
    assert len(rows) == 2
    assert float(rows[0]["suction_needed_max_Pa"]) < float(rows[1]["suction_needed_max_Pa"])
