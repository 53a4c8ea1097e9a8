"""Meshes cached on disk by their parameters.

The key is the SHA-256 of the parameter dataclass (its type name and fields), the gmsh version
and :data:`SCHEMA_VERSION` (raised whenever the geometry code changes what a parameter set
means). The ``.msh`` file is written to a temporary name in the cache folder and renamed into
place, so a reader never sees half a file and concurrent writers of the same key are harmless.
The folder is ``$OOCYTE_FE_CACHE`` if set, else ``~/.cache/oocyte-fe/meshes``; deleting it is
always safe.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path

import skfem

from oocyte_fe.mesh.gmsh_session import gmsh_version, write_gmsh_mesh
from oocyte_fe.mesh.msh_reader import read_mesh

SCHEMA_VERSION = 1


def cache_dir() -> Path:
    """The mesh cache folder (``$OOCYTE_FE_CACHE`` or ``~/.cache/oocyte-fe/meshes``)."""
    env = os.environ.get("OOCYTE_FE_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "oocyte-fe" / "meshes"


def cache_path(params: object) -> Path:
    """Where the mesh of the parameter dataclass ``params`` is (or will be) cached."""
    record = {
        "type": type(params).__name__,
        "fields": dataclasses.asdict(params),
        "gmsh": gmsh_version(),
        "schema": SCHEMA_VERSION,
    }
    digest = hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()
    return cache_dir() / f"{type(params).__name__}-{digest[:24]}.msh"


def cached_mesh(params: object, order: int, build: Callable[[], float]) -> skfem.Mesh:
    """The mesh of ``params``: read from the cache, or built with gmsh (``build``, see
    :func:`write_gmsh_mesh`), stored atomically, then read. Either way it is checked for
    degenerate and inverted elements."""
    path = cache_path(params)
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(suffix=".msh", prefix=".tmp-", dir=path.parent)
        os.close(fd)
        try:
            write_gmsh_mesh(build, order, Path(tmp))
            os.replace(tmp, path)
        finally:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
    return read_mesh(path)
