"""Rotation and scale sequences: a spindle pushed while it turns by 60 deg or grows / shrinks
by 20 % (synthetic.SequenceSpec turn_deg, growth), and the second, independent video model
(heldout.py) that settings are reported on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from oocyte_fe.tracking import metrics
from oocyte_fe.tracking.evidence import SignatureCheck
from oocyte_fe.tracking.extent import ExtentModel
from oocyte_fe.tracking.heldout import generate_heldout, heldout_grid
from oocyte_fe.tracking.synthetic import SequenceSpec, generate
from oocyte_fe.tracking.tracker import MFAKCF, track


def pushed(seed: int, turn_deg: float = 0.0, growth: float = 0.0) -> SequenceSpec:
    """A 6 % spindle pushed 20 um over 100 frames, visible at every angle."""
    return SequenceSpec(
        name=f"turn{turn_deg:g}_grow{growth:g}", seed=seed, n_frames=200, contrast=0.06,
        displacement_um=20.0, approach_frames=100, enter_frames=30, turn_deg=turn_deg,
        growth=growth, rotation_deg=0.0, polarizer_visibility=False,
    )  # fmt: skip


def test_turn_and_growth_follow_the_advance() -> None:
    """The ground-truth box of a 10 x 5 um barrel: turned by 90 deg its sides swap (within
    the +-8 % breathing), grown by 20 % both sides scale by 1.2."""
    still = generate(pushed(3))
    turned = generate(pushed(3, turn_deg=90.0))
    grown = generate(pushed(3, growth=0.2))
    w0, h0 = still.boxes[-1, 2:]
    np.testing.assert_allclose(turned.boxes[-1, 2:], (h0, w0), rtol=0.12)
    np.testing.assert_allclose(grown.boxes[-1, 2:], 1.2 * still.boxes[-1, 2:], rtol=1e-9)


@pytest.mark.slow
def test_signature_keeps_a_turning_spindle_that_the_anchor_loses() -> None:
    """A spindle turning by 60 deg in the push (seeds 201-203, not the 101-102 the signature
    settings were tried on): MFAKCF declares it lost and coasts on two draws (precision
    @20 px 0.79, 1.00, 0.51 measured), MFAKCF with the signature check keeps it (1.00 on
    each). Asserted: the signature tracker >= 0.95 on each draw and above MFAKCF by > 0.15
    on the mean (0.23 measured)."""
    config = replace(MFAKCF, signature=SignatureCheck(band=1.6, min_coherence=0.2, learn=2.0))
    p20 = {"old": [], "new": []}
    for seed in (201, 202, 203):
        seq = generate(pushed(seed, turn_deg=60.0))
        box = tuple(seq.boxes[0])
        for name, cfg in (("old", MFAKCF), ("new", config)):
            errors = metrics.centre_error(track(seq.frames, box, cfg).boxes, seq.boxes)
            p20[name].append(metrics.precision_at(errors, 20.0))
    assert min(p20["new"]) >= 0.95
    assert np.mean(p20["new"]) - np.mean(p20["old"]) > 0.15


def test_extent_follows_a_clear_spindle_that_grows() -> None:
    """The moment-based box size (extent.py) on a 20 % contrast spindle that grows by 20 %:
    over the last 10 frames the box area is 0.80-0.83 of the truth's (measured; the region
    of 1.6 first boxes cuts the grown spindle's tails), the fixed box's 0.73 (about 1 / 1.2^2).
    Asserted: mean ratio > 0.77 with the extent, < 0.75 without. Off in MFAKCF: on the own
    benchmark's cells it lowered the success AUC (docs/tracking.md)."""
    spec = replace(pushed(4, growth=0.2), contrast=0.2, n_frames=150, approach_frames=80)
    seq = generate(spec)
    truth = np.prod(seq.boxes[-10:, 2:], axis=1)
    ratio = {}
    for name, config in (("fixed", MFAKCF), ("extent", replace(MFAKCF, extent=ExtentModel()))):
        boxes = track(seq.frames, tuple(seq.boxes[0]), config).boxes
        ratio[name] = float(np.mean(np.prod(boxes[-10:, 2:], axis=1) / truth))
    assert ratio["extent"] > 0.77
    assert ratio["fixed"] < 0.75


def test_heldout_model_is_seeded_and_its_box_holds_the_spindle() -> None:
    """The second model: the same seed gives the same frames; the brightest smoothed pixel
    near the true centre lies inside the true box on a plain 8 % draw (frame 0, before the
    push), and the 12 conditions carry the draw in their names."""
    grid = heldout_grid()
    assert len(grid) == 12 and all(s.name.endswith("_s50000") for s in grid)
    spec = replace(next(s for s in grid if s.name.startswith("ho_c8_fast_plain")), n_frames=80)
    a, b = generate_heldout(spec), generate_heldout(spec)
    np.testing.assert_array_equal(a.frames, b.frames)
    from scipy import ndimage

    x, y, w, h = a.boxes[0]
    smooth = ndimage.gaussian_filter(a.frames[0], 3.0)
    r0, r1, c0, c1 = int(y - h), int(y + 2 * h), int(x - w), int(x + 2 * w)
    i, j = np.unravel_index(np.argmax(smooth[r0:r1, c0:c1]), (r1 - r0, c1 - c0))
    assert x <= c0 + j <= x + w and y <= r0 + i <= y + h
