"""Prints the fuzz tally (refused / accepted per target) at the end of the session."""

from __future__ import annotations

import pytest

from tests.fuzz.harness import FULL, TALLY


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    if not TALLY:
        return
    targets = sorted({label for label, _ in TALLY})
    total = sum(TALLY.values())
    mode = "full" if FULL else "CI"
    terminalreporter.section(f"fuzz tally ({mode} budget): {total} generated inputs")
    for label in targets:
        refused, accepted = TALLY[label, "refused"], TALLY[label, "accepted"]
        terminalreporter.write_line(
            f"{label:<40} {refused + accepted:>6} inputs: {refused:>6} refused with the "
            f"project's error, {accepted:>6} accepted with finite results"
        )
