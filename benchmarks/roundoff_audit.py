"""The brief's round-off rule over the default run: perturb every real number a case reads from
its ``[inputs]`` by a relative 1e-9 and see which reported figure moves by more than 0.5 %.

For each case of ``cases/`` that the default run takes (not ``heavy``), two copies are run in
this process's machine, one after the other: the case as shipped, and the case whose every float
under ``[inputs]`` (nested tables and lists too; not integers or booleans, not the data files)
is multiplied by ``1 + s 1e-9`` with a sign ``s`` drawn per value (``--seed``). Where the
perturbed case is refused (a value on a bound of its field, e.g. a fraction of exactly 1) the
signs are flipped once. Every metric of ``metrics.json`` is then compared: the largest relative
change per case, ``|b - a| / max(|a|, |b|)`` over the metric's values (NaN on both sides is no
change, NaN on one side is a flip; both below :data:`ZERO` is no change), the metric it
belongs to, and whether it breaks the rule (> 0.5 %), with every metric that does and its two
values. Costs (:data:`NOT_RESULTS`) are left out. A relative deviation (a dimensionless
error, imbalance, change or residual: :func:`is_deviation`) ``e = F / F_ref - 1`` moves by
``dF / F_ref`` when its figure ``F`` moves, so its *absolute* change is held to the rule (0.005,
or 0.5 points for ``_pct``): a verification error of 1e-4 moving to 0.9e-4 is its figure
moving by 1e-5, not by 10 %. Those are listed, not counted.

Run: ``python benchmarks/roundoff_audit.py [--only CASE ...] [--seed N] [-j N] [--keep DIR]``
(the whole default run twice: about twice the main job's time).
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import tomli_w

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case

ROOT = Path(__file__).parents[1]
EPS = 1e-9
RULE = 0.005
ZERO = 1e-9
"""Values below this in magnitude on both sides are round-off of a zero (a verification
error of 1e-15), whose relative change says nothing; in the internal units (um, nN, kPa, s) a
figure this small does not occur."""
NOT_RESULTS = ("fps", "seconds", "press_ms", "calibration_s", "fe_steps", "cutbacks")
"""Metric names holding these are the run's costs (wall or CPU time, solver steps taken),
not results."""


def perturbed(value: object, rng: np.random.Generator, sign: float) -> tuple[object, int]:
    """``value`` with each float scaled by ``1 + s EPS`` (``s`` = +-1 drawn, times ``sign``),
    and how many floats were scaled."""
    if isinstance(value, float):
        s = sign * (1.0 if rng.random() < 0.5 else -1.0)
        return value * (1.0 + s * EPS), 1
    if isinstance(value, dict):
        out, n = {}, 0
        for key, item in value.items():
            out[key], k = perturbed(item, rng, sign)
            n += k
        return out, n
    if isinstance(value, list):
        items = [perturbed(item, rng, sign) for item in value]
        return [v for v, _ in items], sum(k for _, k in items)
    return value, 0


def write_perturbed(case: Path, seed: int, sign: float) -> int:
    """Rewrite ``case/case.toml`` with its inputs perturbed; the number of floats scaled."""
    raw = tomllib.loads((case / "case.toml").read_text())
    raw["inputs"], n = perturbed(raw.get("inputs", {}), np.random.default_rng(seed), sign)
    (case / "case.toml").write_text(tomli_w.dumps(raw))
    return n


def validates(case: Path) -> str:
    """'' if the case loads as ``oocyte-fe validate`` loads it (:func:`load_case`), else its
    one-line error."""
    try:
        load_case(case)
    except InputError as exc:
        return str(exc)
    return ""


def run(cases: Path, out: Path, jobs: int) -> None:
    subprocess.run(
        [
            sys.executable,
            "-m",
            "oocyte_fe",
            "run",
            str(cases),
            "-q",
            "-j",
            str(jobs),
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
    )


def change(a: object, b: object) -> float:
    """Largest relative change between two metric values (inf where one is NaN or the shapes
    differ)."""
    x = np.atleast_1d(np.asarray(a, dtype=float))
    y = np.atleast_1d(np.asarray(b, dtype=float))
    if x.shape != y.shape:
        return math.inf
    both = np.isnan(x) & np.isnan(y)
    if np.any(np.isnan(x) ^ np.isnan(y)):
        return math.inf
    x, y = x[~both], y[~both]
    if x.size == 0:
        return 0.0
    scale = np.maximum(np.abs(x), np.abs(y))
    rel = np.where(scale > ZERO, np.abs(y - x) / np.where(scale > ZERO, scale, 1.0), 0.0)
    return float(np.max(rel))


DEVIATION = ("error", "imbalance", "change", "residual", "push_fraction")
DIMENSIONAL = ("_um", "_nN", "_uN", "_kPa", "_Pa", "_s", "_deg", "_um_s", "_mm_s")


def is_deviation(key: str) -> bool:
    """A metric that is a relative deviation, by its name: dimensionless (no unit suffix, or
    in %) and an error, imbalance, change, residual or the neck's rear-cap push fraction, or a
    percentage of one figure against another (``_vs_`` ... ``_pct``)."""
    if key.endswith(DIMENSIONAL):
        return False
    return any(w in key for w in DEVIATION) or ("_vs_" in key and key.endswith("_pct"))


def compare(a: Path, b: Path) -> tuple[float, str, str, list[str]]:
    """(largest relative change of a figure, its metric, the two statuses, each metric beyond
    the rule with its two values) of one case's two runs."""
    ra, rb = json.loads(a.read_text()), json.loads(b.read_text())
    worst, name, beyond = 0.0, "", []
    for key, value in ra["metrics"].items():
        if any(t in key for t in NOT_RESULTS) or key not in rb["metrics"]:
            continue
        other = rb["metrics"][key]
        try:
            c = change(value, other)
        except (TypeError, ValueError):
            c = 0.0 if value == other else math.inf
        moved = f"{key} {_short(value)} -> {_short(other)}"
        if c > RULE and is_deviation(key) and math.isfinite(c):
            pct = key.endswith("_pct")
            step = float(np.nanmax(np.abs(np.subtract(other, value, dtype=float))))
            if step <= (100 * RULE if pct else RULE):
                unit = " points" if pct else ""
                beyond.append(f"{moved} (a relative deviation moved {step:.2g}{unit}: not counted)")
                continue
        if c > worst:  # the largest change of a counted figure, within the rule or not
            worst, name = c, key
        if c > RULE:
            beyond.append(moved)
    return worst, name, f"{ra['status']} / {rb['status']}", beyond


