"""Batch fitting: a folder of curves -> one row per curve, and mean +- SD per group.

A file that cannot be read, or a curve that cannot be fitted, is recorded with its one-line
error and skipped; the batch goes on. A force map gives one row per curve, with its index and
map position. Every row names the height channel its tip position came from. A row's group is
the first glob pattern of ``groups`` matching its file's path, else the curve's ``group`` (the
file's ``# group =`` metadata), else its folder name (:meth:`CurveFitting.group`); ``pierce``
names the groups whose curves are pierce-through curves (:func:`afm.pierce.fit_pierce`), or
all (true) or none (false). Statistics:
arithmetic mean and sample SD (ddof = 1) over the fits rated good (poor ones only when asked);
the SD of a single value is not defined (NaN, "n/a" in tables).
"""

from __future__ import annotations

import csv
import fnmatch
import math
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from afm.curve import ForceCurve
from afm.curve_io import TEXT_SUFFIXES, count_curves, iter_curves
from afm.fit import IndentationFit, fit_indentation
from afm.instrument_io import INSTRUMENT_SUFFIXES
from afm.pierce import PierceFit, fit_pierce
from oocyte_fe.errors import InputError, MissingExtraError

CHUNK_CURVES = 64
"""Curves sent to a fitting process at a time; a batch of fewer is fitted in this process."""


@dataclass(frozen=True)
class BatchRow:
    """One curve of a batch: its fitted moduli (``zp`` only for plain curves) or its error.

    ``curve_index`` and ``map_position_um`` (x, y) are set for the curves of a force map;
    ``curve`` is the curve as read, kept for a curve that could not be fitted (for its plot).
    """

    file: str
    group: str
    fit: IndentationFit | None = None
    cytoplasm: IndentationFit | None = None
    error: str = ""
    height_channel: str = ""
    curve_index: int | None = None
    map_position_um: tuple[float, float] | None = None
    spring_constant_N_per_m: float | None = None
    curve: ForceCurve | None = None

    @property
    def good(self) -> bool:
        """Fitted and rated good (the cytoplasm too, for a pierce-through curve)."""
        fits = [f for f in (self.fit, self.cytoplasm) if f is not None]
        return bool(fits) and not self.error and all(f.quality == "good" for f in fits)


@dataclass(frozen=True)
class GroupStats:
    """Mean and sample SD of one modulus over the fits of a group that enter statistics.

    ``n`` fits entered; ``n_poor`` fits were rated poor (left out unless asked for);
    ``sd_kPa`` is NaN for n = 1.
    """

    group: str
    quantity: str
    n: int
    n_poor: int
    mean_kPa: float
    sd_kPa: float

    @property
    def mean_sd_text(self) -> str:
        """``mean +- SD`` for a table (kPa, 4 and 3 significant digits; SD ``n/a`` for n = 1)."""
        sd = f"{self.sd_kPa:.3g}" if math.isfinite(self.sd_kPa) else "n/a"
        return f"{self.mean_kPa:.4g} +- {sd}"


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

    def stats(self, include_poor: bool = False) -> list[GroupStats]:
        """Mean +- SD of E (and of the cytoplasm's E for pierce curves) per group.

        Fits rated poor are left out (counted in ``n_poor``) unless ``include_poor``. A group
        whose fits are all poor has n = 0 and NaN mean and SD.
        """
        out = []
        for group in sorted({r.group for r in self.rows}):
            rows = [r for r in self.rows if r.group == group and not r.error]
            for quantity, attr in (("E_kPa", "fit"), ("E_cytoplasm_kPa", "cytoplasm")):
                fits = [getattr(r, attr) for r in rows if getattr(r, attr) is not None]
                if not fits:
                    continue
                used = [f for f in fits if include_poor or f.quality == "good"]
                values = np.array([f.E_kPa for f in used])
                mean = float(values.mean()) if values.size else float("nan")
                sd = float(np.std(values, ddof=1)) if values.size > 1 else float("nan")
                n_poor = sum(f.quality != "good" for f in fits)
                out.append(GroupStats(group, quantity, values.size, n_poor, mean, sd))
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


def pattern_group(relative: str, patterns: Mapping[str, str]) -> str | None:
    """The group of the first glob pattern (group -> pattern) matching ``relative`` (a curve
    file's path, ``/``-separated), or None."""
    return next((g for g, p in patterns.items() if fnmatch.fnmatch(relative, p)), None)


