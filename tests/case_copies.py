"""A shipped case copied to a temporary folder with some of its inputs changed."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path
from typing import Any

import tomli_w

CASES = Path(__file__).resolve().parents[1] / "cases"


def edited_case(tmp_path: Path, name: str, **inputs: Any) -> Path:
    """A copy of ``cases/<name>`` with ``inputs`` set (dotted keys reach nested tables)."""
    folder = tmp_path / name
    shutil.copytree(CASES / name, folder)
    return set_inputs(folder, **inputs)


def set_inputs(folder: Path, **inputs: Any) -> Path:
    """``folder/case.toml`` with ``inputs`` set (dotted keys reach nested tables; ``None``
    removes the key)."""
    raw = tomllib.loads((folder / "case.toml").read_text())
    for key, value in inputs.items():
        table = raw["inputs"]
        *parents, last = key.split(".")
        for part in parents:
            table = table.setdefault(part, {})
        if value is None:
            table.pop(last, None)
        else:
            table[last] = value
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    return folder


def refused_message(folder: Path) -> str:
    """The one-line error ``load_case`` raises on ``folder`` (the test fails if it loads, or if
    the message spans lines or is pydantic's own)."""
    import pytest

    from oocyte_fe.errors import InputError
    from oocyte_fe.runner.casefile import load_case

    with pytest.raises(InputError) as err:
        load_case(folder)
    message = str(err.value)
    assert "\n" not in message and "validation error" not in message, message
    return message