def _short(value: object) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_short(v) for v in value[:4]) + (", ...]" if len(value) > 4 else "]")
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--only", nargs="*", default=None)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-j", type=int, default=2)
    parser.add_argument("--keep", type=Path, default=None, help="write both runs here")
    args = parser.parse_args()
    if args.keep is not None and args.keep.exists() and any(args.keep.iterdir()):
        parser.error(f"--keep {args.keep}: an empty or new folder")
    with tempfile.TemporaryDirectory() as scratch:
        tmp = Path(args.keep or scratch)
        shipped, moved = tmp / "shipped", tmp / "perturbed"
        for copy in (shipped, moved):
            copy.mkdir(parents=True)
        names, scaled, notes = [], {}, {}
        for case in sorted((ROOT / "cases").iterdir()):
            text = (case / "case.toml").read_text() if (case / "case.toml").is_file() else ""
            if (
                not text
                or tomllib.loads(text).get("heavy")
                or (args.only and case.name not in args.only)
            ):
                continue
            names.append(case.name)
            for copy in (shipped, moved):
                shutil.copytree(case, copy / case.name)
            scaled[case.name] = write_perturbed(moved / case.name, args.seed, 1.0)
            refused = validates(moved / case.name)
            if refused:
                shutil.copy(case / "case.toml", moved / case.name / "case.toml")
                write_perturbed(moved / case.name, args.seed, -1.0)
                notes[case.name] = "signs flipped: " + refused.splitlines()[-1][:120]
                again = validates(moved / case.name)
                if again:
                    notes[case.name] = "refused both ways: " + again.splitlines()[-1][:120]
        print(
            f"{len(names)} cases; each float input x (1 +- {EPS:g}), seed {args.seed}", flush=True
        )
        run(shipped, tmp / "out_shipped", args.j)
        run(moved, tmp / "out_perturbed", args.j)
        print(
            "| case | floats perturbed | largest change | metric | status (shipped / perturbed) "
            "| rule |"
        )
        print("|---|---|---|---|---|---|")
        broken, details = 0, []
        for name in names:
            a = tmp / "out_shipped" / name / "metrics.json"
            b = tmp / "out_perturbed" / name / "metrics.json"
            if not (a.is_file() and b.is_file()):
                print(f"| {name} | {scaled[name]} | - | - | no metrics | {notes.get(name, '')} |")
                continue
            worst, metric, status, beyond = compare(a, b)
            details.extend(f"- {name}: {line}" for line in beyond)
            ok = worst <= RULE
            broken += not ok
            shown = "flip (NaN or shape)" if math.isinf(worst) else f"{worst:.2e}"
            verdict = ("kept" if ok else "**broken**") + (
                f"; {notes[name]}" if name in notes else ""
            )
            print(f"| {name} | {scaled[name]} | {shown} | {metric or '-'} | {status} | {verdict} |")
        print(f"\n{broken} of {len(names)} cases move a figure by more than {RULE:.1%}")
        print("\n".join(details))


if __name__ == "__main__":
    main()
