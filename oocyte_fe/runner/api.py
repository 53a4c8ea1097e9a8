"""The Python route for notebooks: ``run_case(path)`` returns the case's result and tables.

>>> from oocyte_fe.runner import run_case                        # doctest: +SKIP
>>> res = run_case("cases/microchannel_flow", out="results", quick=True)  # doctest: +SKIP
>>> res.status, res.checks[["check", "value", "status"]]          # doctest: +SKIP
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.execute import check_writable, clean_stale
from oocyte_fe.runner.progress import EventSink, ignore
from oocyte_fe.runner.registry import batch_runner
from oocyte_fe.runner.result import CaseResult, read_result
from oocyte_fe.runner.run import run_one


@dataclass(frozen=True)
class CaseRun:
    """One finished case: its summary row, folder, metrics and checks.

    ``metrics`` maps each metric name to a number or a list of numbers (internal units,
    docs/units.md); ``checks`` is a DataFrame with the columns of the report's checks table:
    ``check, value, reference, unit, deviation, tolerance, status, remark, source``.
    """

    result: CaseResult
    folder: Path
    metrics: dict[str, Any]
    checks: pd.DataFrame

    @property
    def status(self) -> str:
        """``PASS``, ``MISS`` (only documented misses), ``SKIPPED`` (a tool missing), ``FAIL``
        or ``ERROR``."""
        return self.result.status

    @property
    def ok(self) -> bool:
        return self.result.ok

    def scalars(self) -> pd.Series:
        """The scalar metrics as a Series indexed by metric name."""
        return pd.Series(
            {k: v for k, v in self.metrics.items() if isinstance(v, int | float)}, dtype=float
        )


def _checks_frame(rows: list[dict[str, Any]]) -> pd.DataFrame:
    frame = pd.DataFrame(
        [
            {
                "check": r["name"],
                "value": r["computed"],
                "reference": r["reference"],
                "unit": r.get("unit"),
                "deviation": (None if r["reference"] is None else r["computed"] - r["reference"]),
                "tolerance": r["tolerance"],
                "status": r.get("status", "PASS" if r["passed"] else "FAIL"),
                "remark": r.get("remark", ""),
                "source": r.get("source"),
            }
            for r in rows
        ],
        columns=[
            "check",
            "value",
            "reference",
            "unit",
            "deviation",
            "tolerance",
            "status",
            "remark",
            "source",
        ],
    )
    return frame


def read_case_run(folder: Path | str) -> CaseRun:
    """Read a finished case folder (``result.json``, ``metrics.json``) back into a CaseRun."""
    folder = Path(folder)
    result = read_result(folder)
    if result is None:
        raise FileNotFoundError(f"{folder}: no result.json (not a finished case folder)")
    metrics_file = folder / "metrics.json"
    data = json.loads(metrics_file.read_text()) if metrics_file.is_file() else {}
    return CaseRun(result, folder, data.get("metrics", {}), _checks_frame(data.get("checks", [])))


def run_case(
    path: Path | str,
    out: Path | str = "results",
    quick: bool = False,
    events: EventSink = ignore,
    full: bool = False,
) -> CaseRun:
    """Run the case folder ``path`` into ``out/<case>/`` in this process and read it back.

    ``quick``/``full`` apply the case's ``[quick]``/``[full]`` input overrides.
    Raises :class:`oocyte_fe.errors.InputError` for an invalid case; a case that fails or
    raises is returned with status ``FAIL``/``ERROR`` (its reason in ``result.reason``).
    """
    case = load_case(path, quick=quick, full=full)
    out_root = Path(out)
    check_writable(out_root)
    clean_stale(out_root)
    if case.spec.sweep is not None:
        batch_runner("sweep")([case], out_root, events, None, None)
    else:
        run_one(case, out_root, quick, events)
    return read_case_run(out_root / case.name)
