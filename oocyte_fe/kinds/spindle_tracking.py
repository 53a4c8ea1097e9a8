"""Case kind ``spindle_tracking``: the MFAKCF benchmark on synthetic polarized-light video
(seed 000, Section II.A, Algorithm 1, Section III.B, Fig. 11) against the goals of issue 21."""

from __future__ import annotations

import os

from pydantic import Field, field_validator

from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Distinct
from oocyte_fe.tracking import benchmark as bench
from oocyte_fe.tracking.plots import plot_precision_success, pooled
from oocyte_fe.tracking.synthetic import benchmark_grid
from oocyte_fe.tracking.tracker import MFAKCF, SINGLE_KCF

SEED = "seed 000, Section III.B"


class TrackingInputs(CaseInputs):
    """Which synthetic sequences to run and the goals to check."""

    n_frames: int = Field(
        300, ge=120, le=2000, json_schema_extra={"unit": "frames"},
        description="frames per sequence (at most 2000: 1.6 GB of 320 x 320 frames)",
    )  # fmt: skip
    sequences: list[str] = Field(
        default_factory=list,
        description="names from the benchmark grid (synthetic.benchmark_grid); empty: all 24",
    )
    use_opencv: bool = Field(True, description="add OpenCV KCF and CSRT when installed")
    fps_window_px: int = Field(
        128, ge=32, le=512, json_schema_extra={"unit": "px"},
        description="search window for the speed test (at most 512: 100 frames of 1024 x 1024)",
    )  # fmt: skip
    gain_goal_pct: float = Field(
        30.0, ge=-100, le=1000,
        description="precision gain over KCF (HOG) on occlusion and light-drift sequences",
        json_schema_extra={"unit": "%"},
    )  # fmt: skip
    fps_goal: float = Field(
        200.0, gt=0, le=1e6,
        description="issue 21's MFAKCF frames per CPU second at the speed-test window, shown "
        "beside the measured speed (benchmarks/tracking.py checks it; not a case check)",
        json_schema_extra={"unit": "frames/s"},
    )  # fmt: skip

    rules = (Distinct("sequences"),)

    @field_validator("sequences")
    @classmethod
    def _known(cls, value: list[str]) -> list[str]:
        """Names of the benchmark grid (found at ``validate``, not when the run starts)."""
        known = sorted(s.name for s in benchmark_grid())
        unknown = [name for name in value if name not in known]
        if unknown:
            raise ValueError(f"names among {', '.join(known)} (unknown: {', '.join(unknown)})")
        return value


METRICS = {
    "precision_20px": "MFAKCF precision at 20 px, all sequences, 1",
    "precision_2um": "MFAKCF precision at 2 um, all sequences, 1",
    "success_rate": "MFAKCF success rate (IoU > 0.5), all sequences, 1",
    "success_auc": "MFAKCF success-plot AUC, all sequences, 1",
    "kcf_precision_20px": "KCF (HOG, fixed rate) precision at 20 px, all sequences, 1",
    "kcf_success_rate": "KCF (HOG, fixed rate) success rate, all sequences, 1",
    "precision_gain_all_pct": "MFAKCF over KCF (HOG), precision at 20 px, all sequences, %",
    "success_gain_all_pct": "MFAKCF over KCF (HOG), success rate, all sequences, %",
    "precision_gain_occlusion_pct": "MFAKCF over KCF (HOG), precision, occlusion sequences, %",
    "precision_gain_light_pct": "MFAKCF over KCF (HOG), precision, light-drift sequences, %",
    "fps_window": "MFAKCF frames per CPU second at the speed-test window, one core, frames/s",
    "fps_window_wall": "MFAKCF frames per wall-clock second at the speed-test window, frames/s",
    "kcf_fps_window": "KCF (HOG) frames per CPU second at the speed-test window, frames/s",
}


def _specs(inp: TrackingInputs):
    """The sequences to run (their names were checked when the inputs were read)."""
    grid = {s.name: s for s in benchmark_grid(inp.n_frames)}
    return [grid[n] for n in inp.sequences] if inp.sequences else list(grid.values())


