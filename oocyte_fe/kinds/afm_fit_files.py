"""Case kind ``afm_fit_files``: the user's own curve files -> fit table -> material files.

The whole user route without Python: a folder (or glob) of curve files inside the case folder,
the tip model, nu, the cantilever calibration where the files lack it (globally or per file
pattern), the fit range and contact method, groups (by subfolder or pattern) and an optional
creep file per group. Writes ``fits.csv`` (one row per curve, with its rating and why, refused
curves with their error; columns in :data:`afm.batch.COLUMNS`), a plot per curve (refused ones
showing why), a strip plot and mean +- SD per group over the curves rated good (poor ones
only with ``include_poor``), a modulus map per force-map file, and per group
``material_<group>.toml`` with its ANSYS and FEBio blocks. The run ends with "done: N fitted,
M poor, K refused". With ``viscoelastic`` every ramp is also fitted in time (Ting's method;
its columns in ``fits.csv``, F(t) figures, a group's material from its joint fit). With
``correction`` every modulus is also corrected for the sample's shape (shelled oocyte, bonded
layer; :mod:`~oocyte_fe.kinds.afm_fit_files_correction`): a column beside the apparent one,
and the groups' statistics and materials from the corrected moduli. With ``pierce`` (true, or
the groups it names) those curves are pierce-through curves, fitted per layer (ZP, cytoplasm;
:mod:`~oocyte_fe.kinds.afm_fit_files_pierce`), beside plain curves of the other groups.

Inputs and what they name: :mod:`~oocyte_fe.kinds.afm_fit_files_inputs`; the fits, groups and
materials: :func:`afm.fit_files.fit_files`; the outputs:
:mod:`~oocyte_fe.kinds.afm_fit_files_report`.
"""

from __future__ import annotations

import os

from afm.fit_files import fit_files, read_known_moduli
from oocyte_fe.kinds.afm_fit_files_args import (
    creep_records,
    find_curve_files,
    fit_options,
    known_moduli_file,
    pierce_options,
    read_options,
)
from oocyte_fe.kinds.afm_fit_files_correction import add_correction_columns, correction
from oocyte_fe.kinds.afm_fit_files_inputs import METRICS, FitFilesInputs
from oocyte_fe.kinds.afm_fit_files_pierce import no_pierce
from oocyte_fe.kinds.afm_fit_files_ramps import ramp_metrics
from oocyte_fe.kinds.afm_fit_files_report import sections, write_fits, write_materials
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, case_kind

WORKERS = min(2, os.cpu_count() or 1)
"""Processes fitting the curves and drawing the per-curve plots (the machine's 2 cores)."""


@case_kind("afm_fit_files", inputs=FitFilesInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Fit every curve file of the case folder; table, plots, statistics, material files."""
    inp: FitFilesInputs = ctx.inputs  # type: ignore[assignment]
    case_dir = ctx.case_dir
    files = find_curve_files(case_dir, inp.curves)
    creep = creep_records(inp, case_dir)  # refuses a bad creep tip before fitting
    pierced = pierce_options(inp, case_dir / "case.toml")  # its refusals first, as validate
    options = fit_options(inp, case_dir / "case.toml")
    corrected_by = correction(inp, case_dir / "case.toml")  # refused before fitting
    known_file = known_moduli_file(inp, case_dir)
    known = None if known_file is None else read_known_moduli(known_file)

    ctx.step(f"fitting {len(files)} files")
    result = fit_files(
        files,
        inp.model,
        inp.geometry,
        inp.nu,
        case_dir,
        fit_options=options,
        read_options=read_options(inp, case_dir),
        groups=inp.groups,
        pierce=inp.pierce,
        pierce_options=pierced,
        creep=creep,
        include_poor=inp.include_poor,
        known_moduli=known,
        viscoelastic=None if inp.viscoelastic is None else inp.viscoelastic.options(),
        correction=corrected_by,
        workers=WORKERS,
        progress=lambda done, total: ctx.progress(done, total, "curves fitted"),
    )
    ctx.step("plots")
    figures, plots = write_fits(result, inp, ctx.output, case_dir, WORKERS)
    add_correction_columns(ctx.output("fits.csv"), result)
    ctx.step("material files")
    material_rows = write_materials(result, inp, ctx.output)

    n_fitted = len(result.fitted)
    metrics: dict[str, float | list[float]] = {
        "n_curves": float(len(result.batch.rows)),
        "n_fitted": float(n_fitted),
        "n_failed": float(result.n_refused),
        "n_poor": float(result.n_poor),
        **ramp_metrics(result),
        **({"n_no_pierce": float(no_pierce(result))} if inp.pierce else {}),
    }
    checks = [
        Check(
            result.summary,
            float(n_fitted),
            bool(n_fitted),
            "at least one curve fitted",
            unit="curves",
        )
    ]
    worst = result.max_known_error_pct
    if worst is not None:
        tolerance = inp.known_tolerance_pct
        metrics["max_known_error_pct"] = worst
        checks.append(
            Check(
                f"every curve with a known modulus fitted, within {tolerance:g} %",
                worst,
                result.known_within(tolerance),
                f"< {tolerance:g} %, all {result.n_known} fitted",
                unit="%",
            )
        )
    ctx.step(result.summary)
    report = sections(result, inp, case_dir, len(files), plots, material_rows)
    return CaseOutcome(metrics=metrics, figures=figures, sections=report, checks=checks)
