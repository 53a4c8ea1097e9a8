"""The case runner: case files, the case-kind registry, running and reporting.

``run_case`` (the Python route, :func:`oocyte_fe.runner.api.run_case`) is imported on first
use: it pulls in pandas and the whole runner, which the registry's users do not need.
"""

from typing import Any

from oocyte_fe.runner.registry import CaseContext, CaseKind, CaseOutcome, case_kind, get_kind, kinds

__all__ = ["CaseContext", "CaseKind", "CaseOutcome", "case_kind", "get_kind", "kinds", "run_case"]


def __getattr__(name: str) -> Any:
    if name == "run_case":
        from oocyte_fe.runner.api import run_case

        return run_case
    raise AttributeError(f"module 'oocyte_fe.runner' has no attribute {name!r}")
