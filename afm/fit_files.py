"""A set of curve files -> moduli per group -> a material per group (the user route).

:func:`fit_files` fits every curve (:func:`afm.batch.fit_batch`: its group by file pattern,
subfolder or ``# group`` metadata; the curves of the ``pierce`` groups as pierce-through
curves, ZP and cytoplasm), takes the mean +- SD of E per group over the fits rated good (poor
ones only when asked; :meth:`afm.batch.BatchResult.stats`) and makes each group's material:

* with a force-clamp creep record of the group: instantaneous E0 and the exact relaxation
  Prony series of the Lee-Radok creep fit for the record's tip (:func:`afm.creep.fit_creep_tip`);
* otherwise, with the viscoelastic option (``viscoelastic``), E0 and the Prony series of the
  group's ramp fit (:func:`afm.ramp_files.fit_ramp_files`: Ting's method, jointly over the
  group's curves; Prony or standard linear solid, rated good unless ``include_poor``);
* otherwise elastic, E = the group's mean E (kPa), nu as assumed by the fits.

A creep record wins over a ramp fit when a group has both. With a ``correction``
(:mod:`afm.corrections`) every fit's modulus is corrected
(:func:`afm.corrected_batch.apply_correction`) and the
statistics and elastic materials use the corrected moduli.

Fits of curves with a known modulus give the relative errors |E / E_known - 1|. Nothing is
written or drawn here: the result goes to a report (the ``afm_fit_files`` case kind's).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import NamedTuple

from afm.batch import BatchResult, BatchRow, GroupStats, ReadOptions, fit_batch
from afm.corrected_batch import Correction, apply_correction, corrected_stats
from afm.creep import CreepFit, fit_creep_tip
from afm.curve_io import read_creep
from afm.material_file import MaterialFile
from afm.ramp_files import GroupRampFit, RampFilesResult, RampOptions, fit_ramp_files
from oocyte_fe import checks
from oocyte_fe.errors import InputError

KNOWN_HEADER = "file,E_kPa"
"""Header row of a known-moduli CSV."""
SOURCE = "afm_fit_files case"
"""How the material files' source lines name where they came from."""


@dataclass(frozen=True)
class CreepRecord:
    """A group's force-clamp creep CSV (:func:`afm.curve_io.read_creep`) and the tip it was
    recorded with (model key and geometry; left-out parameters take the model's default).

    ``file`` and ``field`` name where the record was given (for errors).
    """

    path: str | Path
    model: str = "sneddon_cone"
    geometry: Mapping[str, float] = field(default_factory=dict)
    file: str = "<input>"
    field: str = "creep"


@dataclass(frozen=True)
class GroupMaterial:
    """The material of one group: elastic from the group's mean E (``creep`` None) or from the
    group's creep fit; ``material`` is None for a group with no fit to average and no creep
    record."""

    group: str
    material: MaterialFile | None
    creep: CreepFit | None = None
    ramp: GroupRampFit | None = None


@dataclass(frozen=True)
class FitFilesResult:
    """Result of :func:`fit_files`.

    ``stats`` holds the mean +- SD of E per group (sorted by group; the ZP's for a ``pierce``
    group) and ``materials`` one entry per group of ``stats``; ``pierce`` the groups fitted
    as pierce-through curves (their cytoplasm's E in the rows' ``cytoplasm``); ``ramps`` the
    viscoelastic ramp fits (None without the option); ``corrected`` the corrected E of each
    row of ``batch`` [kPa] or why not (None without ``correction``). ``known_errors`` are
    |E / E_known - 1| of the fitted curves with a known modulus (None without known moduli),
    ``n_known`` the curves listed.
    """

    batch: BatchResult
    include_poor: bool
    stats: dict[str, GroupStats]
    materials: tuple[GroupMaterial, ...]
    known_errors: tuple[float, ...] | None = None
    n_known: int = 0
    ramps: RampFilesResult | None = None
    correction: Correction | None = None
    corrected: tuple[float | str, ...] | None = None
    pierce: frozenset[str] = frozenset()

    @property
    def fitted(self) -> list[BatchRow]:
        """The rows fitted (rated good or poor), in file order."""
        return [r for r in self.batch.rows if r.fit is not None and not r.error]

    @property
    def n_poor(self) -> int:
        """Fitted curves rated poor."""
        return sum(1 for r in self.fitted if not r.good)

    @property
    def n_refused(self) -> int:
        """Curves (or files) that could not be read or fitted."""
        return len(self.batch.rows) - len(self.fitted)

    @property
    def summary(self) -> str:
        """``done: N fitted, M poor, K refused``."""
        return f"done: {len(self.fitted)} fitted, {self.n_poor} poor, {self.n_refused} refused"

    @property
    def max_known_error_pct(self) -> float | None:
        """Largest |E / E_known - 1| in %, 100 when no curve with a known modulus was fitted;
        None without known moduli."""
        if self.known_errors is None:
            return None
        return 100 * max(self.known_errors) if self.known_errors else 100.0

    def known_within(self, tolerance_pct: float) -> bool:
        """Every curve with a known modulus fitted, each within ``tolerance_pct`` %."""
        errors, worst = self.known_errors, self.max_known_error_pct
        return bool(errors) and len(errors) == self.n_known and worst < tolerance_pct


