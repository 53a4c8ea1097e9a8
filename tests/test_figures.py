"""Every kind's figures, rendered on its case's quick settings (cheaper still where a case's
quick run takes long), are not blank and have labelled axes.

Kinds come from the registry and their cases from ``cases/*/case.toml``, so a new kind with a
case is covered without editing this file; a kind with no case must be listed in
``NO_CASE`` with the reason. A sweep case's own figures (histograms, scatter, sensitivity)
are rendered by the sweep's aggregation on a synthetic design of 32 samples. A case whose
quick run other tests read too (``SHARED``) is checked on that run (tests/conftest.py), its
figures' labels recorded as they were saved.

Checks:

* every PNG written (matplotlib or pyvista): pixel standard deviation > 15 (0-255 scale) and
  at least 2 % of the pixels away from the background colour;
* every matplotlib figure, inspected when it is saved (``Figure.savefig`` wrapped): each
  visible axes with its axis lines on has an x and a y label (its own, or one on an axes it
  shares that axis with); a colour bar has a label; an axes drawn without axis lines has a
  title; in an axes with a legend every line is in it (a line meant to stay out says so with
  ``label="_nolegend_"``).
"""

from __future__ import annotations

import json
import logging
import math
import re
from collections.abc import Iterator
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np
import pytest
from matplotlib.figure import Figure as MplFigure

from oocyte_fe.microchannel.vof.runner import INSTALL_HINT, openfoam_available
from oocyte_fe.runner.casefile import load_case, read_toml
from oocyte_fe.runner.registry import CaseContext, kinds
from tests.figure_checks import LABELS_FILE, blank, check_outputs, label_problems, recorded_labels

ROOT = Path(__file__).parents[1]
CASES = ROOT / "cases"

# inputs over the case's [quick] table, only to make slow quick runs cheaper (same figures)
CHEAPER: dict[str, dict] = {
    "afm_zp_cytoplasm": {"n_oocytes": 1},
    "fe_verification": {"shell_size_um": 5.0, "hertz_fractions": [2.0, 1.0, 0.5]},
    "fe_neck_aspiration": {
        "steps": 8,
        "size_um": 16.0,
        "mesh_study_sizes_um": [],
        "sensitivity": False,
    },
    "nmsd_vs_fe": {
        "travel_um": 20.0,
        "arrow_advances_um": [10.0, 20.0],  # FE frames of the shorter press
        "n_starts": 1,
        "max_evaluations": 8,
        "nmsd_n_steps": 10,
        "calibrate_both_speeds": False,
        "check_speed_um_s": 0.0,
    },
    "nmsd_calibration_tableII": {"n_starts": 1, "max_evaluations": 8},
    "nmsd_spindle_offset": {"n_starts": 1, "max_evaluations": 8},
    "rtdc_elastic_cell": {"flow_size_um": 2.0, "mesh_fraction": 0.2},
}
SHARED = {"microchannel_vof_quick"}
"""Cases whose figures are checked on the quick run that other tests read too (tests/conftest.py:
run once per test run, its figures' labels recorded as they were saved)."""
NO_CASE = {
    "analytic_linear": "the closed-form test kind of the sweep tests; it draws nothing",
    "nmsd_spindle_offset_resampled": "the sweep kind of sweep_spindle_offset; draws nothing "
    "per sample (its figures are the sweep's, rendered below)",
    "afm_shell_correction": "a heavy case only (fresh FE runs, minutes); it draws no figures",
}


def _case_dirs() -> dict[str, Path]:
    """One case folder per kind (the first in name order); sweep cases are kept apart, heavy
    cases (``--full`` only) left out."""
    found: dict[str, Path] = {}
    for file in sorted(CASES.glob("*/case.toml")):
        spec = read_toml(file)
        if "sweep" not in spec and not spec.get("heavy", False):
            found.setdefault(spec["kind"], file.parent)
    return found


def _sweep_dirs() -> list[Path]:
    return [f.parent for f in sorted(CASES.glob("*/case.toml")) if "sweep" in read_toml(f)]


@pytest.fixture
def saved_figures() -> Iterator[dict[str, list[str]]]:
    """file name -> label problems of every matplotlib figure saved while the test runs."""
    with recorded_labels() as seen:
        yield seen


def test_every_kind_has_a_case_or_a_reason() -> None:
    # kinds that tests register for themselves (tests/kinds_for_tests.py) have no figures
    builtin = {name for name, kind in kinds().items() if kind.module.startswith("oocyte_fe.")}
    missing = builtin - set(_case_dirs()) - set(NO_CASE)
    assert not missing, f"kinds with no case to render their figures: {sorted(missing)}"


