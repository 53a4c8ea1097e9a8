"""Progress events of a run: what the displays of :mod:`oocyte_fe.runner.display` show.

A running case emits ``stage`` events (``ctx.step``) and ``count`` events
(``ctx.progress(done, total)``); the runner adds ``start`` and ``end``. Events are small
picklable records, so they cross the process boundary of a parallel run through a queue.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from oocyte_fe.runner.result import CaseResult


@dataclass(frozen=True)
class ProgressEvent:
    """One thing that happened to a case (``what``: start, stage, count or end)."""

    case: str
    what: str
    stage: str = ""
    done: int = 0
    total: int = 0
    result: CaseResult | None = None
    time: float = field(default_factory=time.time)


EventSink = Callable[[ProgressEvent], None]
"""Where events go: a display, a queue to the parent process, or nowhere."""


def ignore(_event: ProgressEvent) -> None:
    """The sink of a run without a display."""


class Throttle:
    """Forward ``count`` events at most every ``interval`` seconds (and the last of a stage)."""

    def __init__(self, sink: EventSink, interval: float = 0.25) -> None:
        self.sink = sink
        self.interval = interval
        self._last = 0.0

    def __call__(self, event: ProgressEvent) -> None:
        now = time.monotonic()
        final = event.what != "count" or event.done >= event.total
        if final or now - self._last >= self.interval:
            self._last = now
            self.sink(event)


class Guarded:
    """Pass events on until the sink raises once (a closed terminal, a broken pipe); then drop
    them, so a failing display never stops the run or its summary."""

    def __init__(self, sink: EventSink) -> None:
        self.sink = sink
        self.failed: Exception | None = None

    def __call__(self, event: ProgressEvent) -> None:
        if self.failed is None:
            try:
                self.sink(event)
            except Exception as exc:
                self.failed = exc
