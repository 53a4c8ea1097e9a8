"""The inputs of ``afm_fit_files`` turned into the library's arguments: the curve files found,
the reading and fitting options, the creep tip and records, the known-moduli file."""

from __future__ import annotations

import fnmatch
from collections.abc import Callable
from pathlib import Path

from afm.batch import curve_files
from afm.fit import FitRange
from afm.fit_files import CreepRecord
from afm.nanite_pipeline import fit_nanite_default
from oocyte_fe.checks import inside, regular_file
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs


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


def creep_records(inp: FitFilesInputs, case_dir: Path) -> dict[str, CreepRecord]:
    """The creep record of each group of ``inputs.creep`` (files inside the case folder), with
    the tip of :func:`creep_tip`."""
    where = case_dir / "case.toml"
    for group, file in inp.creep.items():
        _inside(case_dir, Path(file), f"inputs.creep.{group}")
    if not inp.creep:
        return {}
    model, geometry = creep_tip(inp, where)
    return {
        group: CreepRecord(file, model, geometry, str(where), f"inputs.creep.{group}")
        for group, file in inp.creep.items()
    }


def fit_options(inp: FitFilesInputs, where: Path) -> dict[str, object]:
    """Keywords of :func:`afm.batch.fit_batch` for ``analysis``: nanite's fit function (no fit
    range, contact point free), or the fit range and contact method of the default fit."""
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