@case_kind("spindle_tracking", inputs=TrackingInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """MFAKCF vs single-feature KCF (and OpenCV KCF / CSRT) on synthetic spindle video."""
    inp: TrackingInputs = ctx.inputs  # type: ignore[assignment]
    specs = _specs(inp)
    result = bench.run_benchmark(specs, inp.use_opencv, notify=ctx.step)
    ours = result.summary("MFAKCF")
    kcf = result.summary("KCF (HOG)")
    gains = bench.gains(result)
    ctx.step("speed test")
    fps, fps_wall = bench.fps_at_window(MFAKCF, inp.fps_window_px)
    fps_kcf, _ = bench.fps_at_window(SINGLE_KCF, inp.fps_window_px)
    plot_precision_success(
        ctx.output("precision_success.png"), pooled(result), f"{len(specs)} sequences"
    )
    m = {
        "precision_20px": ours["precision_20px"],
        "precision_2um": ours["precision_2um"],
        "success_rate": ours["success_rate"],
        "success_auc": ours["success_auc"],
        "kcf_precision_20px": kcf["precision_20px"],
        "kcf_success_rate": kcf["success_rate"],
        "fps_window": fps,
        "fps_window_wall": fps_wall,
        "kcf_fps_window": fps_kcf,
        **gains,
    }
    checks = []
    for key, label in (("occlusion", "occlusion"), ("light", "light drift")):
        name = f"precision_gain_{key}_pct"
        if name in gains:
            checks.append(
                Check(f"precision gain over KCF (HOG), {label}", gains[name],
                      gains[name] >= inp.gain_goal_pct, f">= {inp.gain_goal_pct:g} %",
                      bench.SEED_PRECISION_GAIN_PCT, SEED + " (all sequences)", "%")
            )  # fmt: skip
    load = os.getloadavg()[0]
    rows = [
        ("precision, all", "precision_gain_all_pct", f"{bench.SEED_PRECISION_GAIN_PCT:+.2f}"),
        ("success, all", "success_gain_all_pct", f"{bench.SEED_SUCCESS_GAIN_PCT:+.2f}"),
        ("precision, occlusion", "precision_gain_occlusion_pct", "-"),
        ("precision, light drift", "precision_gain_light_pct", "-"),
    ]
    seed_rows = "\n".join(
        f"| {label} | {gains[key]:+.1f} | {seed} |" for label, key, seed in rows if key in gains
    )
    return CaseOutcome(
        metrics=m,
        figures=[Figure("precision_success.png", "precision-threshold and success plots")],
        sections=[
            ("OTB table (pooled frames)", bench.table(result)),
            (
                "Gains of MFAKCF over the single-feature KCF (%), next to the seed's",
                "| measure | ours | seed 000 |\n|---|---|---|\n" + seed_rows,
            ),
            (
                "Speed (reported, not checked)",
                f"At a {inp.fps_window_px} x {inp.fps_window_px} px search window, one core: "
                f"MFAKCF {fps:.0f} frames per CPU second ({fps_wall:.0f} per wall-clock second), "
                f"the single-feature KCF (HOG) {fps_kcf:.0f}: MFAKCF costs "
                f"{fps_kcf / fps:.2f} times the single-feature filter, measured in the same "
                f"process. Issue 21's goal is >= {inp.fps_goal:g} frames per CPU second; a "
                "case's outcome does not depend on the speed of the machine it runs on (on a "
                "shared host the figure moves by half from run to run: docs/tracking.md), so "
                "the goal is measured by benchmarks/tracking.py, which repeats the timing and "
                "prints it with this ratio.",
            ),
            (
                "Run conditions",
                f"sequences: {', '.join(s.name for s in specs)}; {inp.n_frames} frames each; "
                f"OpenCV: {result.opencv or 'not installed or not asked'}; "
                f"1-min load average during the run {load:.1f} on {os.cpu_count()} cores "
                "(the table's fps are wall-clock and fall with the load).",
            ),
        ],
        checks=checks,
    )