class KnownModulus(NamedTuple):
    """One row of a known-moduli CSV: the curve file (relative path), its modulus [kPa] and
    the row's line in the file (1 = the first line)."""

    file: str
    E_kPa: float
    line: int


def read_known_rows(path: str | Path) -> list[KnownModulus]:
    """The rows of a known-moduli CSV (:func:`read_known_moduli`) with their line numbers.

    Refused (:class:`InputError` naming the file, the column and the line): a file that is not
    a regular UTF-8 file, no header with columns ``file`` and ``E_kPa``, no data row, a row
    without a file name, a modulus that is not a number within the physical bounds of
    :data:`oocyte_fe.checks.QUANTITIES` (``modulus_kPa``: positive, finite), a file listed twice.
    """
    text = checks.read_text(path)
    lines = checks.csv_lines(path, text)
    if not lines:
        raise InputError(path, "", f"a header row {KNOWN_HEADER!r} and a row per curve (no rows)")
    n_header, names = lines[0][0], [name.strip() for name in lines[0][1]]
    if "file" not in names or "E_kPa" not in names:
        raise InputError(
            path,
            f"header (line {n_header})",
            f"columns {KNOWN_HEADER!r} (the curve file relative to the case folder, its "
            "modulus in kPa)",
            got=", ".join(names)[:80],
        )
    if len(lines) < 2:
        raise InputError(path, "", f"a row per curve below the header {KNOWN_HEADER!r}")
    at_file, at_e = names.index("file"), names.index("E_kPa")
    rows: list[KnownModulus] = []
    seen: dict[str, int] = {}
    for n, cells in lines[1:]:
        if len(cells) != len(names):
            raise InputError(path, f"line {n}", f"{len(names)} comma-separated values")
        name = cells[at_file].strip()
        if not name:
            raise InputError(path, f"file (line {n})", "a curve file (relative to the case folder)")
        if name in seen:
            raise InputError(
                path, f"file (line {n})", f"each file once (listed on line {seen[name]} too)", name
            )
        value = checks.number_cell(path, f"E_kPa (line {n})", cells[at_e].strip(), "a number (kPa)")
        low, high, _ = checks.QUANTITIES["modulus_kPa"]
        expected = f"a positive modulus in kPa, within [{low:g}, {high:g}]"
        e_kPa = checks.number(path, f"E_kPa (line {n})", value, ge=low, le=high, expected=expected)
        seen[name] = n
        rows.append(KnownModulus(name, e_kPa, n))
    return rows


def read_known_moduli(path: str | Path) -> dict[str, float]:
    """Known moduli from a CSV of columns ``file`` (path relative to the folder the curve
    files are named from) and ``E_kPa``; lines starting with ``#`` are comments. Checked as
    :func:`read_known_rows`."""
    return {row.file: row.E_kPa for row in read_known_rows(path)}


def group_material(
    group: str,
    stats: GroupStats,
    model: str,
    nu: float,
    include_poor: bool,
    creep: CreepRecord | None = None,
    ramp: GroupRampFit | None = None,
) -> GroupMaterial:
    """The material of ``group``: from its ``creep`` record when given, else from its ramp
    fit (:func:`ramp_material`), else elastic with the mean E of ``stats`` (fits of tip
    ``model`` with Poisson ratio ``nu``; ``include_poor``: whether poor fits entered it); none
    without fits to average."""
    if creep is None and ramp_material(ramp, include_poor):
        assert ramp is not None
        speeds = ", ".join(f"{v:.3g}" for v in sorted(set(ramp.speeds_um_per_s)))
        source = f"{SOURCE}: ramp fit of {len(ramp.speeds_um_per_s)} curves (speeds {speeds} um/s)"
        return GroupMaterial(group, ramp.fit.material(group, source), ramp=ramp)
    if creep is None:
        if stats.n == 0:
            return GroupMaterial(group, None)
        source = (
            f"{SOURCE}: mean of {stats.n} {model} fits rated "
            f"{'good or poor' if include_poor else 'good'} ({stats.mean_sd_text} kPa), elastic"
        )
        return GroupMaterial(group, MaterialFile(group, source, stats.mean_kPa, nu))
    fit = fit_creep_tip(read_creep(creep.path), creep.model, creep.geometry, nu)
    source = (
        f"{SOURCE}: creep {Path(creep.path).name}, Lee-Radok {fit.model} ({tip_text(fit)}), "
        "Prony fit, exact relaxation series"
    )
    return GroupMaterial(group, fit.material(group, source), fit)


