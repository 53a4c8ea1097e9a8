"""Batch fitting: a folder of curves -> one row per curve, and mean +- SD per group.

A curve that cannot be read or fitted is recorded with its one-line error and skipped; the
batch goes on. Groups come from each curve's ``group`` (the file's ``# group =`` metadata, or
its folder name). Statistics: arithmetic mean and sample SD (ddof = 1) over the good fits.
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from afm.curve import ForceCurve
from afm.curve_io import TEXT_SUFFIXES, read_curve
from afm.errors import AfmInputError, MissingExtraError
from afm.fit import IndentationFit, fit_indentation
from afm.pierce import PierceFit, fit_pierce

INSTRUMENT_SUFFIXES = {".jpk-force", ".ibw", ".jpk-force-map", ".jpk-qi-data", ".h5"}


@dataclass(frozen=True)
class BatchRow:
    """One curve of a batch: its fitted moduli (``zp`` only for plain curves) or its error."""

    file: str
    group: str
    fit: IndentationFit | None = None
    cytoplasm: IndentationFit | None = None
    error: str = ""


@dataclass(frozen=True)
class GroupStats:
    """Mean and sample SD of one modulus over the good fits of a group."""

    group: str
    quantity: str
    n: int
    mean_kPa: float
    sd_kPa: float


@dataclass
class BatchResult:
    """All rows of a batch, in file order."""

    rows: list[BatchRow] = field(default_factory=list)

    @property
    def failures(self) -> list[BatchRow]:
        return [r for r in self.rows if r.error]

    def stats(self) -> list[GroupStats]:
        """Mean +- SD of E (and of the cytoplasm's E for pierce curves) per group."""
        out = []
        for group in sorted({r.group for r in self.rows}):
            rows = [r for r in self.rows if r.group == group and not r.error]
            for quantity, attr in (("E_kPa", "fit"), ("E_cytoplasm_kPa", "cytoplasm")):
                values = np.array([getattr(r, attr).E_kPa for r in rows if getattr(r, attr)])
                if values.size:
                    sd = float(np.std(values, ddof=1)) if values.size > 1 else float("nan")
                    out.append(GroupStats(group, quantity, values.size, float(values.mean()), sd))
        return out


def curve_files(folder: str | Path) -> list[Path]:
    """Curve files under ``folder`` (recursively): text tables and instrument files."""
    folder = Path(folder)
    if not folder.is_dir():
        raise AfmInputError(folder, "", "a folder of curve files")
    suffixes = TEXT_SUFFIXES | INSTRUMENT_SUFFIXES
    files = sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix.lower() in suffixes)
    if not files:
        raise AfmInputError(folder, "", f"curve files ({', '.join(sorted(suffixes))})")
    return files


def fit_batch(
    files: Sequence[str | Path],
    pierce: bool = False,
    reader: Callable[[Path], ForceCurve] = read_curve,
    **fit_options: object,
) -> BatchResult:
    """Fit every file (``fit_pierce`` when ``pierce``, else ``fit_indentation``).

    ``fit_options`` go to the fit function (model, geometry, nu, fit range, contact method).
    A missing optional extra (instrument files without afmformats) is not a curve error and
    is raised.
    """
    result = BatchResult()
    for file in map(Path, files):
        group = file.parent.name
        try:
            curve = reader(file)
            group = curve.group or group
            if pierce:
                both: PierceFit = fit_pierce(curve, **fit_options)
                row = BatchRow(str(file), group, both.zp, both.cytoplasm)
            else:
                row = BatchRow(str(file), group, fit_indentation(curve, **fit_options))
        except MissingExtraError:
            raise
        except (AfmInputError, ValueError, FloatingPointError) as exc:
            row = BatchRow(str(file), group, error=str(exc).splitlines()[0])
        result.rows.append(row)
    return result


def write_batch_table(
    result: BatchResult, path: str | Path, relative_to: str | Path | None = None
) -> Path:
    """One CSV row per curve: moduli, contact points, R^2, residual, quality, error.

    File names are written relative to ``relative_to`` when given.
    """
    path = Path(path)
    header = [
        "file",
        "group",
        "E_kPa",
        "contact_point_um",
        "r_squared",
        "residual_rms_nN",
        "quality",
        "E_cytoplasm_kPa",
        "cytoplasm_contact_um",
        "cytoplasm_r_squared",
        "contact_method",
        "error",
    ]
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(header)
        for r in result.rows:
            f, c = r.fit, r.cytoplasm
            name = Path(r.file).relative_to(relative_to) if relative_to else r.file
            writer.writerow(
                [
                    str(name),
                    r.group,
                    f"{f.E_kPa:.6g}" if f else "",
                    f"{f.contact_point_um:.6g}" if f else "",
                    f"{f.r_squared:.6f}" if f else "",
                    f"{f.residual_rms_nN:.4g}" if f else "",
                    f.quality if f else "error",
                    f"{c.E_kPa:.6g}" if c else "",
                    f"{c.contact_point_um:.6g}" if c else "",
                    f"{c.r_squared:.6f}" if c else "",
                    f.contact_method if f else "",
                    r.error,
                ]
            )
    return path
