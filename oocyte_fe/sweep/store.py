"""One folder per sample, named by a key derived from its parameters, so a sweep resumes.

``<case>/samples/<key>/`` holds the sample's ordinary case result (``report.md``,
``metrics.json``, its figures, or ``error.log``) plus ``status.json``; each folder is written
whole or not at all (built under a temporary name, renamed into place). A folder that exists
is a finished sample -- passed or failed -- and is never recomputed; delete it to rerun it.
"""

from __future__ import annotations

import hashlib
import json
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

SAMPLES = "samples"
STATUS = "status.json"


def sample_key(kind: str, base_inputs: dict[str, Any], values: dict[str, Any]) -> str:
    """16 hex digits of SHA-256 over the kind, the case's inputs and the sampled values.

    ``base_inputs`` is the raw ``[inputs]`` table (with the ``[full]``/``[quick]`` overrides the
    case runs with), so the key does not depend on where the case folder lies; a changed input
    changes every key.
    """
    text = json.dumps(
        {"kind": kind, "inputs": base_inputs, "values": values}, sort_keys=True, default=str
    )
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class SampleRecord:
    """A finished (or lost) sample as the table shows it."""

    key: str
    status: str  # PASS, FAIL (a check of the kind failed; still counted), ERROR, LOST
    seconds: float
    reason: str = ""
    metrics: dict[str, Any] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status in ("PASS", "FAIL")


def write_status(folder: Path, key: str, status: str, seconds: float, reason: str) -> None:
    """``status.json`` of a sample (inside its folder before the folder is renamed into place)."""
    (folder / STATUS).write_text(
        json.dumps({"key": key, "status": status, "seconds": seconds, "reason": reason})
    )


def read_sample(folder: Path) -> SampleRecord | None:
    """The record of a finished sample folder, or ``None`` when it has not finished."""
    status_file = folder / STATUS
    if not status_file.is_file():
        return None
    status = json.loads(status_file.read_text())
    metrics_file = folder / "metrics.json"
    metrics = json.loads(metrics_file.read_text())["metrics"] if metrics_file.is_file() else {}
    return SampleRecord(
        status["key"], status["status"], float(status["seconds"]), status["reason"], metrics
    )


def recover_samples(out_root: Path, name: str) -> Path:
    """``out_root/<name>/samples``, adopting finished samples left in interrupted temporaries.

    A sweep killed while its result folder was being swapped leaves its samples under
    ``out_root/.<name>.*/samples``; they are moved back and the temporaries removed.
    """
    samples = out_root / name / SAMPLES
    samples.mkdir(parents=True, exist_ok=True)
    for stale in sorted(out_root.glob(f".{name}.*")):
        for folder in sorted((stale / SAMPLES).glob("*")) if (stale / SAMPLES).is_dir() else []:
            target = samples / folder.name
            if (folder / STATUS).is_file() and not target.exists():
                folder.rename(target)
        shutil.rmtree(stale, ignore_errors=True)
    for partial in samples.glob(".*"):  # samples interrupted mid-run: never finished
        shutil.rmtree(partial, ignore_errors=True)
    return samples
