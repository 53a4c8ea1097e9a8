"""Fuzz the files a case reads: ``case.toml`` itself, every data file, and what a path names.

The data-file inputs are found from the kinds' models (:func:`readers_of`), so a new kind's data
files are covered with no new code. Contents: random bytes, other encodings (Latin-1,
UTF-16), deep nesting, CSV tables with right, wrong and misspelt columns and cells that are
NaN, inf, huge, tiny or text. Paths: a directory, a FIFO, a symlink loop, a symlink out of the
case folder, ``..``, an absolute path, a name over 255 bytes. Every outcome is one line naming
the file (and the field or column), or a case that loads; nothing blocks, nothing else escapes.
"""

from __future__ import annotations

import copy
import os
import shutil
from pathlib import Path

import pytest
import tomli_w
from hypothesis import given
from hypothesis import strategies as st
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import discover, load_case
from oocyte_fe.runner.schema import readers_of
from tests.fuzz.harness import check_outcome, fuzz_settings, hang_guard
from tests.fuzz.test_fuzz_case_schema import bases, builtin_kinds  # noqa: F401 - fixture

COLUMNS = [
    "displacement_um",
    "force_experiment_uN",
    "force_simulation_uN",
    "pressure_hPa",
    "pressure_kPa",
    "pressure_psi",
    "ratio_experiment",
    "ratio_simulation",
    "strain_rate_1_s",
    "viscosity_Pa_s",
    "viscosity_mPa_s",
    "time_s",
    "force_nN",
    "indentation_um",
    "height_um",
    "displacment_um",
    "ratio_experimnt",
    "",
]
CELLS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["nan", "inf", "-inf", "1e308", "1e-308", "1e400", "0", "-1", "", "x", "1,2"]),
    st.integers(-(10**20), 10**20).map(str),
    st.text(max_size=6),
)


@st.composite
def csv_tables(draw: st.DrawFn) -> bytes:
    header = draw(st.lists(st.sampled_from(COLUMNS), min_size=0, max_size=4))
    rows = draw(st.lists(st.lists(CELLS, min_size=0, max_size=5), max_size=6))
    text = ",".join(header) + "\n" + "\n".join(",".join(r) for r in rows)
    encoding = draw(st.sampled_from(["utf-8", "utf-8", "latin-1", "utf-16"]))
    return text.encode(encoding, errors="replace")


CONTENTS = st.one_of(
    csv_tables(),
    st.binary(max_size=200),
    st.integers(1, 3000).map(lambda n: b"a = " + b"[" * n + b"]" * n + b"\n"),
    st.integers(1, 3000).map(lambda n: b"a = " + b"{b = " * n + b"1" + b"}" * n + b"\n"),
    st.text(max_size=100).map(lambda t: t.encode("utf-16")),
    st.sampled_from([b"", b"\xef\xbb\xbf", b"\x00\x01", "é,ü\n1,2".encode("latin-1")]),
)


DEGENERATE = ["one row", "equal rows", "equal column", "huge last", "tiny last"]
"""Tables a fit cannot be made to: one row, all rows or one column equal, a last value of
1e300 or 1e-300 (issue 26, class 4); the readers refuse them, naming the file and column."""


def _perturb(original: bytes, data: st.DataObject) -> bytes:
    """The real table with one cell, one header name or one line changed, or made degenerate."""
    lines = original.decode().splitlines()
    body = [i for i, line in enumerate(lines) if line and not line.startswith("#")]
    i = data.draw(st.sampled_from(body), label="line")
    cells = lines[i].split(",")
    j = data.draw(st.integers(0, len(cells) - 1), label="cell")
    how = data.draw(
        st.sampled_from(["cell", "cell", "drop line", "drop column", *DEGENERATE]), label="how"
    )
    rows = body[1:]  # below the header
    if how in DEGENERATE and len(rows) < 2:
        return original
    if how == "one row":
        lines = [lines[k] for k in body[:2]]
    elif how == "equal rows":
        lines = [lines[body[0]]] + [lines[rows[0]]] * len(rows)
    elif how == "equal column":
        first = lines[rows[0]].split(",")
        for k in rows:
            row = lines[k].split(",")
            lines[k] = ",".join(first[m] if m == j else c for m, c in enumerate(row))
    elif how in ("huge last", "tiny last"):
        row = lines[rows[-1]].split(",")
        row[j] = "1e300" if how == "huge last" else "1e-300"
        lines[rows[-1]] = ",".join(row)
    elif how == "cell":
        cells[j] = data.draw(st.one_of(CELLS, st.sampled_from(COLUMNS)), label="new cell")
        lines[i] = ",".join(cells)
    elif how == "drop line":
        del lines[i]
    else:
        lines = [",".join(c for k, c in enumerate(x.split(",")) if k != j) for x in lines]
    return "\n".join(lines).encode()