@dataclass(frozen=True)
class CurveFitting:
    """How each curve of a batch gets its group and its fit (sent to the fitting processes).

    ``groups`` (group -> glob on the file's path relative to ``relative_to``, the first
    matching) name a file's group; ``pierce`` is true (every curve), false (none) or the
    groups whose curves are fitted by :func:`afm.pierce.fit_pierce` with ``pierce_options``;
    the other curves by ``fit_function`` with ``fit_options``.
    """

    fit_function: Callable[..., IndentationFit]
    fit_options: Mapping[str, object]
    pierce: bool | frozenset[str] = False
    pierce_options: Mapping[str, object] = field(default_factory=dict)
    groups: Mapping[str, str] = field(default_factory=dict)
    relative_to: Path | None = None

    def group(self, file: Path, curve: ForceCurve | None = None) -> str:
        """The group of a curve of ``file`` (``curve`` None: a file that could not be read):
        the first pattern of ``groups`` matching the file's path relative to ``relative_to``,
        else the curve's own ``group``, else the file's folder name."""
        found = None
        if self.groups:
            relative = file if self.relative_to is None else file.relative_to(self.relative_to)
            found = pattern_group(relative.as_posix(), self.groups)
        return found or (curve.group if curve is not None else "") or file.parent.name

    def is_pierce(self, group: str) -> bool:
        """Whether the curves of ``group`` are fitted as pierce-through curves."""
        return self.pierce if isinstance(self.pierce, bool) else group in self.pierce

    def row(self, file: Path, curve: ForceCurve) -> BatchRow:
        """The fitted row of ``curve`` (of ``file``), or its error row."""
        where = {
            "height_channel": curve.height_channel,
            "curve_index": curve.curve_index,
            "map_position_um": curve.map_position_um,
            "spring_constant_N_per_m": curve.spring_constant_nN_per_um / 1e3,
        }
        group = self.group(file, curve)
        try:
            if self.is_pierce(group):
                both: PierceFit = fit_pierce(curve, **self.pierce_options)
                return BatchRow(str(file), group, both.zp, both.cytoplasm, **where)
            fit = self.fit_function(curve, **self.fit_options)
            _ = fit.rating  # rated in the fitting process; the cached rating travels with the fit
            return BatchRow(str(file), group, fit, **where)
        except (InputError, ValueError, FloatingPointError) as exc:
            return BatchRow(str(file), group, error=str(exc).splitlines()[0], curve=curve, **where)


ReadOptions = Mapping[str, object] | Callable[[Path], Mapping[str, object]]
"""Reader keywords for every file, or a function giving each file its own."""


def _fit_curves(jobs: list[tuple[Path, ForceCurve]], fitting: CurveFitting) -> list[BatchRow]:
    return [fitting.row(file, curve) for file, curve in jobs]


def _read_and_fit(
    file: Path, options: Mapping[str, object], selection: range, fitting: CurveFitting
) -> list[BatchRow]:
    """Rows of the curves ``selection`` of ``file``, read and fitted in this process."""
    try:
        curves = list(iter_curves(file, **options, selection=selection))
    except (InputError, ValueError, FloatingPointError) as exc:
        first = f"curves {selection.start}-{selection.stop - 1}: "
        return [BatchRow(str(file), fitting.group(file), error=first + str(exc).splitlines()[0])]
    return _fit_curves([(file, c) for c in curves], fitting)


