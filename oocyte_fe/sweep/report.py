"""A sweep's table (``samples.csv``), statistics, sensitivity indices, figures and report parts."""

from __future__ import annotations

import csv
import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from oocyte_fe.runner.casefile import Case
from oocyte_fe.runner.registry import CaseOutcome, Figure
from oocyte_fe.sweep.plotting import plot_histograms, plot_scatter, plot_sensitivity
from oocyte_fe.sweep.statistics import (
    BOOTSTRAP,
    MIN_SAMPLES,
    RECOMMENDED,
    Sensitivity,
    Summary,
    sensitivity,
    summarize,
)
from oocyte_fe.sweep.store import SampleRecord

TABLE = "samples.csv"


@dataclass(frozen=True)
class SampleRow:
    """One row of the design: its values, unit-cube point and what became of it."""

    index: int
    values: dict[str, Any]
    unit: np.ndarray
    record: SampleRecord

    @property
    def ok(self) -> bool:
        return self.record.ok


def _scalar(value: Any) -> float:
    number = isinstance(value, int | float) and not isinstance(value, bool)
    return float(value) if number else math.nan


def write_table(path: Path, rows: list[SampleRow], names: list[str], metrics: list[str]) -> None:
    """``samples.csv``: one row per sample; inputs as ``input.<path>``, then every metric."""
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(
            ["sample", "key", "status", "seconds", "reason"]
            + [f"input.{n}" for n in names]
            + metrics
        )
        for r in rows:
            writer.writerow(
                [r.index, r.record.key, r.record.status, f"{r.record.seconds:.3f}", r.record.reason]
                + [r.values[n] for n in names]
                + [repr(_scalar(r.record.metrics.get(m))) for m in metrics]
            )


def _numeric_axis(rows: list[SampleRow], name: str, column: int) -> np.ndarray:
    """The sampled values of a parameter for plotting (its unit coordinate if not numeric)."""
    values = [r.values[name] for r in rows]
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=float)
    return np.array([r.unit[column] for r in rows])


def _fmt(value: float) -> str:
    return "" if not math.isfinite(value) else f"{value:.4g}"


def aggregate(case: Case, rows: list[SampleRow], names: list[str], out_dir: Path) -> CaseOutcome:
    """Statistics and indices of every scalar metric over the finished samples; figures."""
    sweep = case.spec.sweep
    assert sweep is not None
    ok = [r for r in rows if r.ok]
    reported = {m for r in ok for m, v in r.record.metrics.items() if not math.isnan(_scalar(v))}
    metrics = [m for m in (sweep.metrics or case.kind.metrics) if m in reported]
    write_table(out_dir / TABLE, rows, names, list(sweep.metrics or case.kind.metrics))
    y = {m: np.array([_scalar(r.record.metrics.get(m)) for r in ok]) for m in metrics}
    summaries: dict[str, Summary] = {m: summarize(v) for m, v in y.items()}
    unit = np.array([r.unit for r in ok]).reshape(len(ok), len(names))
    indices: dict[str, Sensitivity] = {}
    for m in metrics:
        s = sensitivity(unit, y[m], names, sweep.sensitivity, seed=sweep.seed)
        if s is not None:
            indices[m] = s
    out: dict[str, float | list[float]] = {"n_ok": float(len(ok))}
    out["n_failed"] = float(len(rows) - len(ok))
    out["ok_fraction"] = len(ok) / len(rows) if rows else math.nan
    for m, s in summaries.items():
        out.update({f"{m}.{k}": v for k, v in s.as_dict().items()})
    figures = []
    if metrics:
        plot_histograms(out_dir / "histograms.png", y, summaries)
        params = {n: _numeric_axis(ok, n, j) for j, n in enumerate(names)}
        plot_scatter(out_dir / "scatter.png", params, y)
        figures += [
            Figure("histograms.png", "each metric over the finished samples: mean, 5-95 % band"),
            Figure("scatter.png", "each metric against each sampled parameter"),
        ]
    if indices:
        plot_sensitivity(out_dir / "sensitivity.png", indices, names)
        figures.append(
            Figure(
                "sensitivity.png",
                f"{sweep.sensitivity} indices with 95 % intervals; hatched: the interval "
                "reaches zero",
            )
        )
    sections = [
        ("Sweep", _settings(case, len(rows), names)),
        ("Statistics over the finished samples", _stats_table(summaries, case)),
        ("Sensitivity", _sensitivity_table(indices, names, sweep.sensitivity, len(ok))),
    ]
    failed = [r for r in rows if not r.ok]
    if failed:
        sections.append(("Failed samples (excluded from the statistics)", _failures(failed)))
    return CaseOutcome(metrics=out, figures=figures, sections=sections)


