"""Case kind ``afm_fit_files``: the user's own curve files -> fit table -> material files.

The whole user route without Python: a folder (or glob) of curve files inside the case folder,
the tip model, nu, the fit range and contact method, groups (by subfolder or pattern) and an
optional creep file per group. Writes ``fits.csv`` (one row per curve, bad curves with their
error), a plot per curve, a histogram and mean +- SD per group, a modulus map per force-map
file, and per group ``material_<group>.toml`` with its ANSYS and FEBio blocks.
"""

from __future__ import annotations

import csv
import fnmatch
import math
import os
import re
from dataclasses import replace
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from afm import plotting
from afm.batch import BatchResult, curve_files, fit_batch, write_batch_table
from afm.creep import fit_creep
from afm.curve_io import read_creep
from afm.curve_plots import plot_curves, plot_name
from afm.fe_export import ansys_prony_block, febio_material
from afm.fit import FitRange
from afm.material_file import MaterialFile, write_material
from afm.models import MODELS
from afm.nanite_pipeline import fit_nanite_default
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.data_templates import KNOWN_MODULI
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs


class FitFilesInputs(CaseInputs):
    curves: str = Field(
        min_length=1,
        description="folder (searched recursively) or glob of curve files, relative to the "
        "case folder: CSV/TSV tables or any instrument file afmformats reads",
    )
    model: str = Field("sneddon_cone", description="tip model key (afm.models)")
    geometry: dict[str, float] = Field(
        default_factory=dict,
        description="tip parameters of the model, e.g. half_angle_deg = 10 (deg) or "
        "radius_um (um); left-out ones take the model's default",
        json_schema_extra={"unit": "deg or um, by the key's suffix"},
    )
    nu: float = Field(
        0.5,
        gt=-1,
        le=0.5,
        description="Poisson ratio of the sample",
        json_schema_extra={"unit": "1"},
    )
    max_indentation_um: float | None = Field(
        None, gt=0, description="fit range: depth past contact", json_schema_extra={"unit": "um"}
    )
    max_force_fraction: float | None = Field(
        None,
        gt=0,
        le=1,
        description="fit range: fraction of the maximum force",
        json_schema_extra={"unit": "1"},
    )
    contact_method: Literal["fit", "deviation"] = Field(
        "fit", description="contact point: a fit parameter, or the deviation estimate"
    )
    analysis: Literal["default", "nanite"] = Field(
        "default",
        description="default: afm.fit.fit_indentation (baseline line, unweighted fit); nanite: "
        "afm.nanite_pipeline.fit_nanite_default (nanite's offset, contact weighting, free "
        "baseline; whole approach, so no fit range)",
    )
    groups: dict[str, str] = Field(
        default_factory=dict,
        description="group name -> glob pattern on the file path relative to the case folder; "
        "files matching none are grouped by their subfolder",
    )
    height_channel: str | None = Field(
        None, description="height channel of instrument files (default: as the instrument does)"
    )
    creep: dict[str, DataFile] = Field(
        default_factory=dict,
        description="group name -> force-clamp creep CSV: its material gets E0 and a Prony series",
    )
    half_angle_deg_creep: float = Field(
        10.0,
        gt=0,
        lt=90,
        description="cone half angle for the creep fit",
        json_schema_extra={"unit": "deg"},
    )
    known_moduli: DataFile | None = Field(
        None,
        description="optional CSV (file, E_kPa) of known moduli to check the fits against",
        json_schema_extra=KNOWN_MODULI,
    )
    known_tolerance_pct: float = Field(
        5.0, gt=0, description="largest error against known_moduli", json_schema_extra={"unit": "%"}
    )

    @field_validator("model")
    @classmethod
    def _known_model(cls, value: str) -> str:
        if value not in MODELS:
            raise ValueError(f"one of {', '.join(sorted(MODELS))}")
        return value

    @model_validator(mode="after")
    def _finite(self) -> FitFilesInputs:
        for key, value in self.geometry.items():
            if not math.isfinite(value):
                raise ValueError(f"geometry.{key}: a finite number")
        return self


PLOT_WORKERS = min(2, os.cpu_count() or 1)
"""Processes drawing the per-curve plots (the machine's 2 cores)."""

METRICS = {
    "n_curves": "curves read (a force map counts each of its curves)",
    "n_fitted": "curves fitted",
    "n_failed": "curves that could not be read or fitted (reported and skipped)",
    "n_poor": "fitted curves rated poor",
    "max_known_error_pct": "largest |E / E_known - 1| over curves with a known modulus, %",
}


