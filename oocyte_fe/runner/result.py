"""A case's outcome as the summary shows it, and its ``result.json`` in the case folder."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

RESULT_FILE = "result.json"
STATUSES = ("PASS", "MISS", "SKIPPED", "FAIL", "ERROR")
"""``MISS``: every check passes except documented known misses (not a failure); ``SKIPPED``:
the case could not run here because an external tool is missing (it says which and how to
install it; not a failure)."""


@dataclass(frozen=True)
class CaseResult:
    """The outcome of one case: status, checks passed of total, run time, why not PASS."""

    name: str
    kind: str
    status: str  # one of STATUSES
    passed: int
    total: int
    seconds: float
    reason: str = ""
    misses: tuple[str, ...] = field(default_factory=tuple)
    """One line per documented miss: the check, its distance to the goal and the reason."""
    cpu_seconds: float = 0.0
    """CPU time of the case's run (its process and the children it waited for), s: on a
    shared machine the cost, where ``seconds`` (wall) also counts the waiting."""

    @property
    def ok(self) -> bool:
        """Counts as a success for the exit code: passed, only documented misses, or skipped
        for a missing external tool."""
        return self.status in ("PASS", "MISS", "SKIPPED")

    def write(self, folder: Path) -> None:
        """Write ``result.json`` into the case folder (read back by :func:`read_result`)."""
        (folder / RESULT_FILE).write_text(json.dumps(asdict(self), indent=2))


def read_result(folder: Path) -> CaseResult | None:
    """The result stored in a case folder, or ``None`` when it has none or it is unreadable."""
    try:
        data = json.loads((folder / RESULT_FILE).read_text())
        data["misses"] = tuple(data.get("misses", ()))
        result = CaseResult(**data)
    except (OSError, ValueError, TypeError):
        return None
    return result if result.status in STATUSES else None
