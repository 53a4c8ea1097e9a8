"""The error type of the ``afm`` package: bad input named by file, field and expectation."""

from __future__ import annotations

from pathlib import Path


class AfmInputError(ValueError):
    """Bad AFM input (curve file, fit range, material file, probe constant).

    ``str(err)`` is one line, ``"<file>: <field>: expected <expected>, got <got>"``; ``file``
    is ``"<input>"`` for arrays passed from Python.
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


class MissingExtraError(ImportError):
    """An optional dependency (a pip extra of oocyte-fe) is needed but not installed."""
