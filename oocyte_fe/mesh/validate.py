"""Checks shared by the mesh parameter dataclasses; each raises a one-line InputError."""

from __future__ import annotations

import math

from oocyte_fe.errors import InputError


def positive(source: str, field: str, value: float) -> None:
    """``value`` must be a finite number > 0."""
    if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
        raise InputError(source, field, "a finite number > 0", value)


def element_order(source: str, value: int) -> None:
    """``value`` must be 1 (3-node) or 2 (6-node, curved) triangles."""
    if value not in (1, 2) or isinstance(value, bool):
        raise InputError(source, "order", "1 (linear) or 2 (quadratic) elements", value)


def one_of(source: str, field: str, value: str, allowed: tuple[str, ...]) -> None:
    """``value`` must be one of ``allowed``."""
    if value not in allowed:
        raise InputError(source, field, " or ".join(repr(a) for a in allowed), value)
