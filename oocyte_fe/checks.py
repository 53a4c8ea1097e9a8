"""Argument checks of the public ``oocyte_fe`` functions (microchannel, neck, crosscheck).

:func:`number` refuses what is not a real, finite number within the stated bounds (``bool``,
strings, complex, NaN, inf, ``2.5`` where a count is expected); :func:`numbers_array` does the
same for every element of an array. Both raise :class:`~oocyte_fe.errors.InputError` naming
the function (or object), the argument and the expectation.
"""

from __future__ import annotations

import dataclasses
import math
import numbers

import numpy as np

from oocyte_fe.errors import InputError


def _expected(integer: bool, gt, ge, lt, le) -> str:
    parts = [
        f"{op} {bound:g}"
        for op, bound in ((">", gt), (">=", ge), ("<", lt), ("<=", le))
        if bound is not None
    ]
    what = "an integer" if integer else "a finite real number"
    return f"{what} {' and '.join(parts)}".strip()


def _within(x: float, gt, ge, lt, le) -> bool:
    return not (
        (gt is not None and not x > gt)
        or (ge is not None and not x >= ge)
        or (lt is not None and not x < lt)
        or (le is not None and not x <= le)
    )


def number(
    where: str,
    name: str,
    value: object,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    integer: bool = False,
) -> float:
    """``value`` as a float (an int if ``integer``) if real, finite and within the bounds."""
    kind = numbers.Integral if integer else numbers.Real
    if isinstance(value, bool) or not isinstance(value, kind):
        raise InputError(where, name, _expected(integer, gt, ge, lt, le), got=value)
    x = int(value) if integer else float(value)  # type: ignore[arg-type]
    if not (math.isfinite(x) and _within(x, gt, ge, lt, le)):
        raise InputError(where, name, _expected(integer, gt, ge, lt, le), got=value)
    return x


def numbers_array(
    where: str,
    name: str,
    value: object,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
) -> np.ndarray:
    """``value`` as a float array (scalars allowed) whose every element passes :func:`number`."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(where, name, "an array of real numbers") from None
    if array.dtype == bool or not np.issubdtype(array.dtype, np.number) or np.iscomplexobj(array):
        raise InputError(where, name, "an array of real numbers", got=str(array.dtype))
    array = array.astype(float)
    bad = ~(np.isfinite(array) & _vector_within(array, gt, ge, lt, le))
    if np.any(bad):
        expected = "an array of " + _expected(False, gt, ge, lt, le).removeprefix("a ") + "s"
        raise InputError(where, name, expected, got=float(array[bad].flat[0]))
    return array


def _vector_within(a: np.ndarray, gt, ge, lt, le) -> np.ndarray:
    ok = np.ones(a.shape, dtype=bool)
    if gt is not None:
        ok &= a > gt
    if ge is not None:
        ok &= a >= ge
    if lt is not None:
        ok &= a < lt
    if le is not None:
        ok &= a <= le
    return ok


def numeric_fields(obj: object, where: str, max_abs: float = 1e12) -> None:
    """Every ``float``/``int`` field of the dataclass ``obj`` real, finite and ``|x| <= max_abs``
    (its own range checks follow in its ``__post_init__``)."""
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        if f.type in ("float", "int", float, int):
            integer = f.type in ("int", int)
            number(where, f.name, getattr(obj, f.name), ge=-max_abs, le=max_abs, integer=integer)


TINY = 1e-30
HUGE = 1e30
"""Range of a positive physical quantity in internal units (um, nN, kPa, s and their products):
wide enough for every real one (water's density is 1e-15 nN s^2/um^4), narrow enough that the
closed forms' products of a few of them stay finite."""


def positive(where: str, name: str, value: object) -> float:
    """``value`` if a real number in [:data:`TINY`, :data:`HUGE`] (see :func:`number`)."""
    return number(where, name, value, ge=TINY, le=HUGE)
