"""Frames in and out: TIFF stacks (tifffile), videos and GIFs (imageio), the pixel size and
frame rate that turn pixel tracks into um and seconds, and the per-frame track CSV.

Frames come in as a float64 array (T, H, W); colour frames are averaged over their channels.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe import checks
from oocyte_fe.errors import InputError

TIFF_SUFFIXES = (".tif", ".tiff")
VIDEO_SUFFIXES = (".gif", ".avi", ".mp4", ".mov", ".mkv", ".m4v", ".webm")
"""Read by imageio (videos need its FFmpeg or PyAV plugin installed)."""


@dataclass(frozen=True)
class Calibration:
    """Pixel size (um/px) and frame rate (frames/s) of a recording."""

    pixel_um: float
    fps: float

    def __post_init__(self) -> None:
        if not self.pixel_um > 0 or not self.fps > 0:
            raise ValueError(f"pixel_um and fps must be > 0, got {self.pixel_um}, {self.fps}")

    def to_um(self, px: np.ndarray) -> np.ndarray:
        """Positions or lengths in px to um: ``x_um = x_px * pixel_um``."""
        return np.asarray(px, dtype=float) * self.pixel_um

    def times_s(self, n_frames: int) -> np.ndarray:
        """Frame times ``t_k = k / fps``, s."""
        return np.arange(n_frames) / self.fps


def read_frames(path: str | Path) -> np.ndarray:
    """A TIFF stack, a video or an animated GIF as a float (T, H, W) array."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "", "an existing TIFF stack, video or GIF file")
    if path.suffix.lower() not in TIFF_SUFFIXES + VIDEO_SUFFIXES:
        expected = "a TIFF stack, video or GIF by its extension: " + ", ".join(
            TIFF_SUFFIXES + VIDEO_SUFFIXES
        )
        raise InputError(path, "", expected, path.suffix or "no extension")
    try:
        if path.suffix.lower() in TIFF_SUFFIXES:
            import tifffile

            frames = tifffile.imread(path)
        else:
            import imageio.v3 as iio

            frames = iio.imread(path, index=None)
    except Exception as exc:  # the readers raise many types for unreadable files
        raise InputError(path, "", "a readable TIFF stack, video or GIF", str(exc)) from None
    frames = np.asarray(frames)
    if frames.dtype.kind not in "biuf":  # complex: the cast would drop the imaginary part
        raise InputError(path, "", "real pixel values (integer or float)", str(frames.dtype))
    return as_gray_stack(frames.astype(np.float64), path)


COLOUR_CHANNELS = (3, 4)
"""RGB and RGBA."""


def as_gray_stack(frames: np.ndarray, path: str | Path) -> np.ndarray:
    """A (T, H, W) grayscale stack, or (T, H, W, 3 or 4) colour frames averaged over their
    first 3 channels; InputError for anything else (a single frame, a single colour image
    (H, W, 3), a planar colour stack (T, 3, H, W), which would otherwise be read as frames 3
    or 4 px wide or 3 rows high)."""
    shape = frames.shape
    if frames.ndim == 4 and shape[-1] in COLOUR_CHANNELS:
        frames = frames[..., :3].mean(axis=-1)
    elif frames.ndim == 4 and shape[1] in COLOUR_CHANNELS:
        raise InputError(path, "", "frames (T, H, W) or (T, H, W, 3), not planar colour", shape)
    elif frames.ndim == 3 and shape[-1] in COLOUR_CHANNELS:
        raise InputError(path, "", "a stack of frames, not a single colour image (H, W, 3)", shape)
    elif frames.ndim > 3:
        expected = "frames (T, H, W) or (T, H, W, 3 or 4), not a stack of planes per frame"
        raise InputError(path, "", expected + " (T, Z, H, W): save one plane per frame", shape)
    if frames.ndim != 3 or frames.shape[0] < 2:
        raise InputError(path, "", "at least 2 grayscale or colour frames", shape)
    if not np.all(np.isfinite(frames)):
        raise InputError(path, "", "finite pixel values", "NaN or infinite pixels")
    return frames


def write_tiff(path: str | Path, frames: np.ndarray) -> None:
    """Write a (T, H, W) stack as 16-bit TIFF (values clipped to 0..65535)."""
    import tifffile

    data = np.clip(np.round(frames), 0, 65535).astype(np.uint16)
    tifffile.imwrite(path, data, photometric="minisblack")