def fit_batch(
    files: Sequence[str | Path],
    pierce: bool | Collection[str] = False,
    reader: Callable[..., ForceCurve | Iterable[ForceCurve]] = iter_curves,
    read_options: ReadOptions | None = None,
    fit_function: Callable[..., IndentationFit] = fit_indentation,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
    *,
    pierce_options: Mapping[str, object] | None = None,
    groups: Mapping[str, str] | None = None,
    relative_to: str | Path | None = None,
    **fit_options: object,
) -> BatchResult:
    """Fit every curve of every file: :func:`afm.pierce.fit_pierce` for the pierce-through
    curves (``pierce``: true for every curve, or the names of their groups), else
    ``fit_function`` (:func:`afm.fit.fit_indentation`, or
    :func:`afm.nanite_pipeline.fit_nanite_default` for nanite's analysis).

    A row's group is the first glob of ``groups`` (group -> pattern) matching its file's path
    relative to ``relative_to`` (the path as given without it), else the curve's ``group``
    (``# group =`` metadata), else the file's folder name (:meth:`CurveFitting.group`).

    ``reader(file, **options)`` returns one curve or several (a list, or an iterator taken
    as it is read; a force map gives one row per curve); ``options`` is ``read_options``, or
    ``read_options(file)`` when it is a function (per-file calibration). The default
    :func:`afm.curve_io.iter_curves` takes ``spring_constant_N_per_m``,
    ``sensitivity_nm_per_V`` and ``height_channel``. ``fit_options`` go to ``fit_function``
    (model, geometry, nu, fit range, contact method), ``pierce_options`` to ``fit_pierce``
    (model, geometry, nu, ``zp_range``, contact method, ``min_drop_fraction``; default
    ``fit_options``, for a batch of pierce-through curves only). A file that cannot be read
    is an error row (after the rows of the curves read before the error); a missing optional
    dependency is not a curve error and is raised.

    ``workers`` > 1 fits in that many processes, in chunks of ``CHUNK_CURVES`` curves sent
    off as they are read; with the default reader, a file whose curves can be counted
    without reading them (:func:`afm.curve_io.count_curves`: an afmformats HDF5 map) is
    read by the processes too, a chunk each. A batch of fewer curves is fitted here. Rows
    stay in file and curve order; ``fit_function`` must then be a module-level function.
    ``progress(done, total)`` is called as the fitted curves come back (counts of curves).
    """
    fitting = CurveFitting(
        fit_function,
        fit_options,
        pierce if isinstance(pierce, bool) else frozenset(pierce),
        fit_options if pierce_options is None else pierce_options,
        groups or {},
        None if relative_to is None else Path(relative_to),
    )
    segments: list[tuple[list[BatchRow] | Future, int]] = []  # rows (or their future), curves
    pending: list[tuple[Path, ForceCurve]] = []
    pool: ProcessPoolExecutor | None = None

    def processes() -> ProcessPoolExecutor:
        nonlocal pool
        pool = pool or ProcessPoolExecutor(max_workers=workers)
        return pool

    def send() -> None:
        jobs = pending.copy()
        pending.clear()
        if not jobs:
            return
        if workers > 1 and (pool is not None or len(jobs) >= CHUNK_CURVES):
            segments.append((processes().submit(_fit_curves, jobs, fitting), len(jobs)))
        else:
            segments.append((_fit_curves(jobs, fitting), len(jobs)))

    try:
        for file in map(Path, files):
            options = read_options(file) if callable(read_options) else dict(read_options or {})
            count = count_curves(file, **options) if workers > 1 and reader is iter_curves else None
            if count is not None and count >= CHUNK_CURVES:
                send()
                for start in range(0, count, CHUNK_CURVES):
                    part = range(start, min(start + CHUNK_CURVES, count))
                    future = processes().submit(_read_and_fit, file, options, part, fitting)
                    segments.append((future, len(part)))
                continue
            try:
                read = reader(file, **options)
                for curve in [read] if isinstance(read, ForceCurve) else read:
                    pending.append((file, curve))
                    if len(pending) >= CHUNK_CURVES:
                        send()
            except MissingExtraError:
                raise
            except (InputError, ValueError, FloatingPointError) as exc:
                send()
                error = str(exc).splitlines()[0]
                segments.append(([BatchRow(str(file), fitting.group(file), error=error)], 1))
        send()
        rows: list[BatchRow] = []
        done, total = 0, sum(size for _, size in segments)
        for segment, size in segments:
            rows += segment.result() if isinstance(segment, Future) else segment
            done += size
            if progress is not None:
                progress(done, total)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
    return BatchResult(rows)


