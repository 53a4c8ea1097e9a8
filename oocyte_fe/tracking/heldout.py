"""A second synthetic video model, written apart from :mod:`.synthetic`, to report tracker
settings on video they were not chosen on (issue 29, item 4).

Nothing is shared with :mod:`.synthetic` but the pixel size and frame rate; every choice
below differs on purpose, so that a setting that fits the first model's texture, spindle,
droplets, pipette, light or noise shows it here:

- Texture: static fractal (``1 / f^2.5`` power spectrum) cytoplasm at 2 % rms of the level
  ``B``, under a vignetting gain ``1 - 0.15 (r / R)^2`` (R the half-diagonal).
- Spindle: a bundle of 7 parallel fibres, each a line of Gaussian cross-section (0.35 um),
  0.65 um apart, tapered by ``cos(pi u / L)`` along its length ``L`` = 9 um (bundle width about
  4.5 um), ``contrast`` x B brighter at its peak, visible at every angle (a retardance image).
  It turns by ``turn_deg`` and grows by ``1 + growth`` over the push.
- Motion: still for ``rest`` frames, then pushed ``push_um`` along a random direction over
  ``push_frames`` frames (a raised-cosine velocity: the speed peaks at twice its mean), then a
  slow random drift (0.03 um per frame).
- Droplets: ``n_droplets`` bright compact Gaussian blobs (+12 to +25 % of B, sigma 0.5-0.9
  um) drifting at 0.1 um per frame; with ``crossing`` one of them passes over the spindle's
  path in the middle of the push.
- Pipette: a dark (0.5 B) bar 3 um wide with a 0.4 um soft edge, entering along the push
  direction behind the spindle; its tip stays 6 um behind the spindle's centre during the
  push, then stops.
- Light: ``1 + 0.15 sin(2 pi t / 170)`` plus 3 % flicker; defocus: Gaussian blur of 0.9 px,
  rising to 2.5 px over a 30-frame episode after the push.
- Noise: Poisson counts of ``B`` = ``photons`` at a camera gain of 2 e- per count, 4 e- read
  noise and a per-row offset of 3 e- rms (banding), rounded to counts.
- Ground truth: the axis-aligned box of the ellipse of axes ``L (1 + growth s)`` by
  ``W (1 + growth s)`` at the spindle's angle, px (x, y, w, h).

:func:`heldout_grid` gives 12 conditions (contrast 4 % / 8 % x slow / fast push x
{plain, turn 60 deg and grow 15 %, a droplet crossing}); draws differ by seed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage


@dataclass(frozen=True)
class HeldOutSpec:
    """One sequence of the second model (module doc); lengths in um unless named px."""

    name: str
    seed: int
    n_frames: int = 200
    shape: tuple[int, int] = (240, 240)
    contrast: float = 0.06
    push_um: float = 20.0
    push_frames: int = 50
    rest: int = 40
    turn_deg: float = 0.0
    growth: float = 0.0
    n_droplets: int = 6
    crossing: bool = False
    photons: float = 1500.0
    pixel_um: float = 0.227
    fps: float = 10.0
    length_um: float = 9.0
    width_um: float = 4.5

    def __post_init__(self) -> None:
        if self.rest + self.push_frames > self.n_frames or self.contrast <= 0:
            raise ValueError(f"{self.name}: need rest + push_frames <= n_frames, contrast > 0")


@dataclass(frozen=True)
class HeldOutSequence:
    """Frames (T, H, W) in e-, ground-truth boxes (T, 4) px (x, y, w, h), and the frames
    where a droplet covers the spindle's centre (what the benchmark reads of a sequence)."""

    spec: HeldOutSpec
    frames: np.ndarray
    boxes: np.ndarray
    occluded: np.ndarray


def _fractal(rng: np.random.Generator, shape: tuple[int, int]) -> np.ndarray:
    """Static texture with a ``1 / f^2.5`` power spectrum, zero mean, unit rms."""
    fy = np.fft.fftfreq(shape[0])[:, None]
    fx = np.fft.fftfreq(shape[1])[None, :]
    f = np.hypot(fx, fy)
    f[0, 0] = np.inf
    field = np.real(np.fft.ifft2(np.fft.fft2(rng.normal(size=shape)) * f ** (-1.25)))
    return (field - field.mean()) / field.std()


def _bundle(
    x: np.ndarray, y: np.ndarray, centre: np.ndarray, theta: float, length: float, width: float
) -> np.ndarray:
    """The fibre bundle's brightness profile (peak about 1) at pixel coordinates x, y (px)."""
    u = (x - centre[0]) * np.cos(theta) + (y - centre[1]) * np.sin(theta)
    v = -(x - centre[0]) * np.sin(theta) + (y - centre[1]) * np.cos(theta)
    along = np.where(np.abs(u) < length / 2, np.cos(np.pi * u / length), 0.0)
    spacing = width / 7.0
    sigma = 0.54 * spacing
    fibres = sum(np.exp(-0.5 * ((v - (i - 3) * spacing) / sigma) ** 2) for i in range(7))
    return along * fibres / 1.3