def write_track_csv(
    path: str | Path,
    boxes_px: np.ndarray,
    confidence: np.ndarray,
    calibration: Calibration,
    lost: np.ndarray | None = None,
    redetected_from: np.ndarray | None = None,
) -> None:
    """One row per frame: time (s), box x, y, w, h (px), centre (px and um), confidence,
    whether the target was lost (1: the box coasts on the motion prediction), and on a
    frame where a lost target was taken back, where it had been lost (px; blank otherwise)."""
    n = len(boxes_px)
    lost = np.zeros(n, dtype=bool) if lost is None else np.asarray(lost, dtype=bool)
    found = np.full((n, 2), np.nan) if redetected_from is None else np.asarray(redetected_from)
    centres = boxes_px[:, :2] + 0.5 * boxes_px[:, 2:]
    centres_um = calibration.to_um(centres)
    times = calibration.times_s(n)
    with open(path, "w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(
            ["frame", "time_s", "x_px", "y_px", "w_px", "h_px", "cx_px", "cy_px", "cx_um",
             "cy_um", "confidence", "lost", "redetected_from_x_px", "redetected_from_y_px"]
        )  # fmt: skip
        for k in range(n):
            c, c_um = centres[k], centres_um[k]
            src = ["", ""] if np.isnan(found[k, 0]) else [f"{v:.3f}" for v in found[k]]
            out.writerow(
                [k, f"{times[k]:.6g}", *(f"{v:.3f}" for v in boxes_px[k]), f"{c[0]:.3f}",
                 f"{c[1]:.3f}", f"{c_um[0]:.4f}", f"{c_um[1]:.4f}", f"{confidence[k]:.4f}",
                 int(lost[k]), *src]
            )  # fmt: skip


BOX_COLUMNS = ("x_px", "y_px", "w_px", "h_px")


def read_boxes_csv(path: str | Path) -> np.ndarray:
    """Boxes (T, 4) px from a CSV with columns x_px, y_px, w_px, h_px (a track or truth file).

    Read through :func:`oocyte_fe.checks.read_text` (a regular UTF-8 file; a FIFO never
    blocks); a data row with fewer or more cells than the header is refused, naming it
    (1 = the first row below the header).
    """
    path = Path(path)
    field = ", ".join(BOX_COLUMNS)
    text = checks.read_text(path, field)
    try:
        rows = list(csv.DictReader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise InputError(path, field, "a CSV with these columns", str(exc)) from None
    for number, row in enumerate(rows, start=1):
        if None in row or None in row.values():  # cells beyond the header, or missing
            raise InputError(path, f"data row {number}", "as many cells as header columns")
    missing = [k for k in BOX_COLUMNS if rows and k not in rows[0]]
    if missing:
        header = ", ".join(str(k) for k in rows[0])
        raise InputError(path, "header", f"the columns {field}", checks.excerpt(header))
    boxes = []
    for number, row in enumerate(rows, start=1):
        try:
            boxes.append([float(row[k]) for k in BOX_COLUMNS])
        except ValueError:
            cells = checks.excerpt(", ".join(str(row[k]) for k in BOX_COLUMNS))
            raise InputError(path, f"data row {number}", f"numbers in {field}", cells) from None
    return np.array(boxes)


GIF_MAX_DELAY_MS = 655_350.0
"""Longest frame delay a GIF stores (65535 hundredths of a second)."""


def write_overlay_gif(
    path: str | Path, frames: np.ndarray, boxes_px: np.ndarray, every: int = 1, fps: float = 10.0
) -> None:
    """Animated GIF of the frames (8-bit, one fixed scale) with the tracked box drawn white."""
    import imageio.v3 as iio

    lo, hi = np.percentile(frames[0], [1, 99.5])
    images = []
    for frame, box in zip(frames[::every], boxes_px[::every], strict=True):
        img = (255 * np.clip((frame - lo) / max(hi - lo, 1e-12), 0, 1)).astype(np.uint8)
        x0, y0, w, h = (int(round(v)) for v in box)
        x1, y1 = x0 + w, y0 + h
        rows, cols = img.shape
        xs = slice(max(x0, 0), min(x1 + 1, cols))
        ys = slice(max(y0, 0), min(y1 + 1, rows))
        for r in (y0, y1):
            if 0 <= r < rows:
                img[r, xs] = 255
        for c in (x0, x1):
            if 0 <= c < cols:
                img[ys, c] = 255
        images.append(img)
    delay_ms = min(1000.0 / fps * every, GIF_MAX_DELAY_MS)  # a slow time-lapse: the longest delay
    iio.imwrite(path, np.array(images), duration=delay_ms, loop=0)
