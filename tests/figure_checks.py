"""What the figure tests check in a figure: labelled axes (on the matplotlib figure when it is
saved) and a PNG that is not blank. Used by tests/test_figures.py and by the shared quick runs
of tests/conftest.py, whose figures are checked from the labels recorded while they ran."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure as MplFigure
from PIL import Image

LABELS_FILE = "figure_labels.json"
"""Beside a shared quick run's case folder (tests/conftest.py): file -> label problems of every
figure the run saved."""


def label_problems(fig: MplFigure) -> list[str]:
    """What is unlabelled in ``fig`` (empty when every axes is labelled)."""
    problems = []
    for i, ax in enumerate(fig.axes):
        if not ax.get_visible():
            continue
        where = f"axes {i} ({ax.get_title() or 'untitled'})"
        if hasattr(ax, "_colorbar"):
            if not (ax.get_xlabel() or ax.get_ylabel()):
                problems.append(f"{where}: colour bar without a label")
            continue
        if not ax.axison:
            if not ax.get_title():
                problems.append(f"{where}: drawn without axes and without a title")
            continue
        if ax.get_legend() is not None:
            problems += [
                f"{where}: a line left out of the legend without a label"
                for line in ax.get_lines()
                if line.get_label().startswith("_child")
            ]
        xs = ax.get_shared_x_axes().get_siblings(ax)
        ys = ax.get_shared_y_axes().get_siblings(ax)
        if not any(a.get_xlabel() for a in xs):
            problems.append(f"{where}: no x label")
        if not any(a.get_ylabel() for a in ys):
            problems.append(f"{where}: no y label")
    return problems


@contextmanager
def recorded_labels() -> Iterator[dict[str, list[str]]]:
    """file name -> label problems of every matplotlib figure saved inside the block."""
    seen: dict[str, list[str]] = {}
    original = MplFigure.savefig

    def savefig(self: MplFigure, fname, *args, **kwargs):
        seen[str(fname)] = label_problems(self)
        return original(self, fname, *args, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(MplFigure, "savefig", savefig)
        yield seen


def blank(path: Path) -> str | None:
    """Why the PNG ``path`` looks blank, or None."""
    image = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    background = np.median(image.reshape(-1, 3), axis=0)
    away = (np.abs(image - background).max(axis=2) > 30).mean()
    if image.std() <= 15.0 or away < 0.02:
        return f"{path.name}: pixel SD {image.std():.1f}, {100 * away:.1f} % off-background"
    return None


def check_outputs(out: Path, saved: dict[str, list[str]]) -> None:
    """Every PNG under ``out`` is not blank and every figure ``saved`` is labelled."""
    pngs = sorted(out.rglob("*.png"))
    assert pngs, f"no figure written in {out}"
    blanks = [why for p in pngs if (why := blank(p))]
    assert not blanks, blanks
    unlabelled = {}
    for file, problems in saved.items():
        if problems:
            unlabelled[str(Path(file).relative_to(out))] = problems
    assert not unlabelled, "\n".join(f"{f}: {p}" for f, ps in unlabelled.items() for p in ps)
