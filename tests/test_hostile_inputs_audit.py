"""Regression tests of a hostile-input audit of the command line (``track``, ``new``,
``validate``, ``run``): each input below once gave a traceback, a hang, a message without the
field or a silently wrong result; now it is one line naming the file or option, the field and
what was expected (exit code 2 on the command line, :class:`InputError` in the library).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import ValidationError
from typer.testing import CliRunner

from afm.curve import ForceCurve
from oocyte_fe.cli import app
from oocyte_fe.crosscheck.fe_press import FeSettings, press_experiment
from oocyte_fe.crosscheck.scenario import PressScenario
from oocyte_fe.errors import InputError
from oocyte_fe.experiment.description import Cone, Experiment
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.experiment.tools import cone_profile
from oocyte_fe.fe.material import Material
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan
from oocyte_fe.tracking.video import write_overlay_gif, write_tiff
from tests.case_copies import edited_case

CASES = Path(__file__).resolve().parents[1] / "cases"
BOX = "20,20,16,16"


def _one_line_error(args: list[str], *names: str) -> str:
    """Run the CLI: exit 2, one ``error:`` line naming each of ``names``, no traceback."""
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2, result.output
    assert not isinstance(result.exception, Exception) or isinstance(
        result.exception, SystemExit
    ), repr(result.exception)
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.output
    for name in names:
        assert name in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def video(tmp_path: Path) -> Path:
    """A 4-frame 64 x 64 px TIFF stack of textured noise."""
    rng = np.random.default_rng(0)
    path = tmp_path / "v.tif"
    write_tiff(path, 1000.0 + 100.0 * rng.random((4, 64, 64)))
    return path


def _truth(tmp_path: Path, rows: list[str]) -> Path:
    path = tmp_path / "truth.csv"
    path.write_text("x_px,y_px,w_px,h_px\n" + "\n".join(rows) + "\n")
    return path


# --- track ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("first", "says"),
    [
        ("20,20", "data row 1: expected as many cells as header columns"),  # was a TypeError
        ("20,20,16,16,5", "data row 1: expected as many cells as header columns"),  # was read
        ("-100,-100,3,4", "data row 1: expected a box centred inside the 64 x 64 px frame"),
    ],
)
def test_truth_rows_of_the_wrong_length_or_off_the_frame(
    tmp_path: Path, video: Path, first: str, says: str
) -> None:
    truth = _truth(tmp_path, [first] + ["20,20,16,16"] * 3)
    out = tmp_path / "out"
    args = ["track", str(video), "--box", BOX, "--out", str(out), "--truth", str(truth)]
    _one_line_error(args, "truth.csv", says)
    assert not out.exists()  # refused before tracking


def test_truth_fifo_is_refused_without_blocking(tmp_path: Path, video: Path) -> None:
    fifo = tmp_path / "truth.csv"
    os.mkfifo(fifo)
    args = ["track", str(video), "--box", BOX, "--out", str(tmp_path / "o"), "--truth", str(fifo)]
    _one_line_error(args, "truth.csv", "x_px, y_px, w_px, h_px", "a regular file", "FIFO")


def test_out_that_is_a_file_is_refused(tmp_path: Path, video: Path) -> None:
    out = tmp_path / "out.txt"
    out.write_text("a file")
    _one_line_error(["track", str(video), "--box", BOX, "--out", str(out)], "out.txt", "--out")
    deeper = out / "sub"
    _one_line_error(["track", str(video), "--box", BOX, "--out", str(deeper)], "--out", "folder")


@pytest.mark.parametrize(
    ("option", "value", "says"),
    [
        ("--fps", "1e-300", "--fps: fps: expected a frame rate in [1e-09, 1e+09] frames/s"),
        ("--fps", "1e300", "--fps: fps: expected a frame rate"),
        ("--pixel-um", "1e-320", "--pixel-um: pixel_um: expected a number in [1e-06, 1e+06] um"),
        ("--pixel-um", "1e308", "--pixel-um: pixel_um: expected a number in"),
    ],
)
def test_pixel_size_and_frame_rate_have_physical_bounds(
    tmp_path: Path, video: Path, option: str, value: str, says: str
) -> None:
    """--fps 1e-300 was an OverflowError traceback (the GIF's frame delay); --pixel-um 1e308
    wrote inf um into track.csv."""
    out = tmp_path / "out"
    _one_line_error(["track", str(video), "--box", BOX, "--out", str(out), option, value], says)
    assert not out.exists()


def test_a_slow_time_lapse_writes_its_gif(tmp_path: Path) -> None:
    """One frame a day (within the bounds): the GIF's delay is capped, not an overflow."""
    frames = np.random.default_rng(1).random((2, 16, 16))
    boxes = np.array([[2.0, 2.0, 8.0, 8.0]] * 2)
    write_overlay_gif(tmp_path / "o.gif", frames, boxes, fps=1 / 86400)
    assert (tmp_path / "o.gif").stat().st_size > 0


def test_box_smaller_than_a_feature_cell_is_refused(tmp_path: Path, video: Path) -> None:
    out = tmp_path / "out"
    args = ["track", str(video), "--box", "10,10,0.5,0.5", "--out", str(out)]
    _one_line_error(args, "--box: box: expected W, H >= 4 px")
    assert not out.exists()


def test_complex_pixels_are_refused(tmp_path: Path) -> None:
    """A complex TIFF was cast to float (imaginary part dropped with a warning) and tracked."""
    import tifffile

    frames = np.ones((3, 32, 32)) * (1 + 1j)
    tifffile.imwrite(tmp_path / "c.tif", frames.astype(np.complex64), photometric="minisblack")
    args = ["track", str(tmp_path / "c.tif"), "--box", "4,4,8,8", "--out", str(tmp_path / "o")]
    _one_line_error(args, "c.tif", "real pixel values", "complex64")


# --- new -----------------------------------------------------------------------------------


@pytest.mark.parametrize("template", [None, "plates"])
def test_new_into_a_file_is_one_line(tmp_path: Path, template: str | None) -> None:
    """``new KIND FOLDER`` with FOLDER an existing file (or under one) was a FileExistsError
    / NotADirectoryError traceback."""
    target = tmp_path / "afile"
    target.write_text("x")
    extra = ["--template", template] if template else []
    _one_line_error(["new", "fe_experiment", str(target), *extra], "afile", "FOLDER", "not a file")
    _one_line_error(["new", "fe_experiment", str(target / "sub"), *extra], "FOLDER")
    assert target.read_text() == "x"


def test_new_with_an_empty_folder_name_is_refused(tmp_path: Path, monkeypatch) -> None:
    """``new KIND ""`` wrote the case into the working folder (``Path("")`` is ``.``)."""
    monkeypatch.chdir(tmp_path)
    _one_line_error(["new", "fe_experiment", ""], "FOLDER", "a folder name (use . for this")
    _one_line_error(["new", "fe_experiment", "  "], "FOLDER")
    assert list(tmp_path.iterdir()) == []
    result = CliRunner().invoke(app, ["new", "fe_experiment", "."])  # asked for: allowed
    assert result.exit_code == 0 and (tmp_path / "case.toml").is_file(), result.output


# --- case inputs ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("inputs", "says"),
    [
        (  # the run stopped at 1 s: the tip reached 1.4 um, not the 2.8 um asked for
            {"tools.tip.displacement_um": {"time_s": [0.0, 2.0], "value": [0.0, 2.8]}},
            "tools.tip.displacement_um.time_s within time.duration_s = 1 s",
        ),
        (
            {"tools.dish.displacement_um": {"time_s": [0.0, 3.0], "value": [0.0, 0.0]}},
            "tools.dish.displacement_um.time_s within time.duration_s = 1 s",
        ),
        (  # a 1 um cone pushed 2.8 um: the cell wrapped its base (5.998 kPa for 6.8)
            {"tools.tip.length_um": 1.0},
            "tools.tip.length_um: a cone reaching deeper than its travel into the cell (2.8 um",
        ),
    ],
)
def test_experiment_paths_and_cone_length_against_the_run(
    tmp_path: Path, inputs: dict, says: str
) -> None:
    folder = edited_case(tmp_path, "fe_afm_cone_seed", **inputs)
    with pytest.raises(InputError, match=r"case\.toml: inputs: expected ") as err:
        load_case(folder)
    assert says in str(err.value), str(err.value)


