"""What the inputs of ``afm_fit_files`` name, checked with the functions ``run`` uses
(:func:`check_case`, run by ``validate`` and before ``run`` through the inputs' model
check), and the creep records read as the run reads them (:func:`read_creep_records`)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from afm.creep_data import CreepData
from afm.curve_io import read_creep
from afm.fit_files import read_known_rows
from oocyte_fe.checks import inside
from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_fit_files_args import (
    creep_records,
    default_group,
    file_groups,
    find_curve_files,
    first_readable_curve,
    fit_options,
    known_moduli_file,
    pierce_options,
    read_options,
    tip_geometry,
)
from oocyte_fe.kinds.afm_fit_files_correction import correction

if TYPE_CHECKING:
    from oocyte_fe.kinds.afm_fit_files_inputs import FitFilesInputs
    from oocyte_fe.kinds.afm_fit_files_tables import Viscoelastic


def unused_options(ve: Viscoelastic) -> None:
    """Refuse an option of ``viscoelastic`` given for a relaxation that does not use it
    (``terms``: Prony only; ``t0_s``: power law only), which would be ignored silently. A
    value equal to the default is let through (a re-validated dump of the inputs holds it)."""
    for option, used_by in (("terms", "prony"), ("t0_s", "power_law")):
        default = type(ve).model_fields[option].default
        if ve.relaxation != used_by and getattr(ve, option) != default:
            raise InputError(
                "<input>",
                option,
                f'{option} only with relaxation = "{used_by}" (relaxation = '
                f'"{ve.relaxation}" does not use it): remove it',
                getattr(ve, option),
            )


def read_creep_records(files: Mapping[str, Path]) -> dict[str, CreepData]:
    """Each group's creep record, read as the run reads it (:func:`afm.curve_io.read_creep`):
    ``validate`` refuses an empty, short or non-finite record, naming the file and column."""
    return {group: read_creep(path) for group, path in files.items()}


def check_case(inp: FitFilesInputs, case_dir: Path) -> None:
    """Refuse (:class:`InputError` naming ``case.toml`` and the input) what ``run`` would
    refuse before fitting or only later, with the functions ``run`` uses: the curve files
    (:func:`find_curve_files`; at least one that the reader reads), the tip's geometry (the
    model's own check), a ``groups`` pattern that takes no curve file, a creep record or a
    ``pierce`` name for a group no curve file belongs to, the creep tip, the fit range against
    ``analysis``, what pierce-through curves cannot take (:func:`pierce_options`), the
    ``correction`` against the tip, ``nu`` and the fit range, a known-moduli row naming a
    file that does not exist.

    The data files' own faults (a creep record or known-moduli table that cannot be read)
    are left to their readers (:func:`read_creep_records`, :func:`read_known_moduli`), which
    ``validate`` runs next and which name the data file and its line.
    """
    where = case_dir / "case.toml"
    files = find_curve_files(case_dir, inp.curves)
    first_readable_curve(files, case_dir, read_options(inp, case_dir))
    creep_records(inp, case_dir)  # the creep tip first, as run
    tip_geometry(inp, where)
    by_pattern = file_groups(files, case_dir, inp.groups)
    for group, pattern in inp.groups.items():
        if group not in by_pattern.values():
            raise InputError(
                where,
                f"inputs.groups.{group}",
                "a glob matching at least one curve file of inputs.curves (its path relative "
                "to the case folder, e.g. 'curves/zp/*.csv'; a file goes to the first pattern "
                "matching it)",
                pattern,
            )
    _named_groups_exist(inp, by_pattern, where)
    pierce_options(inp, where)  # before fit_options: its refusal of nanite's analysis first
    fit_options(inp, where)
    correction(inp, where)
    _known_rows_name_files(inp, case_dir)


def _named_groups_exist(
    inp: FitFilesInputs, by_pattern: dict[Path, str | None], where: Path
) -> None:
    """Every group named by ``creep`` (its keys) and by a ``pierce`` list is a group of the
    curve files: a ``groups`` pattern's, else a file's ``# group`` metadata or subfolder
    (:func:`default_group`, read only when a name is no pattern's group)."""
    pierce = [] if isinstance(inp.pierce, bool) else inp.pierce
    if set(inp.creep) | set(pierce) <= set(by_pattern.values()):
        return
    groups = {g or default_group(f) for f, g in by_pattern.items()}
    one_of = (
        f"one of {', '.join(sorted(groups))}: their subfolders, '# group' metadata or inputs.groups"
    )
    unknown = sorted(set(inp.creep) - groups)
    if unknown:
        raise InputError(
            where, f"inputs.creep.{unknown[0]}", f"a group of the curve files ({one_of})"
        )
    unknown = [g for g in pierce if g not in groups]
    if unknown:
        raise InputError(
            where,
            "inputs.pierce",
            f"true, false or names of groups of the curve files ({one_of})",
            unknown[0],
        )


def _known_rows_name_files(inp: FitFilesInputs, case_dir: Path) -> None:
    """Every row of the known-moduli file names an existing file of the case folder (one that
    ``inputs.curves`` leaves out is the check's business: it fails, not fitted)."""
    known = known_moduli_file(inp, case_dir)
    if known is None:
        return
    try:
        rows = read_known_rows(known)
    except InputError:
        return  # the table's own fault: its reader names the file and line (DataReader)
    for row in rows:
        try:
            inside(row.file, case_dir, known, "file")
            exists = (case_dir / row.file).is_file()
        except (ValueError, OSError):  # outside the case folder, a name too long or with NUL
            exists = False
        if not exists:
            raise InputError(
                case_dir / "case.toml",
                "inputs.known_moduli",
                f"an existing curve file (path relative to the case folder) on every row "
                f"({known.name} line {row.line} names a file that does not exist)",
                row.file,
            )
