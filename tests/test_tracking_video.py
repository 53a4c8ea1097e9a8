"""Video I/O and the ``track`` route on a synthetic TIFF stack with known boxes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.tracking.cli_track import parse_box, track_video
from oocyte_fe.tracking.synthetic import SequenceSpec, generate
from oocyte_fe.tracking.tracker import track
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


def _clip(tmp_path: Path) -> tuple[Path, str, np.ndarray]:
    seq = generate(CLEAR)
    write_tiff(tmp_path / "v.tif", seq.frames)
    return tmp_path / "v.tif", ",".join(f"{v:.2f}" for v in seq.boxes[0]), seq.boxes


@pytest.mark.parametrize(
    ("box", "says"),
    [
        ("nan,10,20,20", "four finite numbers"),
        ("10,10,inf,20", "four finite numbers"),
        ("200,200,20,20", "inside the 160 x 160 px frame"),
        ("150,10,20,20", "inside the 160 x 160 px frame"),
        ("-5,10,20,20", "inside the 160 x 160 px frame"),
        ("0,0,170,20", "W <= 160 and H <= 160"),
    ],
)
def test_track_command_refuses_a_bad_box_before_tracking(
    tmp_path: Path, box: str, says: str
) -> None:
    """NaN, infinite, wholly or partly outside the frame, larger than the frame: one line on
    the console, exit 2, no output folder (refused before tracking)."""
    from typer.testing import CliRunner

    from oocyte_fe.cli import app

    video, _, _ = _clip(tmp_path)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["track", str(video), "--box", box, "--out", str(out)])
    assert result.exit_code == 2
    assert says in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize("empty", ["video", "--truth"])
def test_track_command_names_an_empty_path_argument(tmp_path: Path, empty: str) -> None:
    """An empty video or --truth argument was read as the folder '.' (the message named '.');
    now one line naming the argument, exit 2, no output folder."""
    from typer.testing import CliRunner

    from oocyte_fe.cli import app

    video, box, _ = _clip(tmp_path)
    out = tmp_path / "out"
    args = ["track", "" if empty == "video" else str(video), "--box", box, "--out", str(out)]
    if empty == "--truth":
        args += ["--truth", ""]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2
    assert f"{empty}: a file path, not an empty argument" in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize(
    ("shape", "says"),
    [
        ((4, 3, 40, 50), "not planar colour"),
        ((40, 50, 3), "not a single colour image"),
        ((40, 50), "at least 2"),
    ],
)
def test_colour_layouts_read_as_narrow_frames_are_refused(
    tmp_path: Path, shape: tuple[int, ...], says: str
) -> None:
    """A planar RGB stack (T, 3, H, W) and a single RGB image (H, W, 3) were read as frames 3
    px high or wide; now each is one InputError. An interleaved colour stack (T, H, W, 3) is
    averaged over its channels: (2, 3, 4, 3) channels 0, 1, 2 give their mean."""
    import tifffile

    tifffile.imwrite(tmp_path / "c.tif", np.ones(shape, dtype=np.uint16), photometric="minisblack")
    with pytest.raises(InputError, match=says):
        read_frames(tmp_path / "c.tif")
    rgb = np.zeros((2, 30, 40, 3), dtype=np.uint16) + np.array([3, 6, 9], dtype=np.uint16)
    tifffile.imwrite(tmp_path / "rgb.tif", rgb, photometric="rgb")
    np.testing.assert_allclose(read_frames(tmp_path / "rgb.tif"), 6.0)


def test_truth_with_wrong_rows_is_refused_before_tracking(tmp_path: Path) -> None:
    """``--truth`` with 39 rows for 40 frames: InputError naming the rows, nothing written."""
    video, box, truth = _clip(tmp_path)
    cal = Calibration(CLEAR.pixel_um, CLEAR.fps)
    write_track_csv(tmp_path / "truth.csv", truth[:-1], np.ones(len(truth) - 1), cal)
    out = tmp_path / "out"
    with pytest.raises(InputError, match="40 boxes, one per frame, got 39"):
        track_video(video, box, out, truth=tmp_path / "truth.csv")
    assert not out.exists()
    with pytest.raises(InputError, match=r"pixel_um: expected a number in \[1e-06, 1e\+06\] um"):
        track_video(video, box, out, pixel_um=float("nan"))


def test_blank_frames_and_a_featureless_box_give_low_confidence(tmp_path: Path) -> None:
    """Confidence ``r e`` (tracker.FrameEstimate): on a constant clip and on a box over pure
    shot noise it is at most 0.05 on every frame (r alone was 1.43, like a good track); on the
    clear spindle the contrast factor is 1 on every frame (confidence = r)."""
    rng = np.random.default_rng(3)
    blank = np.full((30, 120, 120), 2000.0)
    noise = 2000.0 + rng.normal(size=(30, 120, 120)) * np.sqrt(2000.0)
    box = (40.0, 50.0, 40.0, 20.0)
    assert track(blank, box).reliability[-1] == pytest.approx(1 / 0.7, rel=1e-9)  # r alone
    for frames in (blank, noise):
        assert track(frames, box).confidence.max() <= 0.05
    seq = generate(CLEAR)
    clear = track(seq.frames, tuple(seq.boxes[0]))
    np.testing.assert_allclose(clear.confidence, clear.reliability, rtol=1e-12)


def test_track_command_runs_the_chosen_tracker(tmp_path: Path) -> None:
    """``--tracker scale --max-speed 5``: track.csv holds the boxes of the library's
    ``track`` with MFAKCF (scale) and the reach gate of 5 um/s (to the CSV's 3 decimals), the
    box changes size (the default's never does), and the plot is labelled with the tracker."""
    from dataclasses import replace

    from typer.testing import CliRunner

    from oocyte_fe.cli import app
    from oocyte_fe.tracking.tracker import MFAKCF_SCALE, max_step_px

    video, box, truth = _clip(tmp_path)
    cal = Calibration(CLEAR.pixel_um, CLEAR.fps)
    write_track_csv(tmp_path / "truth.csv", truth, np.ones(len(truth)), cal)
    out = tmp_path / "out"
    args = ["track", str(video), "--box", box, "--out", str(out), "--tracker", "scale"]
    args += ["--max-speed", "5", "--pixel-um", str(CLEAR.pixel_um), "--fps", str(CLEAR.fps)]
    result = CliRunner().invoke(app, [*args, "--truth", str(tmp_path / "truth.csv")])
    assert result.exit_code == 0, result.output
    config = replace(MFAKCF_SCALE, max_step_px=max_step_px(5.0, CLEAR.fps, CLEAR.pixel_um))
    expected = track(read_frames(video), parse_box(box), config).boxes
    tracked = read_boxes_csv(out / "track.csv")
    np.testing.assert_allclose(tracked, expected, atol=5e-4)
    assert np.ptp(tracked[:, 2]) > 0.5  # the scale filter resized the box


def test_track_command_refuses_an_unknown_tracker_and_a_bad_speed(tmp_path: Path) -> None:
    """One line, exit 2, nothing written; the command's default speed is the library's."""
    import inspect

    from typer.testing import CliRunner

    from oocyte_fe.cli import app
    from oocyte_fe.cli import track as track_command
    from oocyte_fe.tracking.cli_track import MAX_SPEED_UM_S

    video, box, _ = _clip(tmp_path)
    out = tmp_path / "out"
    for extra, says in (
        (["--tracker", "csrt"], "--tracker: tracker: expected one of mfakcf, signature, rotation"),
        (["--max-speed", "0"], "--max-speed: max_speed_um_s: expected a spindle speed in"),
        (["--max-speed", "nan"], "--max-speed: max_speed_um_s: expected a spindle speed in"),
        (["--max-speed", "1e300"], "--max-speed: max_speed_um_s: expected a spindle speed in"),
    ):
        result = CliRunner().invoke(
            app, ["track", str(video), "--box", box, "--out", str(out)] + extra
        )
        assert result.exit_code == 2, result.output
        assert says in result.output and len(result.output.strip().splitlines()) == 1
        assert not out.exists()
    default = inspect.signature(track_command).parameters["max_speed"].default.default
    assert default == MAX_SPEED_UM_S


def test_misleading_inputs_get_the_message_of_what_is_wrong(tmp_path: Path) -> None:
    """A TIFF renamed .txt (it read as one 64 x 64 frame: "at least 2 frames"), a (T, Z, H, W)
    stack (read as "at least 2 frames" too), a truth file with other column names (a bare
    ``'x_px'`` KeyError) and a non-number in a box column: each message names the cause."""
    import tifffile

    tifffile.imwrite(tmp_path / "s.tif", np.ones((12, 64, 64), dtype=np.uint16))
    (tmp_path / "s.txt").write_bytes((tmp_path / "s.tif").read_bytes())
    with pytest.raises(InputError, match=r"by its extension: \.tif, .*got '\.txt'"):
        read_frames(tmp_path / "s.txt")
    tifffile.imwrite(tmp_path / "z.tif", np.ones((12, 5, 64, 64), dtype=np.uint16))
    with pytest.raises(InputError, match=r"\(T, Z, H, W\).*got \(12, 5, 64, 64\)"):
        read_frames(tmp_path / "z.tif")
    (tmp_path / "t.csv").write_text("x,y,w,h\n1,2,3,4\n")
    with pytest.raises(InputError, match=r"header: expected the columns x_px, y_px, w_px, h_px"):
        read_boxes_csv(tmp_path / "t.csv")
    (tmp_path / "t2.csv").write_text("x_px,y_px,w_px,h_px\n1,2,3,4\n1,a,3,4\n")
    with pytest.raises(InputError, match=r"data row 2: expected numbers in x_px.*'1, a, 3, 4'"):
        read_boxes_csv(tmp_path / "t2.csv")
