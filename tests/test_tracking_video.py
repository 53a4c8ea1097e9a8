"""Video I/O and the ``track`` route on a synthetic TIFF stack with known boxes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.tracking.cli_track import parse_box, track_video
from oocyte_fe.tracking.synthetic import SequenceSpec, generate
from oocyte_fe.tracking.video import (
    Calibration,
    read_boxes_csv,
    read_frames,
    write_tiff,
    write_track_csv,
)

CLEAR = SequenceSpec(
    name="clear",
    seed=9,
    n_frames=40,
    enter_frames=5,
    approach_frames=30,
    displacement_um=6.0,
    contrast=0.3,
    shape=(160, 160),
)


def test_tiff_round_trip_and_units(tmp_path: Path) -> None:
    frames = np.arange(3 * 4 * 5, dtype=float).reshape(3, 4, 5) * 100
    write_tiff(tmp_path / "s.tif", frames)
    np.testing.assert_array_equal(read_frames(tmp_path / "s.tif"), frames)
    cal = Calibration(0.25, 20.0)
    np.testing.assert_allclose(cal.to_um([4.0, 8.0]), [1.0, 2.0])
    np.testing.assert_allclose(cal.times_s(3), [0.0, 0.05, 0.1])


def test_bad_inputs_name_what_was_expected(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="X,Y,W,H"):
        parse_box("1,2,3")
    with pytest.raises(InputError, match="existing"):
        read_frames(tmp_path / "missing.tif")
    (tmp_path / "junk.tif").write_text("not a tiff")
    with pytest.raises(InputError, match="readable"):
        read_frames(tmp_path / "junk.tif")


def test_track_video_follows_a_clear_spindle(tmp_path: Path) -> None:
    """A high-contrast spindle (30 % of background): every frame within 2 um of the truth;
    the outputs are written and the CSV's um columns are the px ones x pixel size."""
    seq = generate(CLEAR)
    write_tiff(tmp_path / "v.tif", seq.frames)
    cal = Calibration(CLEAR.pixel_um, CLEAR.fps)
    write_track_csv(tmp_path / "truth.csv", seq.boxes, np.ones(len(seq.boxes)), cal)
    box = ",".join(f"{v:.2f}" for v in seq.boxes[0])
    out = tmp_path / "out"
    summary = track_video(
        tmp_path / "v.tif", box, out, CLEAR.pixel_um, CLEAR.fps, tmp_path / "truth.csv"
    )
    for name in ("track.csv", "overlay.gif", "trajectory.png", "precision_success.png"):
        assert (out / name).is_file()
    assert summary["precision_2um"] == 1.0
    tracked = read_boxes_csv(out / "track.csv")
    assert tracked.shape == seq.boxes.shape
    rows = np.genfromtxt(out / "track.csv", delimiter=",", names=True)
    np.testing.assert_allclose(rows["cx_um"], rows["cx_px"] * CLEAR.pixel_um, atol=1e-3)
    assert len(read_frames(out / "overlay.gif")) == len(seq.frames)


def test_track_command_writes_the_outputs_and_refuses_a_bad_box(tmp_path: Path) -> None:
    """``oocyte-fe track``: the same tracking from the command line (exit 0, outputs, the
    precision at 2 um printed); a malformed box is one line and exit 2."""
    from typer.testing import CliRunner

    from oocyte_fe.cli import app

    seq = generate(CLEAR)
    write_tiff(tmp_path / "v.tif", seq.frames)
    cal = Calibration(CLEAR.pixel_um, CLEAR.fps)
    write_track_csv(tmp_path / "truth.csv", seq.boxes, np.ones(len(seq.boxes)), cal)
    box = ",".join(f"{v:.2f}" for v in seq.boxes[0])
    out = tmp_path / "out"
    args = ["track", str(tmp_path / "v.tif"), "--box", box, "--out", str(out)]
    args += ["--pixel-um", str(CLEAR.pixel_um), "--truth", str(tmp_path / "truth.csv")]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "precision_2um = 1" in result.output
    assert (out / "track.csv").is_file() and (out / "trajectory.png").is_file()
    bad = CliRunner().invoke(app, ["track", str(tmp_path / "v.tif"), "--box", "1,2"])
    assert bad.exit_code == 2
    assert "X,Y,W,H" in bad.output