def test_experiment_path_within_the_duration_is_accepted(tmp_path: Path) -> None:
    """A path shorter than the run is held at its last value (a hold): accepted."""
    path = {"time_s": [0.0, 0.5], "value": [0.0, 2.8]}
    folder = edited_case(tmp_path, "fe_afm_cone_seed", **{"tools.tip.displacement_um": path})
    assert load_case(folder).inputs.tools["tip"].displacement_um.time_s == [0.0, 0.5]


@pytest.mark.parametrize(
    ("field", "value", "says"),
    [
        ("fe_refine_size_um", 50.0, "fe_refine_size_um <= fe_size_um = 6"),
        ("fe_size_um", 30.0, "fe_size_um <= half the cytoplasm radius"),
        ("cytoplasm_diameter_um", 40.0, "cytoplasm_diameter_um > half the cell diameter"),
        ("fe_step_um", 0.001, "fe_step_um >= travel_um / 10000"),
    ],
)
def test_nmsd_vs_fe_settings_the_fe_press_refuses_are_found_at_validate(
    tmp_path: Path, field: str, value: float, says: str
) -> None:
    """``validate`` said ok and ``run`` ended in "ValidationError: 1 validation error for
    Experiment" (no file, no field); now ``validate`` names the input and exits 2."""
    folder = edited_case(tmp_path, "nmsd_vs_fe", **{field: value})
    line = _one_line_error_validate(folder)
    assert f"case.toml: inputs.{field}: expected {says}" in line, line


