"""Error types shared by the case runner and the FE core."""

from __future__ import annotations

from pathlib import Path

GOT_CHARS = 80
"""Longest ``got`` shown in an error message (a value, never a file's content)."""


def one_line(text: str) -> str:
    """``text`` with line breaks and other control characters escaped (a one-line message)."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def short_repr(value: object) -> str:
    """``repr(value)`` on one line, cut to :data:`GOT_CHARS` characters."""
    text = one_line(repr(value))
    return text if len(text) <= GOT_CHARS else text[: GOT_CHARS - 4] + " ..."


class InputError(ValueError):
    """Bad user input: names the file, the field and what was expected.

    ``str(err)`` is one line, ``"<file>: <field>: expected <expected>, got <got>"``, fit to
    be printed without a traceback.
    """

    def __init__(
        self, file: str | Path, field: str, expected: str, got: object | None = None
    ) -> None:
        self.file = one_line(str(file))
        self.field = one_line(field)
        self.expected = one_line(expected)
        self.got = got
        msg = (
            f"{self.file}: {self.field}: expected {self.expected}"
            if field
            else f"{self.file}: {self.expected}"
        )
        if got is not None:
            msg += f", got {short_repr(got)}"
        super().__init__(msg)


class SolverError(RuntimeError):
    """A solver that did not converge: the message names the time, residual and cause.

    ``result`` holds what was solved before the failure (for example the FE
    ``SolveResult`` with its frames and step log), or ``None``.
    """

    def __init__(self, message: str, result: object | None = None) -> None:
        super().__init__(message)
        self.result = result


class InadmissibleState(SolverError):
    """A converged solution that is not a state of the body (a surface that passes through
    itself): the solver stops there; ``result`` holds the states before it."""


class MissingExtraError(ImportError):
    """An optional dependency (a pip extra of oocyte-fe) is needed but not installed."""