COLUMNS = {
    "file": "curve file, relative to the case folder",
    "group": "group (subfolder, or the case's group pattern)",
    "E_kPa": "Young's modulus, kPa",
    "quality": "good, poor or error",
    "rating": "why: every figure the rating used (IndentationFit.rating), or the error",
    "model": "tip model key (afm.models)",
    "tip": "tip geometry of the model (half_angle_deg, radius_um, face_angle_deg)",
    "nu": "Poisson ratio assumed",
    "spring_constant_N_per_m": "cantilever spring constant used, N/m",
    "analysis": "default (afm.fit.fit_indentation) or nanite (afm.nanite_pipeline)",
    "fit_range": "points of the contact part fitted",
    "contact_method": "how the contact point was found",
    "contact_from_start_um": "tip travel from the curve's first point to the contact point, um",
    "max_indentation_um": "largest indentation fitted, um",
    "n_contact_points": "points in contact in the fit",
    "r_squared": "R^2 over the contact points",
    "residual_rms_nN": "RMS of the force residual over the fit window, nN",
    "E_cytoplasm_kPa": "cytoplasm modulus of a pierce-through curve, kPa",
    "cytoplasm_contact_from_start_um": "cytoplasm contact reference from the first point, um",
    "cytoplasm_r_squared": "R^2 of the cytoplasm fit",
    "height_channel": "recorded column the tip position came from",
    "curve_index": "index of the curve in a force-map file",
    "map_x_um": "map position x, um",
    "map_y_um": "map position y, um",
    "plot": "the curve's figure",
    "error": "why the curve could not be read or fitted",
}
"""Columns of :func:`write_batch_table` and what each holds (``plot`` only with plot links)."""


def _rating_text(fit: IndentationFit | None, cytoplasm: IndentationFit | None) -> str:
    """The fit's rating; for a pierce-through curve each layer's, named (``ZP good (...);
    cytoplasm poor: ...``)."""
    if cytoplasm is None:
        return "" if fit is None else fit.rating
    return f"ZP {'' if fit is None else fit.rating}; cytoplasm {cytoplasm.rating}"


def _from_start(fit: IndentationFit, start: IndentationFit) -> str:
    """``fit``'s contact point less the first tip position of ``start`` (same curve), um."""
    return f"{fit.contact_point_um - float(start.tip_position_um[0]):.6g}"


def write_batch_table(
    result: BatchResult,
    path: str | Path,
    relative_to: str | Path | None = None,
    plot_links: Mapping[int, str] | None = None,
    analysis: str = "default",
    fit_range: str = "whole approach",
) -> Path:
    """One CSV row per curve, the columns of :data:`COLUMNS`.

    File names are written relative to ``relative_to`` when given. ``plot_links`` (row index ->
    path of the row's plot) adds the ``plot`` column. ``analysis`` and ``fit_range`` name how
    the batch was fitted (the same for every row). The contact point is given as the tip
    travel from the curve's first point (``contact_from_start_um``, >= 0 for a contact inside
    the curve), not as the instrument's absolute height.
    """
    path = Path(path)
    header = [c for c in COLUMNS if c != "plot" or plot_links is not None]
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, header)
        writer.writeheader()
        for i, r in enumerate(result.rows):
            f, c, pos = r.fit, r.cytoplasm, r.map_position_um
            name = Path(r.file).relative_to(relative_to).as_posix() if relative_to else r.file
            quality = "error" if f is None or r.error else "good" if r.good else "poor"
            row = {
                "file": str(name),
                "group": r.group,
                "quality": quality,
                "rating": r.error or _rating_text(f, c),
                "analysis": analysis,
                "fit_range": fit_range,
                "height_channel": r.height_channel,
                "curve_index": "" if r.curve_index is None else r.curve_index,
                "map_x_um": f"{pos[0]:.6g}" if pos else "",
                "map_y_um": f"{pos[1]:.6g}" if pos else "",
                "spring_constant_N_per_m": (
                    f"{r.spring_constant_N_per_m:.6g}" if r.spring_constant_N_per_m else ""
                ),
                "error": r.error,
            }
            if plot_links is not None:
                row["plot"] = plot_links.get(i, "")
            if f is not None:
                row |= {
                    "E_kPa": f"{f.E_kPa:.6g}",
                    "model": f.model,
                    "tip": " ".join(f"{k}={v:g}" for k, v in f.geometry.items()),
                    "nu": f"{f.nu:g}",
                    "contact_method": f.contact_method,
                    "contact_from_start_um": _from_start(f, f),
                    "max_indentation_um": f"{f.max_indentation_um:.6g}",
                    "n_contact_points": f.n_contact_points,
                    "r_squared": f"{f.r_squared:.6f}",
                    "residual_rms_nN": f"{f.residual_rms_nN:.4g}",
                }
            if c is not None and f is not None:
                row |= {
                    "E_cytoplasm_kPa": f"{c.E_kPa:.6g}",
                    "cytoplasm_contact_from_start_um": _from_start(c, f),
                    "cytoplasm_r_squared": f"{c.r_squared:.6f}",
                }
            writer.writerow(row)
    return path
