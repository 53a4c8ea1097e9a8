"""Opening user files safely: one checked route for ``case.toml``, data and material files.

Every file a case names goes through :func:`read_text` (or :func:`regular_file` when a
library reader opens it afterwards), which guarantees, before any parser sees a byte:

* each name in the path is at most 255 bytes (the limit of common file systems);
* the path is not a symlink loop, resolves to a *regular* file (not a directory, FIFO,
  socket or device) and is opened without blocking (``O_NONBLOCK``), so a FIFO never hangs;
* the file is at most :data:`MAX_BYTES` long and is UTF-8 text without NUL bytes.

:func:`inside` refuses a path that resolves outside a folder (``..``, absolute paths,
symlinks out): a case reads only files in its own folder. :func:`excerpt` is the only way file
content reaches an error message: a short, clearly marked piece of one line.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from oocyte_fe.errors import InputError

MAX_NAME_BYTES = 255
"""Longest file or folder name accepted (bytes, UTF-8)."""
MAX_BYTES = 64 * 1024 * 1024
"""Largest text file read (64 MiB): a case file or a data table, never a bulk recording."""
EXCERPT_CHARS = 40


def excerpt(text: str) -> str:
    """A short, clearly marked piece of one line of a file (for an error message)."""
    line = text.splitlines()[0] if text else ""
    cut = line[:EXCERPT_CHARS] + (" ..." if len(line) > EXCERPT_CHARS else "")
    return f"[excerpt: {cut!r}]"


def _kind_of(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def _check_names(path: Path, field: str) -> None:
    for part in path.parts:
        if len(part.encode("utf-8", "surrogateescape")) > MAX_NAME_BYTES:
            raise InputError(
                path.name[:40] + "...",
                field,
                f"file and folder names of at most {MAX_NAME_BYTES} bytes",
            )


def regular_file(path: str | Path, field: str = "") -> Path:
    """``path`` if it names an existing regular file; :class:`InputError` naming it otherwise."""
    path = Path(path)
    _check_names(path, field)
    try:
        info = path.stat()
    except FileNotFoundError:
        raise InputError(path, field, "an existing file") from None
    except OSError as exc:
        reason = "a path without a symlink loop" if exc.errno == errno.ELOOP else "a readable file"
        raise InputError(path, field, reason, got=exc.strerror) from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(path, field, "a regular file", got=_kind_of(info.st_mode))
    if info.st_size > MAX_BYTES:
        raise InputError(path, field, f"a file of at most {MAX_BYTES // 2**20} MiB")
    return path


def read_bytes(path: str | Path, field: str = "") -> bytes:
    """The bytes of a regular file (checked as :func:`regular_file`; never blocks on a FIFO)."""
    path = regular_file(path, field)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        raise InputError(path, field, "a readable file", got=exc.strerror) from None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):  # swapped since the check
            raise InputError(path, field, "a regular file")
        return fh.read(MAX_BYTES + 1)


def decode_text(data: bytes, path: str | Path, field: str = "") -> str:
    """UTF-8 text (a BOM is dropped); a NUL byte or another encoding is one clear line."""
    if b"\x00" in data:
        line = data[: data.index(b"\x00")].count(b"\n") + 1
        raise InputError(path, field or f"line {line}", "a text file (UTF-8), not binary data")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise InputError(
            path,
            field or f"line {line}",
            "UTF-8 text (save the file as UTF-8)",
            got=f"byte 0x{data[exc.start]:02x}",
        ) from None


def read_text(path: str | Path, field: str = "") -> str:
    """The text of a regular UTF-8 file; every fault is one :class:`InputError` line."""
    return decode_text(read_bytes(path, field), path, field)


def inside(path: str | Path, folder: str | Path, where: str | Path, field: str) -> Path:
    """``path`` (relative to ``folder``, or absolute) resolved; refused if outside ``folder``.

    ``where`` and ``field`` name the file and key that gave the path (for the error).
    """
    folder = Path(folder)
    candidate = Path(path)
    _check_names(candidate, field)
    full = candidate if candidate.is_absolute() else folder / candidate
    try:
        resolved = full.resolve(strict=False)
        root = folder.resolve(strict=False)
    except (OSError, RuntimeError):
        raise InputError(where, field, "a path without a symlink loop", got=str(path)) from None
    if not resolved.is_relative_to(root):
        raise InputError(
            where,
            field,
            "a file inside the case folder (nothing outside it is read; copy the file in)",
            got=str(path),
        )
    return resolved
