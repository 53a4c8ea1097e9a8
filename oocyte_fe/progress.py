"""A hook for the long loops of the FE core to report how far they are (no dependencies).

The case runner installs a reporter around a case (:func:`reporting`); library loops call
:func:`report` once per unit of work, which does nothing when no reporter is installed
(scripts, tests). The reporter is a context variable, so threads and processes keep their own.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from contextvars import ContextVar

Reporter = Callable[[int, int, str], None]
_REPORTER: ContextVar[Reporter | None] = ContextVar("oocyte_fe_progress", default=None)


def report(done: int, total: int, what: str) -> None:
    """Tell the installed reporter that ``done`` of ``total`` units of ``what`` are done."""
    reporter = _REPORTER.get()
    if reporter is not None:
        reporter(done, total, what)


@contextlib.contextmanager
def reporting(reporter: Reporter) -> Iterator[None]:
    """Install ``reporter`` for the duration of the block."""
    token = _REPORTER.set(reporter)
    try:
        yield
    finally:
        _REPORTER.reset(token)
