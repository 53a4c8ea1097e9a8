"""``oocyte-fe track``: follow the spindle in a recording from a first box (plain function; the
CLI wiring calls :func:`track_video`).

Writes into ``out_dir``: ``track.csv`` (per frame: time, box px, centre px and um,
confidence, lost, and on a re-detection where the target had been lost), ``overlay.gif``
(the frames with the box), ``trajectory.png`` (centre path, um) and, with a ground-truth CSV
(columns x_px, y_px, w_px, h_px), ``precision_success.png`` and the OTB numbers in the
returned summary.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.tracking import metrics
from oocyte_fe.tracking.plots import plot_precision_success, plot_trajectory
from oocyte_fe.tracking.tracker import TRACKERS, max_step_px, track
from oocyte_fe.tracking.video import (
    Calibration,
    read_boxes_csv,
    read_frames,
    write_overlay_gif,
    write_track_csv,
)

MAX_SPEED_UM_S = 20.0
"""Default largest spindle speed, um/s: above the fastest push of the benchmark's sequences
(35 um in 60 frames at 10 frames/s along the NMSD path, 16.5 um/s at its fastest)."""

MAX_SPEED_BOUND_UM_S = 1e6
"""The largest ``--max-speed`` accepted, um/s (1 m/s: no pipette pushes a spindle so fast)."""


def parse_box(text: str) -> tuple[float, float, float, float]:
    """``"X,Y,W,H"`` (px, top-left corner and size, finite) to a tuple; InputError otherwise."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise InputError("--box", "box", "X,Y,W,H: four finite numbers, px", text)
    if values[2] <= 0 or values[3] <= 0:
        raise InputError("--box", "box", "X,Y,W,H in px with W, H > 0", text)
    return values  # type: ignore[return-value]


def check_box(box: tuple[float, float, float, float], frame_shape: tuple[int, int]) -> None:
    """InputError unless the box (x, y, w, h) px lies wholly inside a (H, W) frame: the
    tracker would learn the repeated edge pixels as the target (a box partly outside is
    refused too, rather than clipped to something the user did not draw)."""
    x, y, w, h = box
    rows, cols = frame_shape
    text = ",".join(f"{v:g}" for v in box)
    if w > cols or h > rows:
        raise InputError("--box", "box", f"W <= {cols} and H <= {rows} px (the frame)", text)
    if x < 0 or y < 0 or x + w > cols or y + h > rows:
        raise InputError(
            "--box", "box", f"inside the {cols} x {rows} px frame (0 <= X <= X + W <= {cols}, "
            f"0 <= Y <= Y + H <= {rows})", text
        )  # fmt: skip


def check_truth_centres(path: str | Path, boxes: np.ndarray, frame_shape: tuple[int, int]) -> None:
    """InputError unless every ground-truth box (x, y, w, h) px has its centre inside the
    (H, W) frame (a box off the frame is a column or row mix-up, not a spindle)."""
    rows, cols = frame_shape
    centres = boxes[:, :2] + 0.5 * boxes[:, 2:]
    outside = np.flatnonzero(
        (centres[:, 0] < 0) | (centres[:, 0] > cols) | (centres[:, 1] < 0) | (centres[:, 1] > rows)
    )
    if outside.size:
        k = int(outside[0])
        raise InputError(
            path,
            f"data row {k + 1}",
            f"a box centred inside the {cols} x {rows} px frame",
            ",".join(f"{v:g}" for v in boxes[k]),
        )