def _settings(case: Case, n: int, names: list[str]) -> str:
    sweep = case.spec.sweep
    assert sweep is not None
    lines = [
        f"{n} samples ({sweep.sampler}, seed {sweep.seed}{', quick' if case.quick else ''}) of "
        f"kind `{case.kind.name}`; one row each in `{TABLE}`, results in `samples/<key>/`.",
        "",
        "| input | distribution | source |",
        "|---|---|---|",
    ]
    lines += [
        f"| {n} | {sweep.parameters[n].describe()} | {sweep.parameters[n].source or ''} |"
        for n in names
    ]
    return "\n".join(lines)


def _stats_table(summaries: dict[str, Summary], case: Case) -> str:
    lines = [
        "| metric | n | mean | SD | 5 % | 50 % | 95 % | description |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for m, s in summaries.items():
        lines.append(
            f"| {m} | {s.n} | {_fmt(s.mean)} | {_fmt(s.sd)} | {_fmt(s.p05)} | {_fmt(s.p50)} "
            f"| {_fmt(s.p95)} | {case.kind.metrics.get(m, '')} |"
        )
    return "\n".join(lines) if summaries else "No metric was reported by any sample."


def _sensitivity_table(
    indices: dict[str, Sensitivity], names: list[str], method: str, n_ok: int
) -> str:
    if method == "none":
        return 'Not computed (`sensitivity = "none"`).'
    if not indices:
        return (
            f"Not computed: {n_ok} finished samples are too few for `{method}` (it needs "
            f"{MIN_SAMPLES[method]}; {RECOMMENDED[method]} are recommended), or every metric "
            "was constant."
        )
    label = (
        "first-order index S1 +- its bootstrap 95 % interval (SALib's `S1_conf`)"
        if method == "rbd_fast"
        else f"PAWN median +- a bootstrap 95 % interval ({BOOTSTRAP} resamples)"
    )
    lines = [f"SALib `{method}`: {label}, on {n_ok} samples."]
    if n_ok < RECOMMENDED[method]:
        lines.append(
            f"\n**Warning: {n_ok} finished samples, below the {RECOMMENDED[method]} "
            f"recommended for `{method}`** (docs/sweeps.md): these indices are indicative "
            "only; read their intervals."
        )
    lines += ["", "| metric | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    flagged = 0
    for m, s in indices.items():
        cells = []
        for n in names:
            cell = f"{s.index[n]:.3f}"
            if math.isfinite(s.conf[n]):
                cell += f" +- {s.conf[n]:.3f}"
            if s.spans_zero(n):
                cell += " (0 in interval)"
                flagged += 1
            cells.append(cell)
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    total = len(indices) * len(names)
    lines.append(
        f"\n{flagged} of {total} indices have a 95 % interval that reaches zero "
        '(marked "0 in interval"): at this sample size they are not told apart from no '
        "influence."
        if flagged
        else f"\nEvery one of the {total} indices is resolved from zero at 95 %."
    )
    return "\n".join(lines)


def _failures(failed: list[SampleRow]) -> str:
    counts = Counter(r.record.reason for r in failed)
    lines = [f"{len(failed)} samples failed.", "", "| samples | reason |", "|---|---|"]
    lines += [f"| {c} | {reason} |" for reason, c in counts.most_common()]
    return "\n".join(lines)
