"""A batch of fits corrected for the sample's shape (:mod:`afm.corrections`): the corrected
modulus of every fitted curve and the group statistics over them.

Each fitted row's E is corrected at the row's largest indentation; a fit the correction
refuses (e.g. deeper than the table) keeps its apparent E in ``fits.csv`` and carries the
reason instead of a corrected value. Statistics follow :meth:`afm.batch.BatchResult.stats`:
the fits rated good (poor ones with ``include_poor``), the rating being the apparent fit's.
"""

from __future__ import annotations

import numpy as np

from afm.batch import BatchResult, GroupStats
from afm.corrections import Correction
from oocyte_fe.errors import InputError


def apply_correction(batch: BatchResult, correction: Correction) -> tuple[float | str, ...]:
    """Per row of ``batch``: the corrected E [kPa], or why not (``""`` for a row not fitted)."""
    out: list[float | str] = []
    for r in batch.rows:
        if r.fit is None or r.error:
            out.append("")
            continue
        f = r.fit
        try:
            out.append(
                correction.corrected(f.E_kPa, f.model, dict(f.geometry), f.max_indentation_um)
            )
        except InputError as exc:
            out.append(f"not corrected: {exc.field}: expected {exc.expected}, got {exc.got}")
    return tuple(out)


def corrected_stats(
    batch: BatchResult, corrected: tuple[float | str, ...], include_poor: bool
) -> list[GroupStats]:
    """Mean +- SD of the corrected E per group (quantity ``E_kPa``); rows whose correction was
    refused are left out of the mean, as poor fits are unless ``include_poor``."""
    out = []
    for group in sorted({r.group for r in batch.rows}):
        fitted = [
            (r.fit, value)
            for r, value in zip(batch.rows, corrected, strict=True)
            if r.group == group and r.fit is not None and not r.error
        ]
        if not fitted:
            continue
        values = np.array(
            [v for f, v in fitted if isinstance(v, float) and (include_poor or f.quality == "good")]
        )
        mean = float(values.mean()) if values.size else float("nan")
        sd = float(np.std(values, ddof=1)) if values.size > 1 else float("nan")
        n_poor = sum(f.quality != "good" for f, _ in fitted)
        out.append(GroupStats(group, "E_kPa", values.size, n_poor, mean, sd))
    return out
