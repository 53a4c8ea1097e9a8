"""Instrument files (JPK, Asylum/Igor, AFM-Workshop, NT-MDT, afmformats HDF5/TAB) via afmformats.

afmformats gives SI columns with the height decreasing towards the sample; here they become
piezo travel towards the sample [um] and force [nN] (``piezo = -height * 1e6``,
``force = F * 1e9``).

Height channel (``height_channel="auto"``): the one the instrument's own software uses for
the tip-sample separation, in this order of preference:

1. ``tip position``, when the file holds it (it already is the tip-sample separation);
2. ``height (measured)``, the height sensor (JPK "measured height", Asylum ``ZSnsr``,
   AFM-Workshop's and NT-MDT's height): the JPK software and nanite compute the tip position
   from it (``tip = measured height + F/k`` in afmformats' sign);
3. ``height (piezo)``, the commanded piezo extension, only when there is no sensor column.

The piezo column of a closed-loop instrument is not the tip travel (on a JPK curve it was 2.7
um against 5.0 um measured over the same approach) and gave moduli up to 30 times too large.
The channel used is kept on every curve (:attr:`afm.curve.ForceCurve.height_channel`) and
can be forced with ``height_channel``.

The approach segment is used as recorded. Where a file stores approach and retract as one
segment (Igor ``.ibw``), the approach ends at the farthest travel (the turning point); this is
the only place the data are cut.

Force maps (``.jpk-force-map``, ``.jpk-qi-data``, AFM-Workshop map ``.zip``, afmformats
``.h5``): every curve is read, with its map position (``position x``/``position y``, um) and
index. An afmformats HDF5 file is read in one pass (:func:`_hdf5_curves`; afmformats' own
loader reopens the file for every column of every curve).

Force-clamp creep files (JPK ``creep-compliance`` modality: approach, hold at constant force,
retract): :func:`read_instrument_creep`.

Approach and retract in time, for the viscoelastic ramp fits: :func:`ramp_from_record`.
"""

from __future__ import annotations

import contextlib
import importlib
import logging
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from afm.baseline import fit_baseline, remove_baseline
from afm.contact_point import deviation_index
from afm.creep_data import CreepData
from afm.curve import ForceCurve, approach_end, spring_constant_nN_per_um
from oocyte_fe.errors import InputError, MissingExtraError

HEIGHT_CHANNELS = ("tip position", "height (measured)", "height (piezo)")
"""Height channels in the order ``height_channel="auto"`` prefers them."""

INSTRUMENT_SUFFIXES = {
    ".jpk-force",
    ".jpk-force-map",
    ".jpk-qi-data",
    ".jpk-qi-series",
    ".ibw",
    ".h5",
    ".tab",
    ".zip",
}
"""Suffixes that only afmformats reads (``.csv`` and ``.txt`` may be either, see
:func:`recognises`)."""

_METADATA_FIELDS = {
    "spring constant": "spring constant (pass spring_constant_N_per_m)",
    "sensitivity": "sensitivity (pass sensitivity_nm_per_V)",
}


def _afmformats():
    try:
        return importlib.import_module("afmformats")
    except ImportError:
        raise MissingExtraError(
            "reading instrument files needs afmformats (pip install afmformats, a dependency "
            "of oocyte-fe)"
        ) from None


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """afmformats logs a traceback for every file it cannot load; the error is ours to report."""
    logger = logging.getLogger("afmformats")
    before = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        logger.setLevel(before)


def recognises(path: str | Path) -> bool:
    """True when afmformats is installed and one of its format recipes accepts ``path``."""
    try:
        afmformats = importlib.import_module("afmformats")
    except ImportError:
        return False
    with _quiet():
        try:
            afmformats.formats.get_recipe(Path(path))
        except (Exception, afmformats.errors.AFMFileFormatError):
            return False
    return True


def _missing_field(message: str) -> str:
    found = [name for name in _METADATA_FIELDS if name in message]
    return " and ".join(found) if found else "metadata"


