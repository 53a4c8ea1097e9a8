"""Writing a case's ``report.md`` and ``metrics.json``, and the run's ``summary.md``."""

from __future__ import annotations

import math
import os
from pathlib import Path

import tomli_w

from oocyte_fe.runner.casefile import Case
from oocyte_fe.runner.html import index_html, write_case_html
from oocyte_fe.runner.registry import CaseOutcome, Check
from oocyte_fe.runner.result import STATUSES, CaseResult, read_result
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
        status, remark = tol.judge(float(value), refval)
        checks.append(
            Check(
                key,
                float(value),
                status == "PASS",
                tol.describe(),
                reference=refval,
                source=ref.source if ref else None,
                unit=ref.unit if ref else None,
                status=status,
                remark="; ".join(r for r in (remark, tol.note or "") if r),
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


def case_status(checks: list[Check]) -> str:
    """``FAIL`` if any check fails, else ``MISS`` if any is a documented miss, else ``PASS``."""
    statuses = {c.status for c in checks}
    return "FAIL" if "FAIL" in statuses else "MISS" if "MISS" in statuses else "PASS"


def misses(checks: list[Check]) -> tuple[str, ...]:
    """One line per documented miss: name, value and the remark (distance and reason)."""
    return tuple(f"{c.name} = {_fmt(c.computed)}: {c.remark}" for c in checks if c.status == "MISS")


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def checks_table(checks: list[Check]) -> list[str]:
    """The checks as a Markdown table; notes and sources are numbered below it."""
    lines = [
        "| check | value | reference | unit | deviation | tolerance | status |",
        "|---|---|---|---|---|---|---|",
    ]
    notes = []
    for c in checks:
        marks = ""
        for text in (c.remark, f"source: {c.source}" if c.source else ""):
            if text:
                notes.append(f"{len(notes) + 1}. **{c.name}**: {text}")
                marks += f" [{len(notes)}]"
        lines.append(
            f"| {c.name}{marks} | {_fmt(c.computed)} | {_fmt(c.reference)} | {c.unit or ''} "
            f"| {c.deviation} | {_cell(c.tolerance)} | {c.status} |"
        )
    return lines + ([""] + notes if notes else [])


def write_case_report(
    case: Case, outcome: CaseOutcome, checks: list[Check], out_dir: Path, seconds: float
) -> str:
    """Write ``report.md`` and ``metrics.json`` into ``out_dir``; return the status."""
    status = "SKIPPED" if outcome.skipped else case_status(checks)
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
                        "unit": c.unit,
                        "tolerance": c.tolerance,
                        "passed": c.passed,
                        "status": c.status,
                        "remark": c.remark,
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
        lines += checks_table(checks)
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
    write_case_html(out_dir, f"{case.name}: {status}")
    return status


def _inputs_toml(case: Case) -> str:
    data = case.inputs.model_dump(mode="json", exclude_none=True)
    data = {key: value for key, value in data.items() if value != ""}  # an unset text
    return tomli_w.dumps(data).strip()


def write_failure_report(name: str, kind: str, reason: str, out_dir: Path) -> None:
    """The whole result of a case that raised: a report stating why, no partial outputs."""
    (out_dir / "report.md").write_text(
        f"# {name}: ERROR\n\nKind `{kind}`. The case did not finish:\n\n    {reason}\n\n"
        "The traceback and the case's log are in `error.log`. No partial results are kept.\n"
    )
    write_case_html(out_dir, f"{name}: ERROR")


def summary_rows(out_root: Path, results: list[CaseResult]) -> list[CaseResult]:
    """Every case folder present under ``out_root`` (its ``result.json``), with ``results``
    (this run's) taking precedence; sorted by name."""
    rows = {}
    for folder in sorted(p for p in out_root.iterdir() if p.is_dir() and p.name[0] != "."):
        found = read_result(folder)
        if found is not None:
            rows[found.name] = found
    rows.update({r.name: r for r in results})
    return [rows[name] for name in sorted(rows)]


def summary_markdown(rows: list[CaseResult]) -> str:
    """``summary.md``: one row per case, then the documented misses."""
    counts = ", ".join(f"{n} {s}" for s in STATUSES if (n := sum(r.status == s for r in rows)))
    lines = [
        "# Validation summary",
        "",
        f"{len(rows)} cases: {counts}.",
        "",
        "| case | kind | status | checks passed | time (s) | reason |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| [{r.name}]({r.name}/report.md) | {r.kind} | {r.status} | "
            f"{r.passed}/{r.total} | {r.seconds:.1f} | {_cell(r.reason)} |"
        )
    documented = [(r.name, m) for r in rows for m in r.misses]
    if documented:
        lines += ["", "## Documented misses (not failures)", ""]
        lines += [f"- {name}: {m}" for name, m in documented]
    return "\n".join(lines) + "\n"


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename (never half-written)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def write_summary(results: list[CaseResult], out_root: Path) -> Path:
    """Rebuild ``summary.md`` and ``index.html`` from the case folders present (atomically)."""
    rows = summary_rows(out_root, results)
    path = out_root / "summary.md"
    write_atomic(path, summary_markdown(rows))
    write_atomic(out_root / "index.html", index_html(rows, out_root))
    return path