def _data_fields(kind: str) -> list[tuple[str, ...]]:
    model = builtin_kinds()[kind].inputs
    fields = [(name,) for name in readers_of(model)]
    for name, info in model.model_fields.items():
        if isinstance(info.annotation, type) and hasattr(info.annotation, "model_fields"):
            fields += [(name, sub) for sub in readers_of(info.annotation)]
    return fields


def _with_data(bases: dict) -> list[str]:  # noqa: F811 - the fixture's value
    return sorted(k for k in bases if _data_fields(k))


@fuzz_settings(ci_examples=120, full_examples=2000)
@given(data=st.data())
def test_data_file_contents(bases: dict, data: st.DataObject) -> None:  # noqa: F811
    kind = data.draw(st.sampled_from(_with_data(bases)), label="kind")
    folder, raw = bases[kind]
    field = data.draw(st.sampled_from(_data_fields(kind)), label="field")
    inputs = raw["inputs"]
    for key in field:
        inputs = inputs.get(key, {}) if isinstance(inputs, dict) else {}
    if not isinstance(inputs, str):
        return  # an optional data file the case does not use
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    target = folder / inputs
    original = target.read_bytes()
    if data.draw(st.booleans(), label="perturb the real table"):
        target.write_bytes(_perturb(original, data))
    else:
        target.write_bytes(data.draw(CONTENTS, label="content"))
    try:
        check_outcome(f"data files ({kind})", lambda: load_case(folder), names=target.name)
    finally:
        target.write_bytes(original)


TIME_FAULTS = ["time back", "time repeated", "time nan", "hold shrinks"]
"""Issue 26, class 5, in the case's own tables: a time cell set below or equal to the one above
it or to NaN, or the hold's height/indentation column reversed (it shrinks under the clamp)."""


def _timed_tables(bases: dict) -> list[tuple[str, tuple[str, ...]]]:  # noqa: F811
    """(kind, data field) of every data table with a ``time_s`` column (a creep record)."""
    found = []
    for kind in _with_data(bases):
        folder, raw = bases[kind]
        for field in _data_fields(kind):
            value = raw["inputs"]
            for key in field:
                value = value.get(key, {}) if isinstance(value, dict) else {}
            if isinstance(value, str) and (folder / value).suffix == ".csv":
                header = [n for n in (folder / value).read_text().splitlines() if n[:1] != "#"][0]
                if "time_s" in header.split(","):
                    found.append((kind, field))
    return found


def test_creep_tables_are_found(bases: dict) -> None:  # noqa: F811
    assert ("nmsd_vs_fe", ("creep_data",)) in _timed_tables(bases)


@fuzz_settings(ci_examples=40, full_examples=1000)
@given(data=st.data())
def test_time_columns_and_holds(bases: dict, data: st.DataObject) -> None:  # noqa: F811
    """Every fault of :data:`TIME_FAULTS` is refused naming the file, the column and, for the
    time, the data row: never read silently."""
    kind, field = data.draw(st.sampled_from(_timed_tables(bases)), label="table")
    folder, raw = bases[kind]
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    name = raw["inputs"]
    for key in field:
        name = name[key]
    target = folder / name
    original = target.read_bytes()
    lines = original.decode().splitlines()
    at = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    header, rows = lines[at].split(","), [line.split(",") for line in lines[at + 1 :]]
    fault = data.draw(st.sampled_from(TIME_FAULTS), label="fault")
    if fault == "hold shrinks":
        column = next(c for c in ("indentation_um", "height_um") if c in header)
        j = header.index(column)
        values = [r[j] for r in rows][::-1]
        for r, v in zip(rows, values, strict=True):
            r[j] = v
        expected = "indentation_um: expected an indentation that does not shrink"
    else:
        row = data.draw(st.integers(1, len(rows) - 1), label="data row (0-based)")
        j = header.index("time_s")
        before = float(rows[row - 1][j])
        back = data.draw(st.floats(0.0, 1e3), label="step back") if fault == "time back" else 0
        rows[row][j] = "nan" if fault == "time nan" else repr(before - back)
        what = "finite numbers" if fault == "time nan" else "values increasing row by row"
        expected = f"time_s: expected {what} (data row {row + 1}"
    lines[at + 1 :] = [",".join(r) for r in rows]
    target.write_text("\n".join(lines) + "\n")
    try:
        case = check_outcome(f"time columns and holds ({kind})", lambda: load_case(folder))
        assert case is None, f"silent acceptance: {fault} in {target.name}"
        with pytest.raises(InputError) as info:
            load_case(folder)
        message = str(info.value)
        assert message.startswith(str(target)) and expected in message, message
    finally:
        target.write_bytes(original)