def _one_line_error_validate(folder: Path) -> str:
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("invalid "), result.output
    return lines[0]


def test_fe_press_settings_the_experiment_refuses_are_one_input_error() -> None:
    """A library caller's settings that the experiment's own rules refuse: an InputError
    naming the source and the experiment's field, not a pydantic ValidationError."""
    scenario = PressScenario()
    materials = LayerMaterials(Material(7.0, 0.5), Material(1.55, 0.5))
    settings = FeSettings(6.0, 50.0, source="my.toml")
    with pytest.raises(InputError) as err:
        press_experiment(scenario, materials, settings, 30.0, np.zeros((0, 2)))
    message = str(err.value)
    assert message.startswith("my.toml: FE press experiment: cell.refine_size_um: expected ")
    assert "refine_size_um <= mesh_size_um = 6" in message and "\n" not in message


def test_unknown_tracking_sequence_is_found_at_validate(tmp_path: Path) -> None:
    """It was refused only when ``run`` started; ``validate`` said ok."""
    folder = edited_case(tmp_path, "spindle_tracking", sequences=["occ0_light0_c4_fast", "occ9"])
    line = _one_line_error_validate(folder)
    assert "case.toml: inputs.sequences: expected names among occ0_light0_c4_fast" in line
    assert "(unknown: occ9)" in line


# --- AFM curve files -----------------------------------------------------------------------


def test_afm_curve_rows_are_counted_from_the_first_data_row() -> None:
    """A NaN force at data row 98 was reported "at row 97" (0-based), off by one from the
    file and from the time column's "data row N" (checks.increasing)."""
    piezo = np.linspace(0.0, 5.0, 200)
    force = np.maximum(piezo - 2.0, 0.0)
    force[97] = math.nan
    with pytest.raises(
        InputError,
        match=r"c\.csv: force_nN: expected finite numbers \(NaN/inf at data row 98: nan\)",
    ):
        ForceCurve(piezo, force, 70.0, source="c.csv")
    back = piezo.copy()
    back[50] = 0.0  # a step back of far more than 2 % of the travel
    with pytest.raises(InputError) as err:
        ForceCurve(back, np.zeros(200), 70.0, source="c.csv")
    assert "piezo_um" in str(err.value) and "at data row 51" in str(err.value)