@pytest.mark.slow
@pytest.mark.parametrize("kind", sorted(_case_dirs()))
def test_kind_figures(
    kind: str, tmp_path: Path, saved_figures: dict[str, list[str]], monkeypatch, request
) -> None:
    monkeypatch.setenv("OOCYTE_FE_CACHE", str(tmp_path / "mesh_cache"))
    folder = _case_dirs()[kind]
    if kind == "microchannel_vof" and not openfoam_available():
        pytest.skip(f"OpenFOAM not installed: {INSTALL_HINT}")
    if folder.name in SHARED:
        out = request.getfixturevalue("quick_run")(folder.name)
        listed = re.findall(r"^!\[.*\]\(([^()\s]+)\)$", (out / "report.md").read_text(), re.M)
        assert listed, f"{folder.name}: no figure listed in its report"
        for file in listed:
            assert (out / file).is_file(), f"{file} listed but not written"
        check_outputs(out, json.loads((out.parent / LABELS_FILE).read_text()))
        return
    case = load_case(folder, quick=True)
    raw = {**case.spec.inputs, **case.spec.quick, **CHEAPER.get(folder.name, {})}
    inputs = case.kind.inputs.model_validate(raw, context={"case_dir": folder})
    out = tmp_path / "out"
    out.mkdir()
    ctx = CaseContext(case.name, folder, out, inputs, True, logging.getLogger(f"figures.{kind}"))
    outcome = case.kind.run(ctx)
    for figure in outcome.figures:
        assert (out / figure.file).is_file(), f"{figure.file} listed but not written"
    check_outputs(out, saved_figures)


@pytest.mark.slow
@pytest.mark.parametrize("folder", _sweep_dirs(), ids=lambda p: p.name)
def test_sweep_figures(folder: Path, tmp_path: Path, saved_figures) -> None:
    """The sweep's aggregation draws labelled, non-blank figures (32 synthetic samples)."""
    from oocyte_fe.sweep.report import SampleRow, aggregate
    from oocyte_fe.sweep.sampling import design
    from oocyte_fe.sweep.store import SampleRecord

    case = load_case(folder)
    sweep = case.spec.sweep
    sweep = sweep.model_copy(update={"samples": 32})
    case = type(case)(
        case.name,
        case.directory,
        case.spec.model_copy(update={"sweep": sweep}),
        case.kind,
        case.inputs,
        False,
    )
    d = design(sweep, False)
    metrics = sweep.metrics or list(case.kind.metrics)
    rows = []
    for i, (values, unit) in enumerate(zip(d.values, d.unit, strict=True)):
        y = {m: float(k + 1 + unit @ np.arange(1, len(unit) + 1)) for k, m in enumerate(metrics)}
        rows.append(
            SampleRow(i, values, np.asarray(unit), SampleRecord(f"{i}", "PASS", 1.0, "", y))
        )
    outcome = aggregate(case, rows, list(sweep.parameters), tmp_path)
    assert math.isclose(outcome.metrics["ok_fraction"], 1.0)
    assert {f.file for f in outcome.figures} == {"histograms.png", "scatter.png", "sensitivity.png"}
    check_outputs(tmp_path, saved_figures)


def test_nmsd_snapshots_share_one_colour_scale(tmp_path: Path, monkeypatch) -> None:
    """All panels on one scale from 0 to the largest |u|; a field at rest gets 0..1 um."""
    from matplotlib.collections import PathCollection

    from nmsd.lattice import circular_lattice
    from nmsd.pipette import Pipette
    from nmsd.plotting import plot_snapshots

    limits: list[list[tuple[float, float]]] = []
    original = MplFigure.savefig

    def savefig(self: MplFigure, fname, *args, **kwargs):
        scatters = [c for ax in self.axes for c in ax.collections if isinstance(c, PathCollection)]
        limits.append([(c.norm.vmin, c.norm.vmax) for c in scatters])
        assert not label_problems(self), label_problems(self)
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(MplFigure, "savefig", savefig)
    lattice = circular_lattice()
    moved = lattice.nodes + np.array([[0.0, 0.0]] * (lattice.n_nodes - 1) + [[3.0, 4.0]])
    snaps = {0.0: lattice.nodes, 10.0: lattice.nodes + 0.5, 20.0: moved}
    plot_snapshots(tmp_path / "a.png", lattice, Pipette(), snaps)
    plot_snapshots(tmp_path / "b.png", lattice, Pipette(), {0.0: lattice.nodes})
    assert limits[0] == [(0.0, 5.0)] * 3  # |(3, 4)| = 5 um, shared by the three panels
    assert limits[1] == [(0.0, 1.0)]  # nothing moved: 0..1, not -0.1..0.1
    assert blank(tmp_path / "a.png") is None