def _inside(case_dir: Path, path: Path, field: str) -> Path:
    resolved = path.resolve()
    if not resolved.is_relative_to(case_dir.resolve()):
        raise InputError(case_dir / "case.toml", field, "a path inside the case folder", str(path))
    return resolved


def find_curve_files(case_dir: Path, pattern: str) -> list[Path]:
    """The curve files named by ``pattern`` (a folder or a glob, relative to ``case_dir``)."""
    where = case_dir / "case.toml"
    if Path(pattern).is_absolute():
        raise InputError(where, "inputs.curves", "a folder or glob relative to the case folder")
    target = case_dir / pattern
    if target.is_dir():
        _inside(case_dir, target, "inputs.curves")
        try:
            return curve_files(target)
        except InputError as exc:
            raise InputError(where, "inputs.curves", exc.expected, str(target)) from None
    files = sorted(p for p in case_dir.glob(pattern) if p.is_file())
    files = [p for p in files if _inside(case_dir, p, "inputs.curves")]
    if not files:
        raise InputError(where, "inputs.curves", "a folder or glob that names curve files", pattern)
    return files


def _regroup(result: BatchResult, case_dir: Path, groups: dict[str, str]) -> None:
    for i, row in enumerate(result.rows):
        relative = Path(row.file).relative_to(case_dir).as_posix()
        for name, pattern in groups.items():
            if fnmatch.fnmatch(relative, pattern):
                result.rows[i] = replace(row, group=name)
                break


def _known(path: Path) -> dict[str, float]:
    known: dict[str, float] = {}
    with path.open() as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        for i, row in enumerate(rows, start=2):
            try:
                known[row["file"]] = float(row["E_kPa"])
            except (KeyError, TypeError, ValueError):
                raise InputError(path, f"row {i}", "columns file, E_kPa (a number)") from None
    return known


def file_stem(group: str) -> str:
    """``group`` as part of a file name: characters other than letters, digits, ``-`` and
    ``_`` become ``_`` (a group name can never reach outside the result folder)."""
    return re.sub(r"[^A-Za-z0-9_-]", "_", group) or "_"


def _sd(values: np.ndarray) -> float:
    """Sample SD (ddof = 1); 0 for a single value."""
    return float(values.std(ddof=1)) if values.size > 1 else 0.0


def _group_material(
    group: str, values: np.ndarray, inp: FitFilesInputs, ctx: CaseContext
) -> tuple[MaterialFile, str]:
    creep_file = inp.creep.get(group)
    if creep_file is None:
        source = (
            f"afm_fit_files case: mean of {values.size} {inp.model} fits "
            f"({values.mean():.4g} +- {_sd(values):.3g} kPa), elastic"
        )
        return MaterialFile(group, source, float(values.mean()), inp.nu), "elastic (mean E)"
    fit = fit_creep(read_creep(creep_file), inp.half_angle_deg_creep, inp.nu)
    plotting.plot_creep(fit, ctx.output(f"creep_{file_stem(group)}.png"))
    source = (
        f"afm_fit_files case: creep {Path(creep_file).name}, Lee-Radok cone "
        f"(alpha {inp.half_angle_deg_creep:g} deg), Prony fit, exact relaxation series"
    )
    return fit.material(group, source), f"creep Prony fit ({fit.quality})"


