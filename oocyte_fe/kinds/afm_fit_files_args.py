"""The inputs of ``afm_fit_files`` turned into the library's arguments: the curve files found,
the reading and fitting options, the creep tip and records, the known-moduli file."""

from __future__ import annotations

import fnmatch
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from afm.batch import curve_files, pattern_group
from afm.curve_io import TEXT_SUFFIXES, is_instrument_file, iter_curves, read_table
from afm.fit import FitRange
from afm.fit_files import CreepRecord
from afm.instrument_io import INSTRUMENT_SUFFIXES
from afm.models import get_model
from afm.nanite_pipeline import fit_nanite_default
from afm.pierce import pierce_model
from oocyte_fe.checks import inside, regular_file
from oocyte_fe.errors import InputError, MissingExtraError

if TYPE_CHECKING:  # the inputs module checks a case with these functions
    from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs


GLOB_CHARACTERS = "*?["
"""Characters that make ``inputs.curves`` a glob rather than a folder."""


def find_curve_files(case_dir: Path, pattern: str) -> list[Path]:
    """The curve files named by ``pattern`` (a folder or a glob, relative to ``case_dir``).

    Refused (naming ``case.toml: inputs.curves``): an absolute path, a ``..`` part, a folder
    or files outside the case folder (a symlink leading out), a folder that does not exist, a
    folder or glob without curve files (:func:`afm.batch.curve_files`' suffixes).
    """
    where, field = case_dir / "case.toml", "inputs.curves"
    if Path(pattern).is_absolute() or ".." in Path(pattern).parts:
        raise InputError(
            where, field, "a folder or glob relative to the case folder, without '..'", pattern
        )
    try:
        inside(pattern, case_dir, where, field)  # names of at most 255 bytes, no symlink loop
        files = _curve_files(case_dir / pattern, case_dir, pattern)
    except (OSError, ValueError) as exc:  # a NUL byte, no permission, a bad glob
        if isinstance(exc, InputError):
            raise
        reason = exc.strerror if isinstance(exc, OSError) else str(exc)
        raise InputError(
            where, field, f"a readable folder or a valid glob ({reason})", pattern
        ) from None
    for file in files:
        inside(file, case_dir, where, field)  # no symlink leading out
    return files


def _curve_files(target: Path, case_dir: Path, pattern: str) -> list[Path]:
    where, field = case_dir / "case.toml", "inputs.curves"
    if target.is_dir():
        try:
            return curve_files(target)
        except InputError:
            suffixes = ", ".join(sorted(TEXT_SUFFIXES | INSTRUMENT_SUFFIXES))
            raise InputError(
                where, field, f"a folder holding curve files ({suffixes}); it has none", pattern
            ) from None
    if not target.exists() and not any(c in pattern for c in GLOB_CHARACTERS):
        raise InputError(
            where,
            field,
            "an existing folder of curve files (or a glob of them) in the case folder; not found",
            pattern,
        )
    files = sorted(p for p in case_dir.glob(pattern) if p.is_file())  # a file: itself
    if not files:
        raise InputError(where, field, "a glob that matches curve files; it matches none", pattern)
    return files


def first_readable_curve(
    files: Sequence[Path], case_dir: Path, options: Callable[[Path], Mapping[str, object]]
) -> Path:
    """The first of ``files`` whose first curve the run's reader reads
    (:func:`afm.curve_io.iter_curves` with the file's ``options``); refused, naming
    ``case.toml: inputs.curves`` and the first file's fault, when none can be read (a folder
    of notes, not curves). The other files are read by the run, which reports and skips a
    curve it cannot read."""
    first = ""
    for file in files:
        try:
            next(iter(iter_curves(file, **options(file), selection=range(1))))  # type: ignore[arg-type]
            return file
        except StopIteration:
            reason = "no curve in the file"
        except (InputError, ValueError, FloatingPointError, MissingExtraError) as exc:
            reason = str(exc).splitlines()[0].removeprefix(f"{file}: ")
        first = first or f"{file.relative_to(case_dir).as_posix()}: {reason}"
    raise InputError(
        case_dir / "case.toml",
        "inputs.curves",
        f"curve files the reader can read; none of the {len(files)} found can (first: {first})",
    )


def tip_geometry(inp: FitFilesInputs, where: Path) -> dict[str, float]:
    """The geometry of the curves' tip, checked by the model (:meth:`check_geometry`: its
    keys only, each within the model's bounds; left-out keys take the model's default)."""
    try:
        return get_model(inp.model).check_geometry(inp.geometry, str(where))
    except InputError as exc:
        key = "" if exc.field == "geometry" else f".{exc.field}"
        raise InputError(where, f"inputs.geometry{key}", exc.expected, exc.got) from None


