"""Checks of scalar and array arguments of the public functions: the project's error or a value.

Every check returns the value as ``float`` (or a float array) or raises
:class:`afm.errors.AfmInputError` naming the argument and what was expected; no ``TypeError``,
``ValueError`` from numpy or silent conversion of a boolean reaches the caller.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from afm.errors import AfmInputError


def real(value: object, field: str, where: str = "<input>", expected: str = "") -> float:
    """``value`` as a finite float; booleans, strings, None, NaN and inf are refused."""
    what = expected or "a finite number"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise AfmInputError(where, field, what, value)
    number = float(value)
    if not math.isfinite(number):
        raise AfmInputError(where, field, what, number)
    return number


def positive(
    value: object, field: str, where: str = "<input>", expected: str = "a positive finite number"
) -> float:
    """A finite number > 0; ``expected`` is the message's expectation."""
    number = real(value, field, where, expected)
    if not number > 0:
        raise AfmInputError(where, field, expected, number)
    return number


def fraction(value: object, field: str, where: str = "<input>") -> float:
    """A number in (0, 1)."""
    number = real(value, field, where, "a fraction in (0, 1)")
    if not 0 < number < 1:
        raise AfmInputError(where, field, "a fraction in (0, 1)", number)
    return number


def integer(value: object, field: str, low: int, high: int, where: str = "<input>") -> int:
    """An int (not a bool) in [low, high]."""
    expected = f"an integer in [{low}, {high}]"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise AfmInputError(where, field, expected, value)
    if not low <= int(value) <= high:
        raise AfmInputError(where, field, expected, int(value))
    return int(value)


def float_array(values: object, field: str, where: str = "<input>") -> np.ndarray:
    """``values`` as a float array; anything numpy cannot read as numbers is refused."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise AfmInputError(where, field, "an array of numbers") from None