@pytest.mark.parametrize(
    ("field", "value", "says"),
    [
        ("n_frames", 5000, "a value less than or equal to 2000"),
        ("fps_window_px", 4096, "a value less than or equal to 512"),
        ("gain_goal_pct", -150.0, "a value greater than or equal to -100"),
    ],
)
def test_tracking_case_sizes_are_bounded(
    tmp_path: Path, field: str, value: float, says: str
) -> None:
    """n_frames and the speed test's window were unbounded: 10^5 frames of 320 x 320 px
    (82 GB) passed ``validate``."""
    folder = edited_case(tmp_path, "spindle_tracking", **{field: value})
    line = _one_line_error_validate(folder)
    assert f"case.toml: inputs.{field}: expected {says}" in line, line


def _cone_experiment(path_end_s: float, duration_s: float, length_um: float) -> dict:
    """The shipped cone case's experiment with its path ending at ``path_end_s``."""
    raw = load_case(CASES / "fe_afm_cone_seed").inputs.model_dump(mode="json")
    raw["tools"]["tip"]["displacement_um"] = {"time_s": [0.0, path_end_s], "value": [0.0, 2.8]}
    raw["tools"]["tip"]["length_um"] = length_um
    raw["time"]["duration_s"] = duration_s
    return raw


@settings(max_examples=40, deadline=None)
@given(
    duration=st.floats(1e-3, 1e3),
    ratio=st.floats(0.01, 100.0),
    length=st.floats(0.5, 40.0),
)
def test_experiment_accepts_exactly_the_paths_within_the_run(
    duration: float, ratio: float, length: float
) -> None:
    """Property: a path ending at or before ``duration_s`` and a cone whose flank reaches
    deeper than the 2.8 um travel, ``rho (1 - sin a) + L cos a`` (a = 10 deg, rho = 0), are
    accepted; otherwise the experiment is refused, naming the field."""
    end = duration * ratio
    reach = length * math.cos(math.radians(10.0))
    raw = _cone_experiment(end, duration, length)
    if end <= duration and reach > 2.8:
        Experiment.model_validate(raw)
        return
    with pytest.raises(ValidationError) as err:
        Experiment.model_validate(raw)
    says = "length_um: a cone reaching deeper" if reach <= 2.8 else "time_s within time.duration_s"
    assert says in str(err.value)


@settings(max_examples=40, deadline=None)
@given(
    angle=st.floats(2.0, 88.0),
    tip=st.floats(0.0, 100.0),
    length=st.floats(0.5, 200.0),
)
def test_the_cone_reach_is_the_depth_of_its_drawn_flank(
    angle: float, tip: float, length: float
) -> None:
    """The reach the refusal above compares with the travel is the depth below the apex of the
    last point of the cone the FE is given (``cone_profile``), to round-off."""
    raw = {"type": "cone", "half_angle_deg": angle, "tip_radius_um": tip, "length_um": length}
    cone = Cone.model_validate(raw)
    drawn = cone_profile(angle, tip, length, 0.0)[-1][1]
    assert cone.reach_um == pytest.approx(drawn, rel=1e-12, abs=1e-12)


def test_run_lists_a_case_nested_too_deeply_as_invalid(tmp_path: Path) -> None:
    """A ``case.toml`` nested beyond the parser's recursion (5 000 arrays) is an invalid case
    with the reader's one line, its kind unknown (``?``): it once raised a RecursionError out of
    ``plan`` when the declared kind was read again from the same file."""
    folder = tmp_path / "deep"
    folder.mkdir()
    (folder / "case.toml").write_text('kind = "fe_experiment"\na = ' + "[" * 5000 + "]" * 5000)
    found = plan([folder])
    assert found.cases == []
    assert found.invalid == [
        ("deep", f"{folder / 'case.toml'}: tables and arrays nested at most 16 deep")
    ]
    assert found.declared == {"deep": "?"}
