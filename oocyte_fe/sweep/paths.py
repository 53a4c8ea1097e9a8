"""Dotted paths into a case's inputs: ``E_kPa``, ``zp.E_kPa`` (nested table), ``x.0`` (list item).

A sweep parameter is named by such a path; its sampled value replaces that input of the case.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any


class PathError(KeyError):
    """A dotted path that does not lead to an input field."""

    def __str__(self) -> str:
        return str(self.args[0])


def set_path(data: Mapping[str, Any], path: str, value: Any) -> dict[str, Any]:
    """A deep copy of ``data`` with the item at the dotted ``path`` replaced by ``value``.

    Dict keys are path segments; a segment into a list or tuple is an integer index. Every
    segment but the last must exist; the last may be a new key of a table (the input model
    then checks it). Raises :class:`PathError` naming the first segment that does not fit.
    """
    out: dict[str, Any] = copy.deepcopy(dict(data))
    parts = path.split(".")
    node: Any = out
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[: depth + 1])
        if isinstance(node, dict):
            if last:
                node[part] = value
                return out
            if part not in node:
                raise PathError(f"{where} is not an input table")
            key: Any = part
        elif isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                raise PathError(f"{where}: an index below {len(node)}")
            key = int(part)
            if last:
                node[key] = value
                return out
        else:
            raise PathError(f"{'.'.join(parts[:depth])} holds a single value, not a table")
        child = node[key]
        node[key] = list(child) if isinstance(child, tuple) else child
        node = node[key]
    return out