@case_kind("afm_fit_files", inputs=FitFilesInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fit every curve file of the case folder; table, plots, statistics, material files."""
    inp: FitFilesInputs = ctx.inputs  # type: ignore[assignment]
    case_dir = ctx.case_dir
    files = find_curve_files(case_dir, inp.curves)
    for group, file in inp.creep.items():
        _inside(case_dir, Path(file), f"inputs.creep.{group}")

    ctx.step(f"fitting {len(files)} files")
    fit_options: dict[str, object] = {"model": inp.model, "geometry": inp.geometry, "nu": inp.nu}
    if inp.analysis == "nanite":
        fit_range = (inp.max_indentation_um, inp.max_force_fraction)
        if fit_range != (None, None) or inp.contact_method != "fit":
            raise InputError(
                case_dir / "case.toml",
                "inputs.analysis",
                'no fit range and contact_method = "fit" with analysis = "nanite" (it fits '
                "the whole approach, contact point free)",
                inp.analysis,
            )
        fit_options["fit_function"] = fit_nanite_default
    else:
        fit_options["fit_range"] = FitRange(inp.max_indentation_um, inp.max_force_fraction)
        fit_options["contact_method"] = inp.contact_method
    if inp.height_channel is not None:
        fit_options["read_options"] = {"height_channel": inp.height_channel}
    result = fit_batch(files, **fit_options)
    _regroup(result, case_dir, inp.groups)
    good = [r for r in result.rows if r.fit is not None and not r.error]

    ctx.step("plots")
    plot_dir = ctx.output("curve_plots/.keep").parent
    plots = {p.name for p in plot_curves(result, plot_dir, workers=PLOT_WORKERS)}
    links = {
        i: f"curve_plots/{plot_name(r)}" for i, r in enumerate(result.rows) if plot_name(r) in plots
    }
    write_batch_table(result, ctx.output("fits.csv"), case_dir, links)
    groups = sorted({r.group for r in good})
    by_group = {g: np.array([r.fit.E_kPa for r in good if r.group == g]) for g in groups}
    figures = []
    if good:
        plotting.plot_histogram(by_group, ctx.output("histogram.png"))
        figures.append(Figure("histogram.png", "Fitted Young's moduli per group"))
    map_files = sorted({r.file for r in result.rows if r.map_position_um is not None})
    for file in map_files:
        name = f"modulus_map_{Path(file).stem}.png"
        plotting.plot_modulus_map(result, file, ctx.output(name))
        figures.append(Figure(name, f"Modulus map of {Path(file).name}"))

    ctx.step("material files")
    unknown = sorted(set(inp.creep) - set(groups))
    if unknown:
        raise InputError(
            case_dir / "case.toml",
            f"inputs.creep.{unknown[0]}",
            f"a group of the fitted curves (one of {', '.join(groups) or 'none'})",
        )
    material_lines = []
    for group in groups:
        material, how = _group_material(group, by_group[group], inp, ctx)
        stem = f"material_{file_stem(group)}"
        write_material(material, ctx.output(f"{stem}.toml"))
        ctx.output(f"{stem}_ansys.inp").write_text(ansys_prony_block(material))
        ctx.output(f"{stem}_febio.xml").write_text(febio_material(material))
        material_lines.append(
            f"| {group} | {material.E_kPa:.4g} | {material.nu:g} | {len(material.g)} | {how} |"
        )

    n_poor = sum(1 for r in good if r.fit.quality != "good")
    metrics: dict[str, float | list[float]] = {
        "n_curves": float(len(result.rows)),
        "n_fitted": float(len(good)),
        "n_failed": float(len(result.rows) - len(good)),
        "n_poor": float(n_poor),
    }
    checks = []
    if inp.known_moduli is not None:
        known = _known(_inside(case_dir, Path(inp.known_moduli), "inputs.known_moduli"))
        errors = [
            abs(r.fit.E_kPa / known[key] - 1)
            for r in good
            if (key := Path(r.file).relative_to(case_dir).as_posix()) in known
        ]
        worst = 100 * max(errors) if errors else 100.0  # none fitted: count as 100 % off
        metrics["max_known_error_pct"] = worst
        checks.append(
            Check(
                f"every curve with a known modulus fitted, within {inp.known_tolerance_pct:g} %",
                worst,
                bool(errors) and len(errors) == len(known) and worst < inp.known_tolerance_pct,
                f"< {inp.known_tolerance_pct:g} %, all {len(known)} fitted",
                unit="%",
            )
        )

    stats = "\n".join(
        f"| {g} | {v.size} | {v.mean():.3f} +- {_sd(v):.3f} |" for g, v in by_group.items()
    )
    failed = "\n".join(
        f"* `{Path(r.file).relative_to(case_dir).as_posix()}`: {r.error}" for r in result.failures
    )
    links = "\n".join(
        f"* [{Path(r.file).name}](curve_plots/{plot_name(r)}): E = {r.fit.E_kPa:.4g} kPa, "
        f"{r.fit.quality}"
        for r in good
        if plot_name(r) in plots
    )
    contact = f", contact by {inp.contact_method}" if inp.analysis == "default" else ""
    sections = [
        (
            "Moduli per group (mean +- SD, kPa)",
            f"{len(good)} of {len(result.rows)} curves fitted ({inp.model}, nu = {inp.nu:g}, "
            f"{inp.analysis} analysis{contact}); every row is in `fits.csv`.\n\n"
            "| group | n | E [kPa] |\n|---|---|---|\n" + stats,
        ),
        ("Curves not fitted (skipped)", failed or "none"),
        (
            "Material files",
            "| group | E [kPa] | nu | Prony terms | from |\n|---|---|---|---|---|\n"
            + "\n".join(material_lines)
            + "\n\nEach as `material_<group>.toml` (read by the FE cases), "
            "`material_<group>_ansys.inp` and `material_<group>_febio.xml`.",
        ),
        ("Curve plots", links or "none"),
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)
