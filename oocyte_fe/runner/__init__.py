"""The case runner: case files, the case-kind registry, running and reporting."""

from oocyte_fe.runner.registry import CaseContext, CaseKind, CaseOutcome, case_kind, get_kind, kinds

__all__ = ["CaseContext", "CaseKind", "CaseOutcome", "case_kind", "get_kind", "kinds"]
