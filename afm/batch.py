"""Batch fitting: a folder of curves -> one row per curve, and mean +- SD per group.

A file that cannot be read, or a curve that cannot be fitted, is recorded with its one-line
error and skipped; the batch goes on. A force map gives one row per curve, with its index and
map position. Every row names the height channel its tip position came from. Groups come from
each curve's ``group`` (the file's ``# group =`` metadata, or its folder name). Statistics:
arithmetic mean and sample SD (ddof = 1) over the good fits.
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from afm.curve import ForceCurve
from afm.curve_io import TEXT_SUFFIXES, read_curves
from afm.fit import IndentationFit, fit_indentation
from afm.instrument_io import INSTRUMENT_SUFFIXES
from afm.pierce import PierceFit, fit_pierce
from oocyte_fe.errors import InputError, MissingExtraError


@dataclass(frozen=True)
class BatchRow:
    """One curve of a batch: its fitted moduli (``zp`` only for plain curves) or its error.

    ``curve_index`` and ``map_position_um`` (x, y) are set for the curves of a force map.
    """

    file: str
    group: str
    fit: IndentationFit | None = None
    cytoplasm: IndentationFit | None = None
    error: str = ""
    height_channel: str = ""
    curve_index: int | None = None
    map_position_um: tuple[float, float] | None = None


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

    def map_rows(self, file: str | Path) -> list[BatchRow]:
        """The rows of one force-map file that carry a map position (fitted or not)."""
        return [r for r in self.rows if r.file == str(file) and r.map_position_um is not None]

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
        raise InputError(folder, "", "a folder of curve files")
    suffixes = TEXT_SUFFIXES | INSTRUMENT_SUFFIXES
    files = sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix.lower() in suffixes)
    if not files:
        raise InputError(folder, "", f"curve files ({', '.join(sorted(suffixes))})")
    return files


def _fit_row(
    file: Path,
    curve: ForceCurve,
    pierce: bool,
    fit_function: Callable[..., IndentationFit],
    fit_options: Mapping[str, object],
) -> BatchRow:
    where = {
        "height_channel": curve.height_channel,
        "curve_index": curve.curve_index,
        "map_position_um": curve.map_position_um,
    }
    group = curve.group or file.parent.name
    try:
        if pierce:
            both: PierceFit = fit_pierce(curve, **fit_options)
            return BatchRow(str(file), group, both.zp, both.cytoplasm, **where)
        return BatchRow(str(file), group, fit_function(curve, **fit_options), **where)
    except (InputError, ValueError, FloatingPointError) as exc:
        return BatchRow(str(file), group, error=str(exc).splitlines()[0], **where)


def fit_batch(
    files: Sequence[str | Path],
    pierce: bool = False,
    reader: Callable[..., ForceCurve | Sequence[ForceCurve]] = read_curves,
    read_options: Mapping[str, object] | None = None,
    fit_function: Callable[..., IndentationFit] = fit_indentation,
    **fit_options: object,
) -> BatchResult:
    """Fit every curve of every file (``fit_pierce`` when ``pierce``, else ``fit_function``:
    :func:`afm.fit.fit_indentation`, or :func:`afm.nanite_pipeline.fit_nanite_default` for
    nanite's analysis).

    ``reader(file, **read_options)`` returns one curve or a list (a force map: one row per
    curve); the default :func:`afm.curve_io.read_curves` takes ``spring_constant_N_per_m``,
    ``sensitivity_nm_per_V`` and ``height_channel``. ``fit_options`` go to the fit function
    (model, geometry, nu, fit range, contact method). A file that cannot be read is one error
    row; a missing optional dependency is not a curve error and is raised.
    """
    result = BatchResult()
    options = dict(read_options or {})
    for file in map(Path, files):
        try:
            read = reader(file, **options)
        except MissingExtraError:
            raise
        except (InputError, ValueError, FloatingPointError) as exc:
            result.rows.append(
                BatchRow(str(file), file.parent.name, error=str(exc).splitlines()[0])
            )
            continue
        curves = [read] if isinstance(read, ForceCurve) else list(read)
        result.rows.extend(
            _fit_row(file, curve, pierce, fit_function, fit_options) for curve in curves
        )
    return result


def write_batch_table(
    result: BatchResult,
    path: str | Path,
    relative_to: str | Path | None = None,
    plot_links: Mapping[int, str] | None = None,
) -> Path:
    """One CSV row per curve: moduli, contact points, R^2, residual, quality, height channel,
    map index and position, error.

    File names are written relative to ``relative_to`` when given. ``plot_links`` (row index ->
    path of the row's plot) adds a ``plot`` column before ``error``.
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
        "height_channel",
        "curve_index",
        "map_x_um",
        "map_y_um",
        *(["plot"] if plot_links is not None else []),
        "error",
    ]
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(header)
        for i, r in enumerate(result.rows):
            f, c, pos = r.fit, r.cytoplasm, r.map_position_um
            name = Path(r.file).relative_to(relative_to).as_posix() if relative_to else r.file
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
                    r.height_channel,
                    "" if r.curve_index is None else r.curve_index,
                    f"{pos[0]:.6g}" if pos else "",
                    f"{pos[1]:.6g}" if pos else "",
                    *([plot_links.get(i, "")] if plot_links is not None else []),
                    r.error,
                ]
            )
    return path