def ramp_material(ramp: GroupRampFit | None, include_poor: bool) -> bool:
    """Whether a group's ramp fit gives its material: a Prony or standard-linear-solid fit
    (a power law has no Prony series), rated good unless ``include_poor``."""
    if ramp is None or ramp.fit.relaxation == "power_law":
        return False
    return include_poor or ramp.fit.quality == "good"


def tip_text(fit: CreepFit) -> str:
    """The creep fit's tip geometry, ``half_angle_deg 10`` (comma-separated)."""
    return ", ".join(f"{k} {v:g}" for k, v in fit.geometry.items())


def fit_files(
    files: Sequence[str | Path],
    model: str,
    geometry: Mapping[str, float],
    nu: float,
    relative_to: str | Path,
    *,
    fit_options: Mapping[str, object] | None = None,
    read_options: ReadOptions | None = None,
    groups: Mapping[str, str] | None = None,
    pierce: bool | Collection[str] = False,
    pierce_options: Mapping[str, object] | None = None,
    creep: Mapping[str, CreepRecord] | None = None,
    include_poor: bool = False,
    known_moduli: Mapping[str, float] | None = None,
    viscoelastic: RampOptions | None = None,
    correction: Correction | None = None,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> FitFilesResult:
    """Fit the curves of ``files`` (under ``relative_to``), group them, make the materials.

    ``model``, ``geometry`` and ``nu`` are the tip and Poisson ratio of every fit;
    ``fit_options`` go to :func:`afm.batch.fit_batch` besides them (``fit_range`` and
    ``contact_method``, or ``fit_function``), as do ``read_options``, ``workers`` and
    ``progress``. ``groups`` (group -> glob on the path relative to ``relative_to``) name
    the rows' groups (:func:`afm.batch.fit_batch`); ``pierce`` (true, false or group names)
    the pierce-through curves, fitted by :func:`afm.pierce.fit_pierce` with the tip, ``nu``
    and ``pierce_options`` (``zp_range``, ``contact_method``, ``min_drop_fraction``);
    ``creep`` (group -> :class:`CreepRecord`) gives a group its viscoelastic material (a
    ``pierce`` group: its ZP's); ``include_poor`` keeps fits rated poor in the statistics;
    ``known_moduli`` (relative path -> E_kPa) is compared with the fits; ``viscoelastic``
    also fits every ramp in time (:func:`afm.ramp_files.fit_ramp_files`); ``correction``
    corrects every modulus (:func:`afm.corrected_batch.apply_correction`; checked by the
    caller against the tip and fit range) and the statistics and materials use the corrected
    moduli.

    Refused (:class:`InputError`): a creep record for a group no fitted curve belongs to, a
    creep record :func:`afm.creep.fit_creep_tip` refuses; with ``viscoelastic``, a file
    without times.
    """
    ramps = None  # first: a file without times is refused before the elastic fits
    if viscoelastic is not None:
        ramps = fit_ramp_files(
            files,
            model,
            geometry,
            nu,
            relative_to,
            viscoelastic,
            read_options=read_options,
            groups=groups,
        )
    tip = {"model": model, "geometry": geometry, "nu": nu}
    batch = fit_batch(
        files,
        pierce,
        read_options=read_options,
        workers=workers,
        progress=progress,
        pierce_options=tip | dict(pierce_options or {}),
        groups=groups,
        relative_to=relative_to,
        **tip,
        **(fit_options or {}),
    )
    corrected = None if correction is None else apply_correction(batch, correction)
    listed = (
        batch.stats(include_poor)
        if corrected is None
        else corrected_stats(batch, corrected, include_poor)
    )
    stats = {s.group: s for s in listed if s.quantity == "E_kPa"}
    creep = creep or {}
    unknown = sorted(set(creep) - set(stats))
    if unknown:
        record = creep[unknown[0]]
        names = ", ".join(sorted(stats)) or "none"
        raise InputError(
            record.file, record.field, f"a group of the fitted curves (one of {names})"
        )
    materials = tuple(
        group_material(
            g,
            stats[g],
            model if correction is None else f"{model} ({correction.name}-corrected)",
            nu,
            include_poor,
            creep.get(g),
            None if ramps is None else ramps.group_fit(g),
        )
        for g in sorted(stats)
    )
    result = FitFilesResult(
        batch,
        include_poor,
        stats,
        materials,
        ramps=ramps,
        correction=correction,
        corrected=corrected,
        pierce=frozenset(
            () if pierce is False else {r.group for r in batch.rows} if pierce is True else pierce
        ),
    )
    if known_moduli is None:
        return result
    errors = tuple(
        abs(r.fit.E_kPa / known_moduli[key] - 1)
        for r in result.fitted
        if (key := Path(r.file).relative_to(relative_to).as_posix()) in known_moduli
    )
    return replace(result, known_errors=errors, n_known=len(known_moduli))