def load_records(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    modality: str | None = None,
) -> list:
    """afmformats' records of ``path``; every afmformats error becomes :class:`InputError`.

    The spring constant [N/m] and sensitivity [nm/V] given here override the file's.
    """
    path = Path(path)
    afmformats = _afmformats()
    errors = afmformats.errors
    override: dict[str, float] = {}
    if spring_constant_N_per_m is not None:
        override["spring constant"] = float(spring_constant_N_per_m)
    if sensitivity_nm_per_V is not None:
        override["sensitivity"] = float(sensitivity_nm_per_V) * 1e-9
    if not path.is_file():
        raise InputError(path, "", "an existing file")
    with _quiet():
        try:
            records = afmformats.load_data(path, meta_override=override, modality=modality)
        # afmformats' own errors derive from BaseException, not Exception
        except errors.MissingMetaDataError as exc:
            field = _missing_field(str(exc))
            expected = (
                " and ".join(_METADATA_FIELDS[n] for n in _METADATA_FIELDS if n in field)
                or "metadata the file lacks"
            )
            raise InputError(path, field, expected, str(exc)) from None
        except (Exception, errors.AFMFileFormatError) as exc:
            raise InputError(path, "", f"a file afmformats can read ({exc})") from None
    if not records:
        what = f"{modality} " if modality else ""
        raise InputError(path, "", f"at least one {what}curve")
    return records


def choose_height_channel(columns: list[str], requested: str, source: str) -> str:
    """The height channel to use: ``requested``, or with ``"auto"`` the module's order."""
    if requested == "auto":
        for name in HEIGHT_CHANNELS:
            if name in columns:
                return name
        raise InputError(source, "height", f"one of the columns {', '.join(HEIGHT_CHANNELS)}")
    if requested not in HEIGHT_CHANNELS:
        raise InputError(
            source, "height_channel", f"auto or one of {', '.join(HEIGHT_CHANNELS)}", requested
        )
    if requested not in columns:
        present = [c for c in HEIGHT_CHANNELS if c in columns]
        raise InputError(
            source, "height_channel", f"a channel the file holds ({', '.join(present)})", requested
        )
    return requested


def _spring_constant(record, source: str) -> float:
    k = record.metadata.get("spring constant")
    if k is None:
        raise InputError(source, "spring constant", _METADATA_FIELDS["spring constant"])
    return spring_constant_nN_per_um(k, source)


def _travel_um(segment, channel: str, force_nN: np.ndarray, k_nN_per_um: float) -> np.ndarray:
    """Piezo travel towards the sample, um; for ``tip position`` the travel giving that tip."""
    travel = -np.asarray(segment[channel], dtype=float) * 1e6
    if channel == "tip position":
        return travel + force_nN / k_nN_per_um
    return travel


def curve_from_record(
    record, source: str, height_channel: str = "auto", group: str = "", index: int | None = None
) -> ForceCurve:
    """The approach of one afmformats force-distance record as a :class:`ForceCurve`."""
    channel = choose_height_channel(list(record.columns), height_channel, source)
    k = _spring_constant(record, source)
    approach = record.appr
    force = np.asarray(approach["force"], dtype=float) * 1e9
    travel = _travel_um(approach, channel, force, k)
    end = approach_end(travel)
    time = np.asarray(approach["time"], dtype=float)[:end] if "time" in record.columns else None
    position = None
    if index is not None:
        x, y = record.metadata.get("position x"), record.metadata.get("position y")
        if x is not None and y is not None:
            position = (float(x) * 1e6, float(y) * 1e6)
    return ForceCurve(
        travel[:end],
        force[:end],
        k,
        source,
        group,
        time,
        height_channel=channel,
        map_position_um=position,
        curve_index=index,
    )


@dataclass(frozen=True)
class RecordedRamp:
    """Approach and retract of one curve in time, as recorded: time [s], piezo travel towards
    the sample [um], force [nN] (baseline not removed), spring constant k [nN/um].

    ``n_approach`` points of the approach come first; the rest is the retract. Read by
    :func:`ramp_from_record` (instrument files) and :func:`afm.ramp_io.read_ramps` (tables).
    """

    time_s: np.ndarray
    piezo_um: np.ndarray
    force_nN: np.ndarray
    spring_constant_nN_per_um: float
    n_approach: int
    source: str
    group: str = ""
    curve_index: int | None = None

    @property
    def speed_um_per_s(self) -> float:
        """Mean piezo speed of the approach, um/s."""
        end = max(self.n_approach, 2)
        span = float(self.piezo_um[end - 1] - self.piezo_um[0])
        return span / float(self.time_s[end - 1] - self.time_s[0])