@fuzz_settings(ci_examples=60, full_examples=1000)
@given(content=CONTENTS)
def test_case_toml_bytes(bases: dict, content: bytes) -> None:  # noqa: F811
    folder, _ = bases["afm_creep_prony"]
    (folder / "case.toml").write_bytes(content)
    check_outcome("case.toml bytes", lambda: load_case(folder), names="case.toml")


def _special_paths(folder: Path) -> dict[str, str]:
    """Path values naming things that are not a readable data file inside the case folder."""
    (folder / "a_directory").mkdir(exist_ok=True)
    fifo = folder / "a_fifo"
    if not fifo.exists():
        os.mkfifo(fifo)
    loop = folder / "a_loop"
    if not loop.is_symlink():
        loop.symlink_to(folder / "a_loop")
    out = folder / "link_out"
    if not out.is_symlink():
        out.symlink_to("/etc/hostname")
    return {
        "directory": "a_directory",
        "fifo": "a_fifo",
        "symlink loop": "a_loop",
        "symlink out": "link_out",
        "parent": "../afm_creep_prony/case.toml",
        "absolute": "/etc/passwd",
        "dot dot": "..",
        "long name": "x" * 300 + ".csv",
        "long utf-8 name": "é" * 130 + ".csv",
        "missing": "nowhere.csv",
    }


@pytest.mark.parametrize(
    "what",
    [
        "directory",
        "fifo",
        "symlink loop",
        "symlink out",
        "parent",
        "absolute",
        "dot dot",
        "long name",
        "long utf-8 name",
        "missing",
    ],
)
def test_data_path_is_refused(bases: dict, what: str) -> None:  # noqa: F811
    for kind in _with_data(bases):
        folder, raw = bases[kind]
        raw = copy.deepcopy(raw)
        field = _data_fields(kind)[0]
        table = raw["inputs"]
        for key in field[:-1]:
            table = table[key]
        table[field[-1]] = _special_paths(folder)[what]
        (folder / "case.toml").write_text(tomli_w.dumps(raw))
        with hang_guard(10), pytest.raises(InputError) as info:
            load_case(folder)
        message = str(info.value)
        assert f"inputs.{'.'.join(field)}" in message, message
        assert "root:" not in message and "localhost" not in message  # no outside content


def test_validate_exits_2_on_bad_data(tmp_path: Path) -> None:
    case = tmp_path / "microchannel_carreau_fit"
    shutil.copytree(Path(__file__).resolve().parents[2] / "cases" / case.name, case)
    (case / "table2_viscosity.csv").write_text("strain_rate_1_s,viscosity_Pa_s\nnan,1\n")
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert "table2_viscosity.csv" in result.output
    assert "Traceback" not in result.output


@pytest.mark.parametrize("what", ["long name", "fifo", "symlink loop", "missing", "file"])
def test_case_folder_argument_is_refused(tmp_path: Path, what: str) -> None:
    target = tmp_path / "x"
    if what == "long name":
        target = tmp_path / ("x" * 300)
    elif what == "fifo":
        os.mkfifo(target)
    elif what == "symlink loop":
        target.symlink_to(target)
    elif what == "file":
        target.write_text("not a folder")
    with hang_guard(10), pytest.raises(InputError):
        discover([target])
