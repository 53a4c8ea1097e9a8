"""Every fenced Python block of README.md and docs/**/*.md runs as pasted.

Pages are found by globbing, so a new page's examples are tested without editing this file.
Each block runs alone, in a fresh interpreter, in a scratch folder that sees the repository's
``cases/`` (what the examples write stays out of the tree).

A block that cannot run alone is marked where it stands, in one of two ways, and is then
skipped (and listed by ``pytest -rs``); nothing else is skipped:

* its info string: ```` ```python fragment ````;
* an HTML comment on the line before its fence: ``<!-- fragment: why -->``.

Some blocks read files a user would have (a mesh, a sweep's table). The test makes those
files in the scratch folder first, with the project's own code (``_PREPARE``): the
``my_oocyte.msh`` mesh of mesh.md is the layered-oocyte generator's gmsh file; the sweep's
``samples.csv`` of sweeps.md is written by the sweep's own table writer. The dask-jobqueue
example of sweeps.md runs against stand-ins of SLURM's ``sbatch``/``scancel`` put on PATH
(the cluster object is built and scaled; no job runs) with a newline on stdin for its
``input()``.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
FENCE = re.compile(r"(?P<before>[^\n]*)\n```python(?P<info>[^\n]*)\n(?P<code>.*?)^```", re.S | re.M)
FRAGMENT_COMMENT = re.compile(r"<!--\s*fragment\b")


@dataclass(frozen=True)
class Block:
    page: str
    index: int
    code: str
    fragment: bool

    def __str__(self) -> str:
        return f"{self.page}#{self.index}"


def docs_blocks(pages: list[Path] = PAGES) -> list[Block]:
    """The fenced python blocks of ``pages``, numbered per page from 0."""
    found = []
    for page in pages:
        text = "\n" + page.read_text()
        name = str(page.relative_to(ROOT)) if page.is_relative_to(ROOT) else page.name
        for i, m in enumerate(FENCE.finditer(text)):
            marked = "fragment" in m["info"].split() or bool(FRAGMENT_COMMENT.search(m["before"]))
            found.append(Block(name, i, m["code"], marked))
    return found


def _user_mesh(folder: Path) -> None:
    from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
    from oocyte_fe.mesh.cache import cache_path

    geom = LayeredOocyte(cytoplasm_radius_um=75.0, zona_thickness_um=15.0, size_um=10.0)
    layered_oocyte_mesh(geom)  # builds (or finds) the gmsh file in the cache
    shutil.copy(cache_path(geom), folder / "my_oocyte.msh")


def _sweep_table(folder: Path) -> None:
    from oocyte_fe.sweep.report import SampleRow, write_table
    from oocyte_fe.sweep.store import SampleRecord

    rng = np.random.default_rng(0)
    metrics = ["offset_x_um", "offset_y_um"]
    rows = [
        SampleRow(
            i,
            {"noise_seed": i, "dl_c": 0.6 + 0.05 * i},
            np.array([i / 8, i / 8]),
            SampleRecord(
                f"{i:016x}",
                "PASS",
                1.0,
                "",
                {m: float(v) for m, v in zip(metrics, rng.normal(18, 1, 2), strict=True)},
            ),
        )
        for i in range(8)
    ]
    out = folder / "results" / "sweep_spindle_offset"
    out.mkdir(parents=True)
    write_table(out / "samples.csv", rows, ["noise_seed", "dl_c"], metrics)


def _fake_slurm(folder: Path) -> None:
    bin_dir = folder / "bin"
    bin_dir.mkdir()
    for name, text in {"sbatch": "echo 'Submitted batch job 1'", "scancel": "exit 0"}.items():
        (bin_dir / name).write_text(f"#!/bin/sh\n{text}\n")
        (bin_dir / name).chmod(0o755)


_PREPARE: dict[str, Callable[[Path], None]] = {
    "my_oocyte.msh": _user_mesh,
    "results/sweep_spindle_offset/samples.csv": _sweep_table,
    "dask_jobqueue": _fake_slurm,
}


@pytest.mark.parametrize("block", docs_blocks(), ids=str)
def test_docs_example_runs(block: Block, tmp_path: Path) -> None:
    if block.fragment:
        pytest.skip(f"{block}: marked as a fragment")
    (tmp_path / "cases").symlink_to(ROOT / "cases")
    for needle, prepare in _PREPARE.items():
        if needle in block.code:
            prepare(tmp_path)
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = f"{tmp_path / 'bin'}{os.pathsep}{env['PATH']}"
    script = tmp_path / "example.py"
    script.write_text(block.code)
    done = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        input="\n",
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, f"{block}:\n{done.stderr[-2000:]}"


def test_blocks_are_found_and_marks_read(tmp_path: Path) -> None:
    """The extractor finds every block of a page, with both ways of marking a fragment."""
    page = tmp_path / "probe.md"
    text = (
        "# t\n\n```python\nprint(1)\n```\n\ntext\n<!-- fragment: needs x -->\n"
        "```python\nprint(x)\n```\n\n```python fragment\nprint(y)\n```\n\n"
        "```bash\nls\n```\n"
    )
    page.write_text(text)
    blocks = docs_blocks([page])
    assert [(b.index, b.code, b.fragment) for b in blocks] == [
        (0, "print(1)\n", False),
        (1, "print(x)\n", True),
        (2, "print(y)\n", True),
    ]
