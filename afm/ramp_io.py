"""Force ramps in time from curve files: approach and retract with the time of every point.

Instrument files (afmformats' segments and ``time`` column): :func:`afm.instrument_io.
ramp_from_record`. Text tables (:func:`afm.curve_io.read_table`): the columns of
:mod:`afm.curve_io` plus ``time_s``; the rows run through the approach and on into the
retract (the turn is the farthest travel; a height column decreasing towards the sample is
turned round). A file without times is refused: Ting's
method (:mod:`afm.viscoelastic`) needs them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from afm.curve_io import is_instrument_file, read_table_travel
from afm.instrument_io import RecordedRamp, load_records, ramp_from_record
from afm.viscoelastic import RampCurve, ramp_from_piezo
from oocyte_fe.errors import InputError


def _table_ramp(
    path: Path, spring_constant_N_per_m: float | None, sensitivity_nm_per_V: float | None
) -> RecordedRamp:
    """A text table's ramp: its rows in time through the approach and on into the retract,
    the travel towards the sample of either sign (:func:`afm.curve_io.read_table_travel`);
    the turn is the farthest travel."""
    table = read_table_travel(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    if "time_s" not in table.columns:
        raise InputError(path, "time_s", "a time_s column (the viscoelastic fit needs times)")
    group = table.meta.get("group", path.parent.name)
    turn = int(np.argmax(table.towards_um)) + 1
    return RecordedRamp(
        table.columns["time_s"],
        table.towards_um,
        table.force_nN,
        table.spring_constant_nN_per_um,
        turn,
        str(path),
        group,
    )


def read_ramps(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> list[RecordedRamp]:
    """Every force-distance curve of ``path`` as approach and retract in time (one for a
    table or single curve, all of a force map); arguments as :func:`afm.curve_io.read_curves`."""
    path = Path(path)
    if not is_instrument_file(path):
        return [_table_ramp(path, spring_constant_N_per_m, sensitivity_nm_per_V)]
    records = load_records(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    records = [r for r in records if r.modality == "force-distance"] or records
    many = len(records) > 1 or "grid shape x" in records[0].metadata
    ramps = []
    for i, record in enumerate(records):
        index = int(record.metadata.get("enum", i)) if many else None
        source = f"{path} (curve {index})" if many else str(path)
        ramps.append(ramp_from_record(record, source, height_channel, path.parent.name, index))
    return ramps


def ramp_curve(recorded: RecordedRamp) -> RampCurve:
    """The :class:`~afm.viscoelastic.RampCurve` of a recorded ramp: baseline of the approach
    removed from both segments, tip position ``piezo - F/k`` (:func:`ramp_from_piezo`)."""
    return ramp_from_piezo(
        recorded.time_s,
        recorded.piezo_um,
        recorded.force_nN,
        recorded.spring_constant_nN_per_um,
        recorded.source,
    )