def generate_heldout(spec: HeldOutSpec) -> HeldOutSequence:
    """Render a sequence of the second model (module doc)."""
    rng = np.random.default_rng(spec.seed)
    h, w = spec.shape
    px = 1.0 / spec.pixel_um
    y, x = np.indices(spec.shape, dtype=float)
    radius2 = ((x - w / 2) ** 2 + (y - h / 2) ** 2) / ((w / 2) ** 2 + (h / 2) ** 2)
    base = (1.0 + 0.02 * _fractal(rng, spec.shape)) * (1.0 - 0.15 * radius2)

    t = np.arange(spec.n_frames)
    angle = rng.uniform(0, 2 * np.pi)
    direction = np.array([np.cos(angle), np.sin(angle)])
    phase = np.clip((t - spec.rest) / spec.push_frames, 0.0, 1.0)
    s = 0.5 * (1 - np.cos(np.pi * phase))  # raised-cosine velocity
    drift = np.cumsum(rng.normal(scale=0.03 * px, size=(spec.n_frames, 2)), axis=0)
    start = np.array([w / 2, h / 2]) - 0.5 * spec.push_um * px * direction
    centres = start + (s * spec.push_um * px)[:, None] * direction + drift
    theta0 = rng.uniform(0, np.pi)
    theta = theta0 + np.radians(spec.turn_deg) * s
    size = 1.0 + spec.growth * s
    length = spec.length_um * px * size
    width = spec.width_um * px * size

    drops = []
    for i in range(spec.n_droplets):
        sigma = rng.uniform(0.5, 0.9) * px
        amp = rng.uniform(0.12, 0.25)
        vel = rng.normal(size=2) * 0.1 * px
        if spec.crossing and i == 0:
            mid = spec.rest + spec.push_frames // 2
            pos0 = centres[mid] - vel * mid
        else:
            pos0 = rng.uniform([0, 0], [w, h])
            while np.linalg.norm(pos0 - centres[0]) < 12 * px:
                pos0 = rng.uniform([0, 0], [w, h])
        drops.append((pos0, vel, sigma, amp))

    light = 1 + 0.15 * np.sin(2 * np.pi * t / 170 + rng.uniform(0, 2 * np.pi))
    light = light + 0.03 * rng.uniform(-1, 1, spec.n_frames)
    episode = spec.rest + spec.push_frames + 10
    blur = 0.9 + 1.6 * np.clip(1 - np.abs(t - episode - 15) / 15, 0, 1)
    tip_lag = 6.0 * px

    frames = np.empty((spec.n_frames, h, w), dtype=np.float32)
    boxes = np.empty((spec.n_frames, 4))
    occluded = np.zeros(spec.n_frames, dtype=bool)
    for k in range(spec.n_frames):
        img = base.copy()
        img += spec.contrast * _bundle(x, y, centres[k], theta[k], length[k], width[k])
        for pos0, vel, sigma, amp in drops:
            p = pos0 + vel * k
            img += amp * np.exp(-0.5 * ((x - p[0]) ** 2 + (y - p[1]) ** 2) / sigma**2)
            occluded[k] |= bool(np.linalg.norm(p - centres[k]) < 2 * sigma)
        tip = centres[min(k, spec.rest + spec.push_frames)] - tip_lag * direction
        along = (x - tip[0]) * direction[0] + (y - tip[1]) * direction[1]
        across = np.abs(-(x - tip[0]) * direction[1] + (y - tip[1]) * direction[0])
        bar = np.clip((1.5 * px - across) / (0.4 * px) + 0.5, 0, 1) * (along < 0)
        img = img * (1 - bar) + 0.5 * bar
        img = ndimage.gaussian_filter(img, blur[k])
        mean_e = np.clip(img * spec.photons * light[k], 0, None)
        counts = rng.poisson(mean_e / 2.0) * 2.0 + rng.normal(scale=4.0, size=spec.shape)
        counts += rng.normal(scale=3.0, size=(h, 1))
        frames[k] = np.clip(np.round(counts), 0, 65535)
        a, b = 0.5 * length[k], 0.5 * width[k]
        ex = np.hypot(a * np.cos(theta[k]), b * np.sin(theta[k]))
        ey = np.hypot(a * np.sin(theta[k]), b * np.cos(theta[k]))
        boxes[k] = (centres[k, 0] - ex, centres[k, 1] - ey, 2 * ex, 2 * ey)
    return HeldOutSequence(spec, frames, boxes, occluded)


def heldout_grid(n_frames: int = 200, seed0: int = 50_000) -> list[HeldOutSpec]:
    """12 conditions: contrast {4 %, 8 %} x push {slow: 15 um over 80 frames, fast: 30 um
    over 40 frames} x {plain, turn 60 deg and grow 15 %, a droplet crossing}; seed =
    ``seed0`` + index (a new ``seed0`` is a new draw of the same conditions)."""
    specs = []
    for contrast in (0.04, 0.08):
        for speed, (push, frames) in (("slow", (15.0, 80)), ("fast", (30.0, 40))):
            for extra, kw in (
                ("plain", {}),
                ("turn", {"turn_deg": 60.0, "growth": 0.15}),
                ("cross", {"crossing": True}),
            ):
                specs.append(
                    HeldOutSpec(
                        name=f"ho_c{int(100 * contrast)}_{speed}_{extra}_s{seed0}",
                        seed=seed0 + len(specs),
                        n_frames=n_frames,
                        contrast=contrast,
                        push_um=push,
                        push_frames=frames,
                        **kw,
                    )  # fmt: skip
                )
    return specs