def ramp_from_record(
    record, source: str, height_channel: str = "auto", group: str = "", index: int | None = None
) -> RecordedRamp:
    """Approach and retract of one afmformats force-distance record with their times
    (afmformats' segments and ``time`` column). A record without times is refused
    (:class:`InputError`: Ting's method needs the time of every point)."""
    channel = choose_height_channel(list(record.columns), height_channel, source)
    if "time" not in record.columns:
        raise InputError(source, "time", "a time column (the viscoelastic fit needs times)")
    k = _spring_constant(record, source)
    parts = []
    for segment in (record.appr, record.retr):
        force = np.asarray(segment["force"], dtype=float) * 1e9
        if force.size:
            travel = _travel_um(segment, channel, force, k)
            parts.append((np.asarray(segment["time"], dtype=float), travel, force))
    time, travel, force = (np.concatenate(c) for c in zip(*parts, strict=True))
    n_approach = parts[0][0].size if len(parts) == 2 else int(np.argmax(travel)) + 1
    return RecordedRamp(time, travel, force, k, n_approach, source, group, index)


@dataclass(frozen=True)
class _HDF5Record:
    """One curve of an afmformats HDF5 file, as much of afmformats' record as
    :func:`curve_from_record` reads (columns, metadata, the approach segment's arrays)."""

    columns: list[str]
    metadata: dict
    appr: dict[str, np.ndarray]


_HDF5_METADATA = ("spring constant", "position x", "position y", "grid shape x")
"""The metadata :func:`curve_from_record` and :func:`iter_instrument_curves` use."""


def _hdf5_keys(path: Path) -> list[str] | None:
    """The curve groups ("0", "1", ...) of an afmformats HDF5 file in curve order, or None
    when ``path`` is not one (afmformats then reports why)."""
    afmformats = _afmformats()
    h5py = importlib.import_module("h5py")
    try:
        if not afmformats.formats.fmt_hdf5.detect_hdf5(path):
            return None
        with h5py.File(path, "r") as h5:
            return sorted(h5.keys(), key=int)
    except (OSError, KeyError, ValueError):
        return None


def _hdf5_is_map(path: Path, key: str) -> bool:
    """True when the curve group ``key`` carries a map grid (a map of one curve is a map)."""
    h5py = importlib.import_module("h5py")
    with h5py.File(path, "r") as h5:
        return "grid shape x" in h5[key].attrs


def _hdf5_dataset(group, name: str) -> np.ndarray:
    """A whole dataset through h5py's low-level API (half the time of ``group[name][:]``)."""
    h5py = importlib.import_module("h5py")
    dataset = h5py.h5d.open(group.id, name.encode())
    values = np.empty(dataset.shape, dtype=dataset.dtype)
    dataset.read(h5py.h5s.ALL, h5py.h5s.ALL, values)
    return values


def _hdf5_curves(
    path: Path, keys: list[str], height_channel: str, many: bool
) -> Iterator[ForceCurve]:
    """The curves of an afmformats HDF5 file, read in one pass as they are needed.

    afmformats' own loader opens the file again for every column of every curve (about 4 ms
    a curve, 17 s for a 64 x 64 map); the layout is its documented one: a group per curve
    named "0", "1", ..., its metadata as attributes, a dataset per column, ``segment`` 0 the
    approach. Only the force, time, the height channel used and the metadata used are read.
    """
    h5py = importlib.import_module("h5py")
    with h5py.File(path, "r") as h5:
        for key in keys:
            index = int(key) if many else None
            source = f"{path} (curve {index})" if many else str(path)
            try:
                group = h5[key]
                columns = sorted(group.keys())
                channel = choose_height_channel(columns, height_channel, source)
                approach = _hdf5_dataset(group, "segment") == 0
                wanted = [c for c in ("force", "time", channel) if c in columns]
                arrays = {c: _hdf5_dataset(group, c)[approach] for c in wanted}
                attrs = group.attrs
                metadata = {m: attrs[m] for m in _HDF5_METADATA if m in attrs}
            except (OSError, KeyError, ValueError) as exc:
                raise InputError(source, "", f"a readable afmformats HDF5 curve ({exc})") from None
            record = _HDF5Record(columns, metadata, arrays)
            yield curve_from_record(record, source, channel, path.parent.name, index)


