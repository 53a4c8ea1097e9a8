"""Shared by the fuzz tests: example budget, a per-example hang guard, the outcome check, a tally.

Every fuzzed call must end in one of two ways:

* the project's own error (:data:`PROJECT_ERRORS`), one line, naming a file or function and a
  field; or
* a result whose every number is finite.

Any other exception is a traceback a user would see (the test fails with it); a call that
runs longer than :data:`HANG_S` is a hang (:class:`Hang`, raised by a timer signal).
``OOCYTE_FUZZ_FULL=1`` multiplies the number of examples (docs/reliability.md).
"""

from __future__ import annotations

import dataclasses
import math
import os
import signal
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from nmsd.errors import NmsdDivergence
from oocyte_fe.errors import InputError, SolverError

INPUT_ERRORS = (InputError, InputError, InputError)
PROJECT_ERRORS = (*INPUT_ERRORS, NmsdDivergence, SolverError)
"""Input errors, and solver errors that name the step and a remedy (never a bare exception)."""
FULL = os.environ.get("OOCYTE_FUZZ_FULL", "") not in ("", "0")
HANG_S = 10.0
"""CPU seconds one fuzzed call may take (a loop that never ends burns CPU)."""
BLOCK_S = 120.0
"""Wall seconds one fuzzed call may take (a call blocked on a FIFO burns none; the machine may
be shared, so this is generous)."""
TALLY: Counter[tuple[str, str]] = Counter()
"""(test label, "refused" | "accepted") -> count, printed at the end of the session."""


def fuzz_settings(ci_examples: int, full_examples: int = 2000) -> settings:
    """Hypothesis settings: a fixed, small budget in CI (derandomized); thousands when FULL."""
    return settings(
        max_examples=full_examples if FULL else ci_examples,
        deadline=None,  # the hang guard below bounds each example instead
        derandomize=not FULL,
        database=None,
        suppress_health_check=[
            HealthCheck.too_slow,
            HealthCheck.function_scoped_fixture,
            HealthCheck.filter_too_much,
            HealthCheck.data_too_large,
        ],
    )


class Hang(Exception):
    """A fuzzed call that did not return within :data:`HANG_S`."""


@contextmanager
def hang_guard(seconds: float = HANG_S, wall_seconds: float = BLOCK_S) -> Iterator[None]:
    """Raise :class:`Hang` after ``seconds`` of CPU time or ``wall_seconds`` of wall time."""

    def fire(_signum: int, _frame: object) -> None:
        raise Hang(f"no answer within {seconds:g} CPU s or {wall_seconds:g} s (a hang)")

    previous = {sig: signal.signal(sig, fire) for sig in (signal.SIGALRM, signal.SIGPROF)}
    signal.setitimer(signal.ITIMER_PROF, seconds)
    signal.setitimer(signal.ITIMER_REAL, wall_seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.setitimer(signal.ITIMER_REAL, 0)
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def all_finite(value: Any, depth: int = 0) -> bool:
    """True if every number reachable in ``value`` (arrays, dataclasses, containers) is finite."""
    if depth > 6 or value is None or isinstance(value, str | bytes | bool):
        return True
    if isinstance(value, complex):
        return False
    if isinstance(value, int | float | np.number):
        return bool(np.isfinite(value))
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc":
            return bool(np.all(np.isfinite(value))) and value.dtype.kind != "c"
        return True
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return all(all_finite(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    if isinstance(value, dict):
        return all(all_finite(v, depth + 1) for v in value.values())
    if isinstance(value, list | tuple):
        return all(all_finite(v, depth + 1) for v in value)
    return True


def check_outcome(
    label: str, call: Callable[[], Any], names: str | None = None, own_file: bool = False
) -> Any:
    """Run ``call``: the project's error (one line; ``names`` in it, if given) or a finite result.

    ``own_file``: an input error must name a real file, not ``<input>`` (a library's
    placeholder, which tells a case's user nothing).

    Returns the result, or ``None`` when the call was refused.
    """
    with hang_guard():
        try:
            result = call()
        except PROJECT_ERRORS as exc:
            message = str(exc)
            assert "\n" not in message, f"error message of more than one line: {message!r}"
            if isinstance(exc, INPUT_ERRORS):
                assert exc.expected, f"error message without an expectation: {message!r}"
            if own_file:
                assert not message.startswith("<input>"), f"misnamed error: {message}"
            if names is not None:
                assert names in message, f"error does not name {names!r}: {message}"
            TALLY[label, "refused"] += 1
            return None
    assert all_finite(result), f"silent acceptance: a non-finite result {result!r}"
    TALLY[label, "accepted"] += 1
    return result


ANYTHING_SCALARS: tuple[Any, ...] = (
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    1e-308,
    5e-324,
    0.0,
    -0.0,
    -1.0,
    1e13,
    2**63,
    -(2**63),
    True,
    False,
    "yes",
    "1",
    "",
    "abc",
    None,
    1j,
)
"""Values every numeric argument is tried with (beside generated ones)."""


POSITIVE = st.floats(min_value=0.0, max_value=1e308, exclude_min=True)
NUMBERS = st.one_of(
    st.sampled_from(ANYTHING_SCALARS),
    st.floats(allow_nan=True, allow_infinity=True),
    POSITIVE,
    POSITIVE,
    st.floats(1e-3, 1e3),
    st.floats(-1e3, 1e3),
    st.integers(-10, 100),
)
"""Any argument where a number is expected: hostile values, generated floats (positive ones,
huge and tiny, weighted up), small integers."""


def capped(strategy: st.SearchStrategy, cap: float) -> st.SearchStrategy:
    """``strategy`` with positive finite numbers above ``cap`` replaced by ``cap`` (bounded work
    where a valid value is expensive; the hostile values are kept)."""

    def clip(value: Any) -> Any:
        if isinstance(value, int | float) and not isinstance(value, bool) and value > cap:
            return type(value)(cap) if math.isfinite(value) else value
        return value

    return strategy.map(clip)
