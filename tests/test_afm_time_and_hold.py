"""Issue 26, class 5: AFM curve files with a decreasing or NaN time column, and creep records
whose indentation shrinks during the hold, are refused when read, naming file, column and row.

Each test reads a file through the public readers (:func:`afm.curve_io.read_curve`,
:func:`afm.curve_io.read_creep`); before the fix the first three were read without a word.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from afm.curve_io import read_creep, read_curve, write_creep
from afm.prony_series import RelaxationProny
from afm.synthetic import creep_indentation, indentation_curve
from afm.viscoelastic import RampCurve
from oocyte_fe.errors import InputError

TRUTH = RelaxationProny(7.01 / 3, (0.3,), (0.5,))
HOLD_T = np.linspace(0.0, 6.0, 301)


def _curve_file(tmp_path: Path, time: np.ndarray) -> Path:
    curve = indentation_curve(7.01, 5.0, n_points=time.size)
    rows = "\n".join(
        f"{t!r},{z!r},{f!r}"
        for t, z, f in zip(
            time.tolist(), curve.piezo_um.tolist(), curve.force_nN.tolist(), strict=True
        )
    )
    path = tmp_path / "curve.csv"
    path.write_text(f"# spring_constant_N_per_m = 0.07\ntime_s,piezo_um,force_nN\n{rows}\n")
    return path


def _creep_file(tmp_path: Path, time: np.ndarray, indentation: np.ndarray) -> Path:
    contact, k = 5.0, 0.07
    force = np.full(time.size, 5.0)
    height = contact + indentation + force / (k * 1e3)
    return write_creep(tmp_path / "hold.csv", time, force, height, contact, k)


def test_a_curve_with_increasing_time_is_read_with_it(tmp_path: Path) -> None:
    time = np.linspace(0.0, 1.0, 200)
    curve = read_curve(_curve_file(tmp_path, time))
    np.testing.assert_allclose(curve.time_s, time, rtol=1e-15)


def test_a_curve_whose_time_decreases_is_refused_naming_the_row(tmp_path: Path) -> None:
    time = np.linspace(0.0, 1.0, 200)
    time[120] = time[118]  # a step back at data row 121
    with pytest.raises(InputError) as info:
        read_curve(_curve_file(tmp_path, time))
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'curve.csv'}: time_s: expected values increasing")
    assert "data row 121 after data row 120" in message
    assert "\n" not in message


def test_a_curve_with_a_nan_time_is_refused_naming_the_row(tmp_path: Path) -> None:
    time = np.linspace(0.0, 1.0, 200)
    time[7] = math.nan
    with pytest.raises(
        InputError, match=r"curve.csv: time_s: expected finite numbers \(data row 8"
    ):
        read_curve(_curve_file(tmp_path, time))


def test_a_creep_record_whose_indentation_shrinks_is_refused_when_read(tmp_path: Path) -> None:
    # the hold recorded backwards: indentation falling from 2.6 to 2.4 um under a clamped force
    shrinking = creep_indentation(TRUTH, HOLD_T, 5.0)[::-1]
    with pytest.raises(InputError) as info:
        read_creep(_creep_file(tmp_path, HOLD_T, shrinking))
    message = str(info.value)
    assert "hold.csv: indentation_um: expected an indentation that does not shrink" in message
    assert "2.609 um over rows 1-60, 2.407 um over rows 242-301" in message


def test_a_creeping_record_is_read(tmp_path: Path) -> None:
    growing = creep_indentation(TRUTH, HOLD_T, 5.0)
    data = read_creep(_creep_file(tmp_path, HOLD_T, growing))
    np.testing.assert_allclose(data.indentation_um, growing, rtol=1e-8)


@pytest.mark.parametrize(("row", "value"), [(40, math.nan), (40, 0.5)])
def test_a_creep_record_with_a_bad_time_names_the_row(
    tmp_path: Path, row: int, value: float
) -> None:
    time = HOLD_T.copy()
    time[row] = value  # NaN, or 0.5 s after 0.78 s (a step back)
    with pytest.raises(InputError, match=f"hold.csv: time_s: .*data row {row + 1}"):
        read_creep(_creep_file(tmp_path, time, creep_indentation(TRUTH, HOLD_T, 5.0)))


def test_a_ramp_whose_time_steps_back_names_the_row() -> None:
    # the viscoelastic ramp record holds its time column to the same check
    time = np.linspace(0.0, 1.0, 50)
    time[30] = 0.2
    with pytest.raises(InputError, match=r"ramp.csv: time_s: .*\(data row 31 after data row 30\)"):
        RampCurve(time, np.linspace(0.0, 2.0, 50), np.zeros(50), "ramp.csv")


def test_a_creep_record_pulling_on_the_cell_is_refused_as_such(tmp_path: Path) -> None:
    # an all-negative clamp force was refused as "SD/mean = inf"
    path = _creep_file(tmp_path, HOLD_T, creep_indentation(TRUTH, HOLD_T, 5.0))
    text = path.read_text().splitlines()
    header = next(i for i, line in enumerate(text) if not line.startswith("#"))
    names = text[header].split(",")
    col = names.index("force_nN")
    rows = [line.split(",") for line in text[header + 1 :]]
    for row in rows:
        row[col] = repr(-float(row[col]))
    path.write_text("\n".join(text[: header + 1] + [",".join(r) for r in rows]) + "\n")
    with pytest.raises(InputError) as info:
        read_creep(path)
    message = str(info.value)
    assert "hold.csv: force_nN: expected a positive clamped force" in message
    assert "mean = -5 nN" in message
