"""The self-contained Python examples of docs/ run as pasted from the repository root (in a
scratch folder that sees the repository's cases/, so what they write stays out of the tree).

Fragments that need the user's own files or earlier results (mesh.md's .msh reader and output
snippets, sweeps.md's cluster and results examples) are left out by name.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
DOCS = ROOT / "docs"
FRAGMENTS = {("mesh.md", 2), ("mesh.md", 3), ("mesh.md", 4), ("sweeps.md", 0), ("sweeps.md", 1)}


def _examples() -> list[tuple[str, int, str]]:
    found = []
    for page in sorted(DOCS.rglob("*.md")):
        blocks = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)
        found += [(page.name, i, code) for i, code in enumerate(blocks)]
    return [(name, i, code) for name, i, code in found if (name, i) not in FRAGMENTS]


@pytest.mark.parametrize(("page", "index", "code"), _examples(), ids=lambda v: str(v)[:20])
def test_docs_example_runs(page: str, index: int, code: str, tmp_path: Path) -> None:
    (tmp_path / "cases").symlink_to(ROOT / "cases")
    script = tmp_path / "example.py"
    script.write_text(code)
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, f"{page} example {index}:\n{done.stderr[-2000:]}"
