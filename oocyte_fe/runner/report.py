"""Writing a case's ``report.md`` and ``metrics.json``, and the run's ``summary.md``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import tomli_w

from oocyte_fe.runner.casefile import Case
from oocyte_fe.runner.registry import CaseOutcome, Check
from oocyte_fe.runner.strict_json import strict_dumps


def _fmt(value: float | None) -> str:
    if value is None:
        return ""
    return f"{value:.6g}"


def evaluate_checks(case: Case, outcome: CaseOutcome) -> list[Check]:
    """Compare the metrics named in ``[tolerances]`` with ``[reference]``; add the kind's checks."""
    checks: list[Check] = []
    for key, tol in case.spec.tolerances.items():
        ref = case.spec.reference.get(key)
        value = outcome.metrics.get(key)
        if not isinstance(value, int | float):
            checks.append(Check(key, math.nan, False, f"{tol.describe()} (metric not reported)"))
            continue
        refval = ref.value if ref else None
        checks.append(
            Check(
                key,
                float(value),
                tol.accepts(float(value), refval),
                tol.describe() + (f" ({tol.note})" if tol.note else ""),
                reference=refval,
                source=ref.source if ref else None,
                unit=ref.unit if ref else None,
            )
        )
    return checks + list(outcome.checks)


def _comparisons(case: Case, outcome: CaseOutcome) -> list[str]:
    """References without a tolerance: reported (how far off), not judged."""
    rows = []
    for key, ref in case.spec.reference.items():
        if key in case.spec.tolerances:
            continue
        value = outcome.metrics.get(key)
        if isinstance(value, int | float):
            c = Check(key, float(value), True, "", ref.value, ref.source, ref.unit)
            rows.append(
                f"| {key} | {_fmt(c.computed)} | {_fmt(ref.value)} {ref.unit or ''} "
                f"| {c.deviation} | {ref.source} |"
            )
    return rows


def write_case_report(
    case: Case, outcome: CaseOutcome, checks: list[Check], out_dir: Path, seconds: float
) -> str:
    """Write ``report.md`` and ``metrics.json`` into ``out_dir``; return the status."""
    status = "PASS" if all(c.passed for c in checks) else "FAIL"
    (out_dir / "metrics.json").write_text(
        strict_dumps(
            {
                "case": case.name,
                "kind": case.kind.name,
                "status": status,
                "seconds": round(seconds, 3),
                "metrics": outcome.metrics,
                "checks": [
                    {
                        "name": c.name,
                        "computed": c.computed,
                        "reference": c.reference,
                        "tolerance": c.tolerance,
                        "passed": c.passed,
                        "source": c.source,
                    }
                    for c in checks
                ],
            },
        )
    )
    lines = [
        f"# {case.name}: {status}",
        "",
        f"Kind `{case.kind.name}`, {seconds:.1f} s. {case.spec.description}",
        "",
    ]
    if case.spec.reading:
        lines += ["## Reading of the paper", "", case.spec.reading.strip(), ""]
    lines += ["## Checks", ""]
    if checks:
        lines += [
            "| check | computed | reference | deviation | tolerance | result | source |",
            "|---|---|---|---|---|---|---|",
        ]
        for c in checks:
            ref = f"{_fmt(c.reference)} {c.unit or ''}".strip()
            lines.append(
                f"| {c.name} | {_fmt(c.computed)} | {ref} | {c.deviation} | {c.tolerance} "
                f"| {'PASS' if c.passed else 'FAIL'} | {c.source or ''} |"
            )
    else:
        lines.append("No checks declared.")
    comparisons = _comparisons(case, outcome)
    if comparisons:
        lines += [
            "",
            "## Compared with the papers (no tolerance: reported only)",
            "",
            "| metric | computed | paper | deviation | source |",
            "|---|---|---|---|---|",
            *comparisons,
        ]
    for title, body in outcome.sections:
        lines += ["", f"## {title}", "", body.strip()]
    if outcome.figures:
        lines += ["", "## Figures", ""]
        for fig in outcome.figures:
            lines += [f"![{fig.caption}]({fig.file})", "", f"*{fig.caption}*", ""]
    lines += ["", "## Inputs", "", "```toml", _inputs_toml(case), "```", ""]
    (out_dir / "report.md").write_text("\n".join(lines))
    return status


def _inputs_toml(case: Case) -> str:
    data = case.inputs.model_dump(mode="json", exclude_none=True)
    return tomli_w.dumps(data).strip()


def write_failure_report(name: str, kind: str, reason: str, out_dir: Path) -> None:
    """The whole result of a case that raised: a report stating why, no partial outputs."""
    (out_dir / "report.md").write_text(
        f"# {name}: ERROR\n\nKind `{kind}`. The case did not finish:\n\n    {reason}\n\n"
        "The traceback and the case's log are in `error.log`. No partial results are kept.\n"
    )


def write_summary(results: list[Any], out_root: Path) -> Path:
    """``summary.md``: one row per case."""
    lines = [
        "# Validation summary",
        "",
        "| case | kind | status | checks passed | time (s) | reason |",
        "|---|---|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            f"| [{r.name}]({r.name}/report.md) | {r.kind} | {r.status} | "
            f"{r.passed}/{r.total} | {r.seconds:.1f} | {r.reason} |"
        )
    path = out_root / "summary.md"
    path.write_text("\n".join(lines) + "\n")
    return path
