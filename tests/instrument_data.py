"""Real instrument files for tests: afmformats 0.18.7's test data (MIT licence).

A few small files are shipped in ``tests/data/instrument/`` (see its README). The full set is
afmformats' PyPI source distribution's ``tests/data``: :func:`afmformats_data` downloads the
sdist once with pip (``pip download --no-deps --no-binary :all: afmformats==0.18.7``) into
``~/.cache/oocyte-fe/afmformats-0.18.7/`` (or ``$OOCYTE_FE_CACHE``) and extracts that folder.
Tests that need a file that is neither shipped nor downloadable skip, saying why.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tarfile
import tempfile
from functools import cache
from pathlib import Path

import pytest

AFMFORMATS_VERSION = "0.18.7"
SHIPPED = Path(__file__).parent / "data" / "instrument"


def cache_dir() -> Path:
    root = Path(os.environ.get("OOCYTE_FE_CACHE", Path.home() / ".cache" / "oocyte-fe"))
    return root / f"afmformats-{AFMFORMATS_VERSION}"


@cache
def afmformats_data() -> Path | None:
    """Folder of afmformats' test data, downloaded on first use; None if that is impossible."""
    target = cache_dir() / "tests" / "data"
    if target.is_dir() and any(target.iterdir()):
        return target
    name = f"afmformats-{AFMFORMATS_VERSION}"
    with tempfile.TemporaryDirectory() as tmp:
        command = [sys.executable, "-m", "pip", "download", "--no-deps", "--no-binary", ":all:"]
        command += [f"afmformats=={AFMFORMATS_VERSION}", "-d", tmp, "-q"]
        try:
            subprocess.run(command, check=True, capture_output=True, timeout=300)
        except (OSError, subprocess.SubprocessError):
            return None
        archive = Path(tmp) / f"{name}.tar.gz"
        if not archive.is_file():
            return None
        prefix = f"{name}/tests/data/"
        with tarfile.open(archive) as tar:
            members = [m for m in tar.getmembers() if m.name.startswith(prefix) and m.isfile()]
            members += [m for m in tar.getmembers() if m.name == f"{name}/LICENSE"]
            safe = {"filter": "data"} if hasattr(tarfile, "data_filter") else {}
            tar.extractall(cache_dir().parent, members=members, **safe)
    return target if target.is_dir() else None


def instrument_file(name: str) -> Path:
    """A shipped file, else the downloaded one; skips the test when neither is there."""
    shipped = SHIPPED / name
    if shipped.is_file():
        return shipped
    data = afmformats_data()
    if data is None:
        pytest.skip(
            f"{name}: not shipped, and afmformats {AFMFORMATS_VERSION}'s sdist "
            "could not be downloaded (no network?)"
        )
    path = data / name
    if not path.is_file():
        pytest.skip(f"{name}: not in afmformats {AFMFORMATS_VERSION}'s tests/data")
    return path
