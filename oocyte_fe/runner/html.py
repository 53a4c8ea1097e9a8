"""HTML beside the Markdown: ``index.html`` (the run) and ``report.html`` (a case).

Both are the Markdown reports rendered by markdown-it (CommonMark with tables), with status
cells coloured and figures shown inline (the images sit beside the page). No JavaScript, no
network: one file per page that any browser opens.
"""

from __future__ import annotations

import html
import re
from pathlib import Path

from markdown_it import MarkdownIt

from oocyte_fe.runner.result import CaseResult

_STYLE = """
body { font-family: sans-serif; max-width: 70em; margin: 2em auto; padding: 0 1em; }
table { border-collapse: collapse; margin: 1em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #eee; }
td.PASS { background: #d4f4d4; } td.MISS { background: #fff2c2; }
td.SKIPPED { background: #dde8f4; }
td.FAIL { background: #ffd6c2; } td.ERROR { background: #f4b8b8; }
img { max-width: 100%; }
pre { background: #f6f6f6; padding: 0.5em; overflow-x: auto; }
"""

_STATUS_CELL = re.compile(r"<td>(PASS|MISS|SKIPPED|FAIL|ERROR)</td>")


def render(markdown: str, title: str) -> str:
    """A standalone HTML page of ``markdown`` with status cells coloured."""
    body = MarkdownIt("commonmark").enable("table").render(markdown)
    body = _STATUS_CELL.sub(r'<td class="\1">\1</td>', body)
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head>\n"
        f"<body>\n{body}</body></html>\n"
    )


def write_case_html(out_dir: Path, title: str) -> None:
    """``report.html`` from the case's ``report.md`` (same folder, figures linked inline)."""
    text = (out_dir / "report.md").read_text()
    (out_dir / "report.html").write_text(render(text, title))


def index_html(rows: list[CaseResult], out_root: Path) -> str:
    """The run's front page: one row per case linking to its HTML and Markdown report."""
    lines = [
        "# Validation summary",
        "",
        "| case | kind | status | checks passed | time (s) | reason | reports |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        page = "report.html" if (out_root / r.name / "report.html").is_file() else "report.md"
        reason = r.reason.replace("|", "\\|")
        lines.append(
            f"| [{r.name}]({r.name}/{page}) | {r.kind} | {r.status} | {r.passed}/{r.total} "
            f"| {r.seconds:.1f} | {reason} | [md]({r.name}/report.md) |"
        )
    documented = [(r.name, m) for r in rows for m in r.misses]
    if documented:
        lines += ["", "## Documented misses (not failures)", ""]
        lines += [f"- **{name}**: {m}" for name, m in documented]
    lines += ["", "Markdown version: [summary.md](summary.md)."]
    return render("\n".join(lines) + "\n", "Validation summary")
