"""Re-detection: the reach gate from the largest push speed, the signature check that
refuses droplets and bare cytoplasm but accepts a turned spindle, and the CSV's record of
which frames were re-detected and from where."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from oocyte_fe.tracking.evidence import Signature, SignatureCheck
from oocyte_fe.tracking.tracker import MFAKCF, max_step_px, track
from oocyte_fe.tracking.video import Calibration, write_track_csv

LEVEL = 2000.0
"""Background, e- per pixel (the benchmark's)."""


def spindle(
    shape: tuple[int, int], centre: tuple[float, float], theta_deg: float, contrast: float = 0.08
) -> np.ndarray:
    """A barrel ``(|u| / 11)^3 + (v / 5.5)^2 <= 1`` px with fibres along its axis, brighter
    than ``LEVEL`` by ``contrast`` (the synthetic generator's spindle at 0.227 um/px)."""
    rows, cols = np.indices(shape, dtype=float)
    t = np.radians(theta_deg)
    dx, dy = cols - centre[0], rows - centre[1]
    u = dx * np.cos(t) + dy * np.sin(t)
    v = -dx * np.sin(t) + dy * np.cos(t)
    body = np.clip(1.0 - (np.abs(u) / 11.0) ** 3 - (v / 5.5) ** 2, 0.0, 0.25) / 0.25
    return LEVEL * contrast * body * (1.0 + 0.2 * np.cos(2 * np.pi * v / 5.3))


def disk(shape: tuple[int, int], centre: tuple[float, float], radius: float) -> np.ndarray:
    rows, cols = np.indices(shape, dtype=float)
    return (np.hypot(cols - centre[0], rows - centre[1]) <= radius).astype(float)


def scene(rng: np.random.Generator, shape: tuple[int, int] = (120, 120)) -> np.ndarray:
    """Cytoplasm: ``LEVEL`` with a 1 % granular texture (no noise yet)."""
    texture = ndimage.gaussian_filter(rng.normal(size=shape), 3.5)
    return LEVEL * (1.0 + 0.01 * texture / texture.std())


def noisy(rng: np.random.Generator, image: np.ndarray) -> np.ndarray:
    """Shot noise (variance = mean)."""
    return image + rng.normal(size=image.shape) * np.sqrt(image)


def test_signature_refuses_droplets_and_cytoplasm_and_accepts_a_turned_spindle() -> None:
    """References learnt on 10 noisy frames of an 8 % spindle at 0 deg; then the same spindle
    turned by 60 deg and by 90 deg passes; a bright compact droplet (+15 %, radius 6 px), a
    dark droplet (-45 %, radius 8 px) and bare cytoplasm do not. 20 noise draws each."""
    rng = np.random.default_rng(5)
    base = scene(rng)
    c = (60.0, 60.0)
    sig = Signature(SignatureCheck(band=1.6, min_coherence=0.2), (24.0, 12.0), (60.0, 30.0))
    for _ in range(10):
        sig.learn(noisy(rng, base + spindle(base.shape, c, 0.0)), c)
    cases = {
        "turned 60": (base + spindle(base.shape, c, 60.0), True),
        "turned 90": (base + spindle(base.shape, c, 90.0), True),
        "bright droplet": (base * (1 + 0.15 * disk(base.shape, c, 6.0)), False),
        "dark droplet": (base * (1 - 0.45 * disk(base.shape, c, 8.0)), False),
        "cytoplasm": (base, False),
    }
    for name, (image, expected) in cases.items():
        passed = [sig.passes(noisy(rng, image), c) for _ in range(20)]
        assert sum(passed) == (20 if expected else 0), name


def hidden_then_moved(
    rng: np.random.Generator, hide: range, jump_px: float, n_frames: int = 110
) -> tuple[np.ndarray, tuple[float, float, float, float], tuple[float, float]]:
    """A still 8 % spindle, hidden (the cytoplasm only) for the frames ``hide``, then shown
    ``jump_px`` to the right: frames, the first box, and where it was hidden."""
    base = scene(rng, (120, 240))
    c0 = (60.0, 60.0)
    c1 = (60.0 + jump_px, 60.0)
    frames = []
    for k in range(n_frames):
        target = 0.0 if k in hide else spindle(base.shape, c0 if k < hide.start else c1, 0.0)
        frames.append(noisy(rng, base + target))
    return np.array(frames), (c0[0] - 12.0, c0[1] - 6.0, 24.0, 12.0), c0


def test_reach_gate_takes_a_far_target_back_only_when_it_could_have_got_there(
    tmp_path: Path,
) -> None:
    """The spindle is hidden for frames 40-44 and reappears 60 px away. MFAKCF without a
    speed limit takes it back within 5 frames of its return; with the largest speed 2 px per
    frame (4.5 um/s at 0.227 um/px and 10 frames/s) it may be there only once
    ``2 n + 13.4 >= 60`` px (n frames lost, 13.4 px the half box diagonal), i.e. n >= 24:
    not before frame 40 + 23. Both re-detections say where the target was lost (within
    3 px of its centre before it was hidden) and the CSV carries it on that row only."""
    frames, box, was = hidden_then_moved(np.random.default_rng(8), range(40, 45), 60.0)
    step = max_step_px(4.54, 10.0, 0.227)
    assert step == pytest.approx(2.0, rel=1e-3)
    first = {}
    for name, config in (("free", MFAKCF), ("gated", replace(MFAKCF, max_step_px=step))):
        result = track(frames, box, config)
        found = np.flatnonzero(~np.isnan(result.redetected_from[:, 0]))
        assert found.size >= 1, name
        first[name] = int(found[0])
        np.testing.assert_allclose(result.redetected_from[found[0]], was, atol=3.0)
        assert np.hypot(*(result.centres[-1] - (120.0, 60.0))) < 3.0, name
    assert first["free"] <= 45 + 5
    assert first["gated"] >= 40 + 23
    write_track_csv(
        tmp_path / "t.csv", result.boxes, result.confidence, Calibration(0.227, 10.0),
        result.lost, result.redetected_from,
    )  # fmt: skip
    rows = np.genfromtxt(tmp_path / "t.csv", delimiter=",", names=True)
    marked = np.flatnonzero(~np.isnan(rows["redetected_from_x_px"]))
    np.testing.assert_array_equal(marked, found)
    assert rows["lost"][first["gated"] - 1] == 1 and rows["lost"][first["gated"]] == 0


def test_search_widens_the_longer_the_target_is_lost() -> None:
    """MFAKCF's grid of (2k + 1)^2 windows, half a window (30 px here) apart, k = 1 + n // 10
    up to 3 after n lost frames: a spindle that reappears 100 px away is beyond the k = 1
    and k = 2 grids (windows reach 60 and 90 px), so it is taken back only once k = 3, not
    before 20 frames after it was lost; and then within 10 more frames."""
    frames, box, _ = hidden_then_moved(np.random.default_rng(9), range(40, 45), 100.0, 120)
    result = track(frames, box, MFAKCF)
    found = np.flatnonzero(~np.isnan(result.redetected_from[:, 0]))
    assert found.size >= 1
    assert 40 + 20 <= found[0] <= 40 + 30
    assert np.hypot(*(result.centres[-1] - (160.0, 60.0))) < 3.0
