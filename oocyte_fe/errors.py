"""Error types shared by the case runner and the FE core."""

from __future__ import annotations

from pathlib import Path


class InputError(ValueError):
    """Bad user input: names the file, the field and what was expected.

    ``str(err)`` is one line, ``"<file>: <field>: expected <expected>, got <got>"``, fit to
    be printed without a traceback.
    """

    def __init__(
        self, file: str | Path, field: str, expected: str, got: object | None = None
    ) -> None:
        self.file = str(file)
        self.field = field
        self.expected = expected
        self.got = got
        msg = f"{self.file}: {field}: expected {expected}" if field else f"{self.file}: {expected}"
        if got is not None:
            msg += f", got {got!r}"
        super().__init__(msg)


class SolverError(RuntimeError):
    """A solver that did not converge: the message names the time, residual and cause.

    ``result`` holds what was solved before the failure (for example the FE
    ``SolveResult`` with its frames and step log), or ``None``.
    """

    def __init__(self, message: str, result: object | None = None) -> None:
        super().__init__(message)
        self.result = result
