"""FE experiment results cached on disk by their inputs, so that cases with equal FE inputs
(the two ``nmsd_vs_fe`` cases press the same FE model) solve it once.

The key is the SHA-256 of the experiment's description (its JSON: every number, material and
path value), a ``tag`` naming what is stored, and a fingerprint of the code that computes it:
the source of ``oocyte_fe/fe``, ``oocyte_fe/experiment`` and ``oocyte_fe/mesh`` and the
versions of numpy, scipy, scikit-fem and gmsh. A change of any of these is a new key, never a
stale result. Results are stored as ``.npz`` (arrays) next to the mesh cache
(``$OOCYTE_FE_CACHE`` or ``~/.cache/oocyte-fe/meshes``; deleting it is always safe), written to
a temporary name and renamed into place. A lock file makes a second process that asks for the
same key while the first is solving wait and read the result instead of solving again;
:func:`cached_arrays_all` asks for several keys and solves first those no other process holds,
so that two cases needing the same two results solve one each instead of one waiting.
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import importlib.metadata
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from oocyte_fe.experiment.description import Experiment
from oocyte_fe.mesh.cache import cache_dir

PACKAGES = ("numpy", "scipy", "scikit-fem", "gmsh")
SOURCES = ("fe", "experiment", "mesh")


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """SHA-256 of the FE, experiment and mesh sources and the numerical packages' versions."""
    root = Path(__file__).parents[1]
    digest = hashlib.sha256()
    for folder in SOURCES:
        for path in sorted((root / folder).glob("*.py")):
            digest.update(path.name.encode())
            digest.update(path.read_bytes())
    for package in PACKAGES:
        with contextlib.suppress(importlib.metadata.PackageNotFoundError):
            digest.update(f"{package}={importlib.metadata.version(package)}".encode())
    return digest.hexdigest()


def result_path(exp: Experiment, tag: str) -> Path:
    """Where the result ``tag`` of ``exp`` is (or will be) cached."""
    record = f"{tag}\n{exp.model_dump_json()}\n{code_fingerprint()}"
    return cache_dir() / f"result-{tag}-{hashlib.sha256(record.encode()).hexdigest()[:24]}.npz"


def _fetch_or_solve(path: Path, compute: Callable[[], dict[str, np.ndarray]]):
    """Under the caller's lock: the cached arrays of ``path``, or ``compute()`` stored there."""
    if path.exists():
        with np.load(path) as data:
            return {k: data[k] for k in data.files}, True
    arrays = compute()
    fd, tmp = tempfile.mkstemp(suffix=".npz", prefix=".tmp-", dir=path.parent)
    os.close(fd)
    try:
        np.savez(tmp, **arrays)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
    return arrays, False


def cached_arrays(
    exp: Experiment, tag: str, compute: Callable[[], dict[str, np.ndarray]]
) -> tuple[dict[str, np.ndarray], bool]:
    """The arrays ``compute()`` returns for ``exp``, from the cache when present; and whether
    they came from it."""
    return cached_arrays_all([(exp, tag, compute)])[0]


def cached_arrays_all(
    jobs: list[tuple[Experiment, str, Callable[[], dict[str, np.ndarray]]]],
) -> list[tuple[dict[str, np.ndarray], bool]]:
    """:func:`cached_arrays` of each ``(exp, tag, compute)``, in the given order; a key another
    process is solving is taken after the free ones (then waited for, and read)."""
    paths = [result_path(exp, tag) for exp, tag, _ in jobs]
    results: list[tuple[dict[str, np.ndarray], bool] | None] = [None] * len(jobs)
    pending = list(range(len(jobs)))
    while pending:
        for wait in (False, True):  # first any key that is free, else wait for the first
            taken = None
            for i in pending:
                paths[i].parent.mkdir(parents=True, exist_ok=True)
                with open(paths[i].with_suffix(".lock"), "w") as lock:
                    try:
                        fcntl.flock(lock, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
                    except BlockingIOError:
                        continue
                    results[i] = _fetch_or_solve(paths[i], jobs[i][2])
                taken = i
                break
            if taken is not None:
                pending.remove(taken)
                break
    return results  # type: ignore[return-value]
