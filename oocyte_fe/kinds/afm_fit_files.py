"""Case kind ``afm_fit_files``: the user's own curve files -> fit table -> material files.

The whole user route without Python: a folder (or glob) of curve files inside the case folder,
the tip model, nu, the cantilever calibration where the files lack it (globally or per file
pattern), the fit range and contact method, groups (by subfolder or pattern) and an optional
creep file per group. Writes ``fits.csv`` (one row per curve, with its rating and why, refused
curves with their error; columns in :data:`afm.batch.COLUMNS`), a plot per curve (refused ones
showing why), a strip plot and mean +- SD per group over the curves rated good (poor ones
only with ``include_poor``), a modulus map per force-map file, and per group
``material_<group>.toml`` with its ANSYS and FEBio blocks. The run ends with "done: N fitted,
M poor, K refused".
"""

from __future__ import annotations

import csv
import fnmatch
import math
import os
import re
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator

from afm import plotting
from afm.batch import (
    COLUMNS,
    BatchResult,
    BatchRow,
    GroupStats,
    curve_files,
    fit_batch,
    write_batch_table,
)
from afm.creep import fit_creep_tip
from afm.curve_io import read_creep
from afm.curve_plots import plot_curves, plot_name
from afm.fe_export import ansys_prony_block, febio_material
from afm.fit import FitRange
from afm.material_file import MaterialFile, write_material
from afm.models import MODELS
from afm.nanite_pipeline import fit_nanite_default
from oocyte_fe.checks import inside, regular_file
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.data_templates import KNOWN_MODULI
from oocyte_fe.runner.casefile import DataFile
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs


class Calibration(CaseInputs):
    """Cantilever calibration for the files of one pattern (overrides the files' own)."""

    spring_constant_N_per_m: float | None = Field(
        None, gt=0, description="spring constant", json_schema_extra={"unit": "N/m"}
    )
    sensitivity_nm_per_V: float | None = Field(
        None,
        gt=0,
        description="deflection sensitivity (for deflection recorded in volts)",
        json_schema_extra={"unit": "nm/V"},
    )


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
    spring_constant_N_per_m: float | None = Field(
        None,
        gt=0,
        description="spring constant for every file (overrides the files' own; needed for "
        "files without one, e.g. AFM-Workshop CSV, NT-MDT)",
        json_schema_extra={"unit": "N/m"},
    )
    sensitivity_nm_per_V: float | None = Field(
        None,
        gt=0,
        description="deflection sensitivity for every file (overrides the files' own)",
        json_schema_extra={"unit": "nm/V"},
    )
    calibration: dict[str, Calibration] = Field(
        default_factory=dict,
        description="glob pattern on the file path relative to the case folder -> "
        "{ spring_constant_N_per_m, sensitivity_nm_per_V } for those files (first match; "
        "over the global values)",
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
    half_angle_deg_creep: float | None = Field(
        None,
        gt=0,
        lt=90,
        description="cone half angle of the creep probe when it differs from the curves' tip "
        "(default: the creep fit uses the curves' model and geometry)",
        json_schema_extra={"unit": "deg"},
    )
    include_poor: bool = Field(
        False,
        description="keep fits rated poor in the group means and material files (default: "
        "left out, counted as n_poor)",
    )
    curve_plots: Literal["all", "poor", "none"] = Field(
        "all",
        description="per-curve figures: every curve, only the poor and refused ones, or none "
        "(large force maps)",
    )
    known_moduli: str | None = Field(
        None,
        description="optional CSV (file, E_kPa) of known moduli to check the fits against, "
        "relative to the case folder",
        json_schema_extra=KNOWN_MODULI,
    )
    known_tolerance_pct: float = Field(
        5.0, gt=0, description="largest error against known_moduli", json_schema_extra={"unit": "%"}
    )

    @field_validator("known_moduli")
    @classmethod
    def _known_moduli_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        """A known-moduli file must exist inside the case folder (checked at ``validate``;
        a plain string, not a data file, so ``oocyte-fe new`` leaves it out)."""
        case_dir = (info.context or {}).get("case_dir")
        if value is None or case_dir is None:
            return value
        where = Path(case_dir) / "case.toml"
        try:
            regular_file(inside(value, case_dir, where, "inputs.known_moduli"))
        except InputError as exc:
            raise ValueError(exc.expected + ("" if exc.got is None else f" ({exc.got})")) from None
        return value

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


WORKERS = min(2, os.cpu_count() or 1)
"""Processes fitting the curves and drawing the per-curve plots (the machine's 2 cores)."""

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


def _reason(row: BatchRow) -> str:
    """A refused row's error without the file name it starts with (the list names it)."""
    return re.sub(rf"^{re.escape(row.file)}( \(curve \d+\))?: ", "", row.error)


def _sd(value: float) -> str:
    """An SD for a table: ``n/a`` where it is not defined (n = 1)."""
    return f"{value:.3g}" if math.isfinite(value) else "n/a"


def read_options(inp: FitFilesInputs, case_dir: Path) -> Callable[[Path], dict[str, object]]:
    """Reader keywords of each file: the height channel and the calibration (the first
    ``calibration`` pattern matching the file's path relative to ``case_dir``, then the
    global ``spring_constant_N_per_m`` / ``sensitivity_nm_per_V``)."""

    def options(file: Path) -> dict[str, object]:
        relative = file.relative_to(case_dir).as_posix()
        match = next((c for p, c in inp.calibration.items() if fnmatch.fnmatch(relative, p)), None)
        found: dict[str, object] = {}
        if inp.height_channel is not None:
            found["height_channel"] = inp.height_channel
        for key in ("spring_constant_N_per_m", "sensitivity_nm_per_V"):
            value = getattr(match, key) if match is not None else None
            value = getattr(inp, key) if value is None else value
            if value is not None:
                found[key] = value
        return found

    return options


def creep_tip(inp: FitFilesInputs, where: Path) -> tuple[str, dict[str, float]]:
    """Tip of the creep fit: the curves' model and geometry, or the cone of
    ``half_angle_deg_creep`` (only with a cone model: another tip has no half angle)."""
    if inp.half_angle_deg_creep is None:
        return inp.model, dict(inp.geometry)
    if inp.model != "sneddon_cone":
        raise InputError(
            where,
            "inputs.half_angle_deg_creep",
            f"left out with model = {inp.model!r} (the creep fit uses the curves' tip)",
            inp.half_angle_deg_creep,
        )
    return "sneddon_cone", {"half_angle_deg": inp.half_angle_deg_creep}


def _group_material(
    group: str, stats: GroupStats | None, inp: FitFilesInputs, ctx: CaseContext
) -> tuple[MaterialFile, str, str] | None:
    """(material, how it was made, E_inf text), or None for a group with no fit to average
    and no creep record."""
    creep_file = inp.creep.get(group)
    if creep_file is None:
        if stats is None or stats.n == 0:
            return None
        source = (
            f"afm_fit_files case: mean of {stats.n} {inp.model} fits rated "
            f"{'good or poor' if inp.include_poor else 'good'} "
            f"({stats.mean_kPa:.4g} +- {_sd(stats.sd_kPa)} kPa), elastic"
        )
        return MaterialFile(group, source, stats.mean_kPa, inp.nu), "elastic (mean E)", "-"
    model, geometry = creep_tip(inp, ctx.case_dir / "case.toml")
    fit = fit_creep_tip(read_creep(creep_file), model, geometry, inp.nu)
    figure = f"creep_{file_stem(group)}.png"
    plotting.plot_creep(fit, ctx.output(figure))
    tip = ", ".join(f"{k} {v:g}" for k, v in fit.geometry.items())
    source = (
        f"afm_fit_files case: creep {Path(creep_file).name}, Lee-Radok {model} ({tip}), "
        "Prony fit, exact relaxation series"
    )
    how = f"creep Prony fit, {model} ({tip}): {fit.quality}; [J(t), G(t)]({figure})"
    return fit.material(group, source), how, f"{fit.E_inf_kPa:.4g}"


def _fit_range_text(inp: FitFilesInputs) -> str:
    if inp.analysis == "nanite":
        return "whole approach"
    parts = []
    if inp.max_indentation_um is not None:
        parts.append(f"to {inp.max_indentation_um:g} um past contact")
    if inp.max_force_fraction is not None:
        parts.append(f"to {inp.max_force_fraction:g} of the peak force")
    return " and ".join(parts) or "whole approach"


ANALYSES = {
    "default": "afm.fit.fit_indentation: baseline line (offset and tilt) fitted before contact "
    "and removed; every point of the fit window weighted equally; contact point free",
    "nanite": "afm.nanite_pipeline.fit_nanite_default, nanite's default: constant offset, "
    "free baseline in the fit, residuals within 1 um of contact weighted down",
}
"""What each ``analysis`` does, for the report and ``fits.csv``."""

WHY_NOT_NANITE = (
    "The default analysis weights every point equally, where nanite weights the residuals "
    "within 1 um of the contact point down (by |x - x0| / 1 um): nanite's fit can then settle "
    "on a contact point up the rise, where its model misses the start of contact (up to 9x "
    "higher E on some instrument files; docs/afm.md, 'The default analysis against nanite'). "
    'Set analysis = "nanite" to reproduce a nanite/PyJibe analysis.'
)


@case_kind("afm_fit_files", inputs=FitFilesInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fit every curve file of the case folder; table, plots, statistics, material files."""
    inp: FitFilesInputs = ctx.inputs  # type: ignore[assignment]
    case_dir = ctx.case_dir
    where = case_dir / "case.toml"
    files = find_curve_files(case_dir, inp.curves)
    for group, file in inp.creep.items():
        _inside(case_dir, Path(file), f"inputs.creep.{group}")
    if inp.creep:
        creep_tip(inp, where)  # refuse a bad creep tip before fitting

    ctx.step(f"fitting {len(files)} files")
    fit_options: dict[str, object] = {"model": inp.model, "geometry": inp.geometry, "nu": inp.nu}
    if inp.analysis == "nanite":
        fit_range = (inp.max_indentation_um, inp.max_force_fraction)
        if fit_range != (None, None) or inp.contact_method != "fit":
            raise InputError(
                where,
                "inputs.analysis",
                'no fit range and contact_method = "fit" with analysis = "nanite" (it fits '
                "the whole approach, contact point free)",
                inp.analysis,
            )
        fit_options["fit_function"] = fit_nanite_default
    else:
        fit_options["fit_range"] = FitRange(inp.max_indentation_um, inp.max_force_fraction)
        fit_options["contact_method"] = inp.contact_method
    result = fit_batch(
        files,
        read_options=read_options(inp, case_dir),
        workers=WORKERS,
        progress=lambda done, total: ctx.progress(done, total, "curves fitted"),
        **fit_options,
    )
    _regroup(result, case_dir, inp.groups)
    fitted = [r for r in result.rows if r.fit is not None and not r.error]
    n_poor = sum(1 for r in fitted if not r.good)
    done = f"done: {len(fitted)} fitted, {n_poor} poor, {len(result.rows) - len(fitted)} refused"

    ctx.step("plots")
    plot_dir = ctx.output("curve_plots/.keep").parent
    plots = {p.name for p in plot_curves(result, plot_dir, workers=WORKERS, which=inp.curve_plots)}
    links = {
        i: f"curve_plots/{plot_name(r)}" for i, r in enumerate(result.rows) if plot_name(r) in plots
    }
    write_batch_table(
        result, ctx.output("fits.csv"), case_dir, links, inp.analysis, _fit_range_text(inp)
    )
    stats = {s.group: s for s in result.stats(inp.include_poor) if s.quantity == "E_kPa"}
    groups = sorted(stats)
    figures = []
    if fitted:
        by_group = {g: [r.fit for r in fitted if r.group == g] for g in groups}
        plotting.plot_strip(by_group, ctx.output("moduli.png"), inp.include_poor)
        figures.append(Figure("moduli.png", "Fitted Young's moduli per group (log axis)"))
    map_files = sorted({r.file for r in result.rows if r.map_position_um is not None})
    for file in map_files:
        name = f"modulus_map_{Path(file).stem}.png"
        plotting.plot_modulus_map(result, file, ctx.output(name))
        figures.append(Figure(name, f"Modulus map of {Path(file).name}"))

    ctx.step("material files")
    unknown = sorted(set(inp.creep) - set(groups))
    if unknown:
        raise InputError(
            where,
            f"inputs.creep.{unknown[0]}",
            f"a group of the fitted curves (one of {', '.join(groups) or 'none'})",
        )
    material_lines = []
    for group in groups:
        made = _group_material(group, stats.get(group), inp, ctx)
        if made is None:
            material_lines.append(f"| {group} | - | - | - | - | none: no fit rated good |")
            continue
        material, how, e_inf = made
        stem = f"material_{file_stem(group)}"
        write_material(material, ctx.output(f"{stem}.toml"))
        ctx.output(f"{stem}_ansys.inp").write_text(ansys_prony_block(material))
        ctx.output(f"{stem}_febio.xml").write_text(febio_material(material))
        material_lines.append(
            f"| {group} | {material.E_kPa:.4g} | {e_inf} | {material.nu:g} | {len(material.g)} "
            f"| {how} |"
        )

    metrics: dict[str, float | list[float]] = {
        "n_curves": float(len(result.rows)),
        "n_fitted": float(len(fitted)),
        "n_failed": float(len(result.rows) - len(fitted)),
        "n_poor": float(n_poor),
    }
    checks = [
        Check(
            done,
            float(len(fitted)),
            bool(fitted),
            "at least one curve fitted",
            unit="curves",
        )
    ]
    if inp.known_moduli is not None:
        field = "inputs.known_moduli"
        known_file = regular_file(inside(inp.known_moduli, case_dir, where, field), field)
        known = _known(known_file)
        errors = [
            abs(r.fit.E_kPa / known[key] - 1)
            for r in fitted
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
    ctx.step(done)

    used = "fits rated good or poor" if inp.include_poor else "fits rated good"
    poor_left_out = "are left out (include_poor = true keeps them)"
    table = "\n".join(
        f"| {s.group} | {s.n} | {s.n_poor} | "
        + (f"{s.mean_kPa:.4g} +- {_sd(s.sd_kPa)} |" if s.n else "- |")
        for s in stats.values()
    )
    failed = "\n".join(
        f"* `{Path(r.file).relative_to(case_dir).as_posix()}`"
        + ("" if r.curve_index is None else f" curve {r.curve_index}")
        + (f" ([plot](curve_plots/{plot_name(r)}))" if plot_name(r) in plots else "")
        + f": {_reason(r)}"
        for r in result.failures
    )
    plot_links = "\n".join(
        f"* [{Path(r.file).name}"
        + ("" if r.curve_index is None else f" curve {r.curve_index}")
        + f"](curve_plots/{plot_name(r)}): E = {r.fit.E_kPa:.4g} kPa, {r.fit.rating}"
        for r in fitted
        if plot_name(r) in plots
    )
    contact = f", contact by {inp.contact_method}" if inp.analysis == "default" else ""
    analysis = f"**{inp.analysis}**: {ANALYSES[inp.analysis]}."
    if inp.analysis == "default":
        analysis += " " + WHY_NOT_NANITE
    columns = "\n".join(f"* `{name}`: {text}" for name, text in COLUMNS.items())
    sections = [
        ("Result", f"{done} ({len(result.rows)} curves in {len(files)} files)."),
        (
            "Moduli per group (mean +- SD, kPa)",
            f"Over the {used} ({inp.model}, nu = {inp.nu:g}, {inp.analysis} analysis"
            f"{contact}; fit range: {_fit_range_text(inp)}); n_poor fits rated poor "
            f"{'are included' if inp.include_poor else poor_left_out}"
            "; SD n/a for n = 1. Every row is in `fits.csv`.\n\n"
            "| group | n | n_poor | E [kPa] |\n|---|---|---|---|\n" + table,
        ),
        ("Analysis", analysis),
        ("Curves refused (skipped)", failed or "none"),
        (
            "Material files",
            "| group | E0 [kPa] | E_inf [kPa] | nu | Prony terms | from |\n"
            "|---|---|---|---|---|---|\n"
            + "\n".join(material_lines)
            + "\n\nEach as `material_<group>.toml` (read by the FE cases), "
            "`material_<group>_ansys.inp` and `material_<group>_febio.xml`; a creep fit's "
            "rating (and any Prony term the record does not determine) is written into their "
            "source line.",
        ),
        ("Columns of fits.csv", columns),
        ("Curve plots", plot_links or "none"),
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)