def track_video(
    video: str | Path,
    box: str | tuple[float, float, float, float],
    out_dir: str | Path,
    pixel_um: float = 0.227,
    fps: float = 10.0,
    truth: str | Path | None = None,
    tracker: str = "mfakcf",
    max_speed_um_s: float = MAX_SPEED_UM_S,
) -> dict[str, float]:
    """Track ``video`` (TIFF stack, video or GIF) from ``box`` on frame 0; write the outputs.

    ``max_speed_um_s``: the largest speed the spindle can have (the pipette's fastest push),
    um/s; with ``fps`` and ``pixel_um`` it bounds how far from where it was lost a target is
    taken back (:func:`.tracker.max_step_px`). Every input is checked before tracking.
    ``tracker``: a name of :data:`.tracker.TRACKERS` (``mfakcf``, the default, or one of its
    options). Returns frames, tracking speed (frames/s) and, with ``truth``, precision at
    20 px and at 2 um, success rate and success AUC.
    """
    for name, path in (("video", video), ("--truth", truth)):
        if isinstance(path, str) and not path.strip():  # Path("") would read as "."
            raise InputError(name, "", "a file path, not an empty argument", path)
    if tracker not in TRACKERS:
        raise InputError("--tracker", "tracker", f"one of {', '.join(TRACKERS)}", tracker)
    label, config = TRACKERS[tracker]
    checks.quantity("--pixel-um", "pixel_um", pixel_um, "length_um")
    low, high, _ = checks.QUANTITIES["time_s"]  # a frame interval of 1 ns to 30 years
    rates = f"a frame rate in [{1 / high:g}, {1 / low:g}] frames/s"
    checks.number("--fps", "fps", fps, ge=1 / high, le=1 / low, expected=rates)
    speeds = f"a spindle speed in (0, {MAX_SPEED_BOUND_UM_S:g}] um/s"  # 1 m/s: far above a push
    checks.number(
        "--max-speed",
        "max_speed_um_s",
        max_speed_um_s,
        gt=0,
        le=MAX_SPEED_BOUND_UM_S,
        expected=speeds,
    )
    config = replace(config, max_step_px=max_step_px(max_speed_um_s, fps, pixel_um))
    calibration = Calibration(pixel_um, fps)
    first = parse_box(box if isinstance(box, str) else ",".join(repr(float(v)) for v in box))
    frames = read_frames(video)
    check_box(first, frames.shape[1:])
    if min(first[2:]) < config.cell:  # smaller than one feature cell: nothing to learn
        text = ",".join(f"{v:g}" for v in first)
        raise InputError("--box", "box", f"W, H >= {config.cell} px (one feature cell)", text)
    truth_boxes = None
    if truth is not None:
        truth_boxes = read_boxes_csv(truth)
        if len(truth_boxes) != len(frames):
            raise InputError(truth, "rows", f"{len(frames)} boxes, one per frame", len(truth_boxes))
        if not np.all(np.isfinite(truth_boxes)) or np.any(truth_boxes[:, 2:] <= 0):
            raise InputError(truth, "x_px, y_px, w_px, h_px", "finite boxes with w, h > 0 px")
        check_truth_centres(truth, truth_boxes, frames.shape[1:])
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(out, "--out", "a folder for the outputs, not a file")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(
            out, "--out", "a folder the outputs can be written to", exc.strerror
        ) from None
    result = track(frames, first, config)
    write_track_csv(
        out / "track.csv", result.boxes, result.confidence, calibration, result.lost,
        result.redetected_from,
    )  # fmt: skip
    write_overlay_gif(out / "overlay.gif", frames, result.boxes, max(1, len(frames) // 150), fps)
    centres_um = calibration.to_um(result.centres)
    summary: dict[str, float] = {"frames": float(len(frames)), "tracking_fps": result.fps}
    truth_um = None
    if truth_boxes is not None:
        truth_um = calibration.to_um(metrics.centres(truth_boxes))
        errors = metrics.centre_error(result.boxes, truth_boxes)
        overlaps = metrics.iou(result.boxes, truth_boxes)
        plot_precision_success(out / "precision_success.png", {label: (errors, overlaps)})
        summary |= {
            "precision_20px": metrics.precision_at(errors, 20.0),
            "precision_2um": metrics.precision_at(errors, 2.0 / pixel_um),
            "success_rate": metrics.success_rate(overlaps),
            "success_auc": metrics.success_auc(overlaps),
        }
    plot_trajectory(out / "trajectory.png", centres_um, truth_um)
    return summary