def file_groups(
    files: Sequence[Path], case_dir: Path, patterns: Mapping[str, str]
) -> dict[Path, str | None]:
    """Each file's group as the run assigns it where that needs no reading: the first
    ``groups`` pattern matching its relative path, else None (the file's own ``# group``
    metadata or its folder; :func:`default_group`)."""
    return {f: pattern_group(f.relative_to(case_dir).as_posix(), patterns) for f in files}


def default_group(file: Path) -> str:
    """The group of a file no pattern matches: a text table's ``# group =`` metadata (read
    with the run's reader), else the file's folder (also for a table the reader refuses: the
    run reports that curve and skips it)."""
    if not is_instrument_file(file):
        try:
            _, meta = read_table(file)
        except InputError:
            return file.parent.name
        return meta.get("group") or file.parent.name  # an empty one too (afm.batch)
    return file.parent.name


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
        tip_geometry(inp, where)  # refused here, not by the creep fit
        return inp.model, dict(inp.geometry)
    if inp.model != "sneddon_cone":
        raise InputError(
            where,
            "inputs.half_angle_deg_creep",
            f"left out with model = {inp.model!r} (the creep fit uses the curves' tip)",
            inp.half_angle_deg_creep,
        )
    return "sneddon_cone", {"half_angle_deg": inp.half_angle_deg_creep}


def creep_records(inp: FitFilesInputs, case_dir: Path) -> dict[str, CreepRecord]:
    """The creep record of each group of ``inputs.creep`` (files inside the case folder), with
    the tip of :func:`creep_tip`."""
    where = case_dir / "case.toml"
    for group, file in inp.creep.items():
        inside(file, case_dir, where, f"inputs.creep.{group}")
    if not inp.creep:
        return {}
    model, geometry = creep_tip(inp, where)
    return {
        group: CreepRecord(file, model, geometry, str(where), f"inputs.creep.{group}")
        for group, file in inp.creep.items()
    }


def fit_options(inp: FitFilesInputs, where: Path) -> dict[str, object]:
    """Keywords of :func:`afm.batch.fit_batch` for the plain curves (those of no ``pierce``
    group), by ``analysis``: nanite's fit function (no fit range, contact point free), or the
    fit range and contact method of the default fit."""
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
        return {"fit_function": fit_nanite_default}
    return {
        "fit_range": FitRange(inp.max_indentation_um, inp.max_force_fraction),
        "contact_method": inp.contact_method,
    }


def known_moduli_file(inp: FitFilesInputs, case_dir: Path) -> Path | None:
    """The known-moduli CSV (a file inside the case folder), or None."""
    if inp.known_moduli is None:
        return None
    field = "inputs.known_moduli"
    return regular_file(inside(inp.known_moduli, case_dir, case_dir / "case.toml", field), field)


PIERCE_REFUSES = {
    "viscoelastic": "a ramp fit in time takes the whole curve as one layer",
    "correction": "a correction takes one layer's modulus, the other's given",
}
"""Input tables refused with pierce-through curves (``pierce`` true or naming groups), and
why."""


def pierce_setting(inp: FitFilesInputs) -> str:
    """``pierce`` as written in ``case.toml``: ``pierce = true`` or ``pierce = ["a", "b"]``."""
    if isinstance(inp.pierce, bool):
        return f"pierce = {str(inp.pierce).lower()}"
    return "pierce = [" + ", ".join(f'"{g}"' for g in inp.pierce) + "]"


def pierce_options(inp: FitFilesInputs, where: Path) -> dict[str, object] | None:
    """Keywords of :func:`afm.pierce.fit_pierce` for the curves of the ``pierce`` groups
    (all with ``pierce = true``; None without pierce-through curves): the ZP's fit range
    (``max_indentation_um`` past the ZP contact, ``max_force_fraction`` of the force at the
    drop), the contact method and the least drop taken as the pierce
    (``pierce_min_drop_fraction``, of the curve's force range).

    Refused (naming ``case.toml`` and the input): a tip for which the cytoplasm fit is not
    defined (:func:`afm.pierce.pierce_model`: ``flat_punch``), nanite's analysis, a
    ``viscoelastic`` or ``correction`` table.
    """
    if not inp.pierce:
        return None
    setting = pierce_setting(inp)
    try:
        pierce_model(inp.model, str(where))
    except InputError as exc:
        raise InputError(
            where, "inputs.model", f"{exc.expected}, with {setting}", exc.got
        ) from None
    if inp.analysis != "default":
        raise InputError(
            where,
            "inputs.analysis",
            f'analysis = "default" with {setting} (both layers are fitted by afm.fit)',
            inp.analysis,
        )
    for name, why in PIERCE_REFUSES.items():
        if getattr(inp, name) is not None:
            raise InputError(where, f"inputs.{name}", f"no {name} table with {setting} ({why})")
    return {
        "zp_range": FitRange(inp.max_indentation_um, inp.max_force_fraction),
        "contact_method": inp.contact_method,
        "min_drop_fraction": inp.pierce_min_drop_fraction,
    }
