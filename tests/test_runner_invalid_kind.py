"""A case that fails validation is reported as ERROR with the kind its ``case.toml`` names
(an outside tester: the report and the summary said "Kind `?`" for a valid kind)."""

from __future__ import annotations

from pathlib import Path

from oocyte_fe.runner.run import plan, run_cases
from tests.case_copies import edited_case


def test_an_invalid_case_keeps_the_kind_it_names(tmp_path: Path) -> None:
    bad = edited_case(tmp_path / "cases", "fe_afm_sphere", **{"cell.outer_diameter_um": -1.0})
    broken = tmp_path / "cases" / "broken"
    broken.mkdir()
    (broken / "case.toml").write_text('kind = "fe_experiment"\n[inputs\n')  # not TOML
    results = run_cases(plan([bad, broken]), tmp_path / "results")
    by_name = {r.name: r for r in results}
    assert [(by_name[n].status, by_name[n].kind) for n in ("fe_afm_sphere", "broken")] == [
        ("ERROR", "fe_experiment"),
        ("ERROR", "?"),
    ]
    report = (tmp_path / "results" / "fe_afm_sphere" / "report.md").read_text()
    assert "Kind `fe_experiment`" in report
    summary = (tmp_path / "results" / "summary.md").read_text()
    assert "| [fe_afm_sphere](fe_afm_sphere/report.md) | fe_experiment | ERROR |" in summary