def hdf5_map_keys(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
) -> list[str] | None:
    """The curve groups of an afmformats HDF5 file read in one pass (:func:`_hdf5_curves`),
    or None for any other file, or when calibration is passed (afmformats' HDF5 loader
    refuses overrides: its forces are stored in N, so it reports that)."""
    path = Path(path)
    if path.suffix.lower() != ".h5" or (spring_constant_N_per_m, sensitivity_nm_per_V) != (
        None,
        None,
    ):
        return None
    return _hdf5_keys(path)


def iter_instrument_curves(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
    selection: range | None = None,
) -> Iterator[ForceCurve]:
    """Every force-distance curve of an instrument file (all curves of a force map), one at a
    time (an afmformats HDF5 force map is read as the curves are taken); with ``selection``
    only the curves at those positions in file order (an HDF5 map reads no other).

    Curves of a multi-curve file carry their index and map position and are named
    ``"<file> (curve <i>)"`` in errors. A curve that cannot be read raises
    :class:`InputError`.
    """
    path = Path(path)
    keys = hdf5_map_keys(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    if keys is not None:
        many = len(keys) > 1 or _hdf5_is_map(path, keys[0])
        chosen = keys if selection is None else [keys[i] for i in selection if i < len(keys)]
        yield from _hdf5_curves(path, chosen, height_channel, many)
        return
    records = load_records(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    records = [r for r in records if r.modality == "force-distance"] or records
    many = len(records) > 1 or "grid shape x" in records[0].metadata
    for i, record in enumerate(records):
        if selection is not None and i not in selection:
            continue
        index = int(record.metadata.get("enum", i)) if many else None
        source = f"{path} (curve {index})" if many else str(path)
        yield curve_from_record(record, source, height_channel, path.parent.name, index)


def read_instrument_curves(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> list[ForceCurve]:
    """:func:`iter_instrument_curves` as a list."""
    return list(
        iter_instrument_curves(path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel)
    )


def read_instrument_file(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
) -> ForceCurve:
    """The first force-distance curve of an instrument file (:func:`read_instrument_curves`)."""
    return read_instrument_curves(
        path, spring_constant_N_per_m, sensitivity_nm_per_V, height_channel
    )[0]


def read_instrument_creep(
    path: str | Path,
    spring_constant_N_per_m: float | None = None,
    sensitivity_nm_per_V: float | None = None,
    height_channel: str = "auto",
    n_sigma: float = 5.0,
) -> CreepData:
    """The force-clamp hold of an instrument creep file as :class:`CreepData`.

    The file has three segments: approach (0), hold at constant force (1), retract (2). On the
    approach the baseline (offset and tilt, :mod:`afm.baseline`) is fitted and contact is the
    deviation estimate (:func:`afm.contact_point.deviation_index`, ``n_sigma`` noise SDs); x0
    is the tip position there. During the hold::

        F(t)     = F_recorded(t) - baseline(piezo at contact)              [nN]
        delta(t) = x(t) - x0,   x = piezo - F/k                            [um]

    and t starts at the start of the hold.
    """
    path = Path(path)
    source = str(path)
    records = load_records(path, spring_constant_N_per_m, sensitivity_nm_per_V)
    record = records[0]
    if record.modality != "creep-compliance":
        raise InputError(
            path, "imaging mode", "a creep-compliance (force-clamp) file", record.modality
        )
    approach = curve_from_record(record, source, height_channel)
    baseline = fit_baseline(approach)
    corrected = remove_baseline(approach, baseline)
    contact = deviation_index(corrected.force_nN, baseline.noise_nN, n_sigma, source)
    x0 = float(corrected.tip_position_um[contact])
    hold = record.intr
    if len(hold["force"]) == 0:
        raise InputError(path, "segment", "a hold segment after the approach")
    k = approach.spring_constant_nN_per_um
    force = np.asarray(hold["force"], dtype=float) * 1e9 - baseline(approach.piezo_um[contact])
    travel = _travel_um(hold, approach.height_channel, np.asarray(hold["force"]) * 1e9, k)
    indentation = travel - force / k - x0
    return CreepData(np.asarray(hold["time"], dtype=float), force, indentation, source)
