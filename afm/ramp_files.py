"""Viscoelastic fits of the ramps of a set of curve files, per curve and jointly per group.

Every curve is read as approach and retract in time (:func:`afm.ramp_io.read_ramps`; a file
without times is refused) and fitted alone with Ting's method (:func:`afm.viscoelastic.
fit_ramp`). A group with several curves (for example ramp speeds a decade apart) gets a joint
fit of all of them: one relaxation modulus, a contact point per curve. That fit is what a
group's material comes from (:func:`afm.fit_files.fit_files`); a single speed resolves only
the times between about 3 sampling steps and the time in contact (docs/afm.md).

The drag offset of a curve: the mean baseline-removed force of its retract points out of
contact (tip short of the fitted contact point by more than a tenth of the largest
indentation). The baseline is the approach's; a viscous drag on the cantilever changes sign
with the direction of travel, so it shows as this offset (about twice the drag force) and is
not removed from the fit.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from afm.batch import ReadOptions, pattern_group
from afm.instrument_io import RecordedRamp
from afm.ramp_io import ramp_curve, read_ramps
from afm.viscoelastic import RampCurve, RampFit, fit_ramp
from oocyte_fe.errors import InputError

RELAXATION_KEYS = {"prony": "prony", "power_law": "power_law", "sls": "standard_linear_solid"}
"""Names of the relaxation models in a case file -> keys of :mod:`afm.viscoelastic`."""

RAMP_COLUMNS = {
    "ve_relaxation": "relaxation model of the ramp fit (prony, power_law, standard_linear_solid)",
    "ve_E0_kPa": "instantaneous modulus E0 (power law: E(t0)), kPa",
    "ve_E_inf_kPa": "long-time modulus E_inf (Prony, SLS), kPa",
    "ve_terms": "E_i [kPa] / tau_i [s] of each relaxation term, or the power law's beta",
    "ve_quality": "good or poor (the reasons: ve_undetermined, or the RMS), or the error",
    "ve_used_retract": "whether the retract was fitted too",
    "ramp_speed_um_per_s": "mean piezo speed of the approach, um/s",
    "ve_drag_offset_nN": "mean force of the retract out of contact with the approach's "
    "baseline removed (viscous drag shows here), nN",
    "ve_undetermined": "parameters the ramp does not determine, and why",
    "ve_plot": "the curve's F(t) figure with its ramp fit",
}
"""Columns a ramp fit adds to ``fits.csv`` and what each holds."""

OUT_OF_CONTACT = 0.1
"""Retract points farther than this fraction of the largest indentation short of contact are
out of contact (for the drag offset)."""


@dataclass(frozen=True)
class RampOptions:
    """What :func:`fit_ramp_files` fits: ``relaxation`` (a key of :mod:`afm.viscoelastic`),
    ``terms`` (Prony), ``t0_s`` (power law's reference time, s), ``use_retract``, and
    ``joint_speeds`` (a joint fit per group of several curves)."""

    relaxation: str = "prony"
    terms: int = 2
    t0_s: float = 1.0
    use_retract: bool = True
    joint_speeds: bool = True


@dataclass(frozen=True)
class RampRow:
    """One curve's ramp fit (``fit`` None and ``error`` set when refused)."""

    file: str
    source: str
    group: str
    speed_um_per_s: float | None
    fit: RampFit | None
    drag_offset_nN: float | None = None
    error: str = ""
    curve_index: int | None = None

    def columns(self) -> dict[str, str]:
        """This row's values of :data:`RAMP_COLUMNS` (empty strings where none)."""
        fit = self.fit
        values = dict.fromkeys(RAMP_COLUMNS, "")  # ve_plot: set by the report
        if self.speed_um_per_s is not None:
            values["ramp_speed_um_per_s"] = f"{self.speed_um_per_s:.6g}"
        if self.drag_offset_nN is not None:
            values["ve_drag_offset_nN"] = f"{self.drag_offset_nN:.4g}"
        if fit is None:
            values["ve_quality"] = f"error: {self.error}"
            return values
        par = fit.parameters
        values |= {
            "ve_relaxation": fit.relaxation,
            "ve_E0_kPa": f"{fit.E0_kPa:.6g}",
            "ve_E_inf_kPa": f"{par['E_inf_kPa']:.6g}" if "E_inf_kPa" in par else "",
            "ve_terms": terms_text(fit),
            "ve_quality": "good" if fit.quality == "good" else "poor",
            "ve_used_retract": str(fit.used_retract).lower(),
            "ve_undetermined": "; ".join(fit.undetermined),
        }
        return values


@dataclass(frozen=True)
class GroupRampFit:
    """The fit of a group's curves together (one curve: its own fit); ``speeds_um_per_s``
    of the curves in it."""

    group: str
    fit: RampFit
    speeds_um_per_s: tuple[float, ...]

    @property
    def n_speeds(self) -> int:
        """Distinct ramp speeds (within 5 %)."""
        speeds = sorted(self.speeds_um_per_s)
        return 1 + sum(1 for a, b in zip(speeds, speeds[1:], strict=False) if b > 1.05 * a)


@dataclass(frozen=True)
class RampFilesResult:
    """Result of :func:`fit_ramp_files`: a row per curve and the groups' joint fits."""

    options: RampOptions
    rows: tuple[RampRow, ...]
    groups: tuple[GroupRampFit, ...]

    def group_fit(self, group: str) -> GroupRampFit | None:
        """The joint fit of ``group``, or None."""
        return next((g for g in self.groups if g.group == group), None)

    def row(self, source: str) -> RampRow | None:
        """The row of the curve named ``source``, or None."""
        return next((r for r in self.rows if r.source == source), None)


def terms_text(fit: RampFit) -> str:
    """The relaxation terms of ``fit``: ``E_1 = 0.3 kPa / tau_1 = 0.05 s; ...`` or
    ``beta = 0.2 (t0 = 1 s)``."""
    par = fit.parameters
    if fit.relaxation == "power_law":
        return f"beta = {par['beta']:.4g} (t0 = {par['t0_s']:g} s)"
    moduli = par.get("E_kPa", (fit.amplitudes_kPa[1],))
    times = par["tau_s"] if isinstance(par["tau_s"], tuple) else (par["tau_s"],)
    return "; ".join(
        f"E_{i} = {e:.4g} kPa / tau_{i} = {t:.4g} s"
        for i, (e, t) in enumerate(zip(moduli, times, strict=True), start=1)
    )


def drag_offset(ramp: RampCurve, contact_um: float) -> float | None:
    """Mean force of the retract points out of contact, nN (module docstring); None when the
    retract has none."""
    x, f, turn = ramp.tip_position_um, ramp.force_nN, ramp.turn
    depth = float(x[turn]) - contact_um
    free = x[turn + 1 :] < contact_um - OUT_OF_CONTACT * max(depth, 0.0)
    return float(np.mean(f[turn + 1 :][free])) if np.any(free) else None


def _group(recorded: RecordedRamp, relative: str, patterns: Mapping[str, str]) -> str:
    return pattern_group(relative, patterns) or recorded.group


def _read(file: Path, read_options: ReadOptions | None) -> list[RecordedRamp]:
    options = read_options(file) if callable(read_options) else (read_options or {})
    keys = ("spring_constant_N_per_m", "sensitivity_nm_per_V", "height_channel")
    return read_ramps(file, **{k: v for k, v in options.items() if k in keys})


def fit_ramp_files(
    files: Sequence[str | Path],
    model: str,
    geometry: Mapping[str, float],
    nu: float,
    relative_to: str | Path,
    options: RampOptions,
    *,
    read_options: ReadOptions | None = None,
    groups: Mapping[str, str] | None = None,
) -> RampFilesResult:
    """Fit the ramp of every curve of ``files`` and, per group, all of them together.

    Groups as :func:`afm.batch.fit_batch` (first glob of ``groups`` on the path relative
    to ``relative_to``, else the folder). A file without times raises :class:`InputError`;
    any other curve that cannot be read or fitted is a row with its error.
    """
    relaxation = RELAXATION_KEYS.get(options.relaxation, options.relaxation)
    keywords = dict(
        model=model,
        geometry=geometry,
        nu=nu,
        relaxation=relaxation,
        terms=options.terms,
        t0_s=options.t0_s,
        use_retract=options.use_retract,
    )
    rows: list[RampRow] = []
    ramps: dict[str, list[tuple[RampCurve, float]]] = {}
    for file in map(Path, files):
        relative = file.relative_to(relative_to).as_posix()
        try:
            recorded = _read(file, read_options)
        except InputError as exc:
            if exc.field in ("time", "time_s"):
                raise
            rows.append(RampRow(relative, str(file), file.parent.name, None, None, None, str(exc)))
            continue
        for rec in recorded:
            index = rec.curve_index
            group = _group(rec, relative, groups or {})
            try:
                ramp = ramp_curve(rec)
                fit = fit_ramp(ramp, **keywords)
            except InputError as exc:
                error = str(exc)
                rows.append(RampRow(relative, rec.source, group, None, None, None, error, index))
                continue
            offset = drag_offset(ramp, fit.contact_points_um[0])
            speed = rec.speed_um_per_s
            rows.append(RampRow(relative, rec.source, group, speed, fit, offset, "", index))
            ramps.setdefault(group, []).append((ramp, speed))
    joint = []
    for group, items in sorted(ramps.items()):
        if len(items) == 1:
            row = next(r for r in rows if r.group == group and r.fit is not None)
            joint.append(GroupRampFit(group, row.fit, (items[0][1],)))  # type: ignore[arg-type]
        elif options.joint_speeds:
            fit = fit_ramp([r for r, _ in items], **keywords)
            joint.append(GroupRampFit(group, fit, tuple(s for _, s in items)))
    return RampFilesResult(options, tuple(rows), tuple(joint))
