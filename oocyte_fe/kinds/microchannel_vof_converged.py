"""The ``microchannel_vof`` report's Table 4 from the mesh limits (``mesh_check_pressures =
"all"``): every pressure on ``dx_um`` and on each finer mesh, b/a read by one rule per
pressure (:func:`.microchannel_vof_studies.readings`), and the power law through the finest
three meshes (:func:`.vof.extrapolation.power_law`)::

    e(h) = e0 + C h^p,   e = 1 - b/a,   e0 the h -> 0 limit

The three-mesh fit is ill-conditioned in the finest value (at 600 hPa a change of 0.3 % there
moved the order from 1.05 to 1.42), so each limit is given with the range it takes when the
finest value moves by ``FINEST_JITTER`` either way."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from oocyte_fe.kinds.microchannel_vof_runs import mesh_label
from oocyte_fe.kinds.microchannel_vof_studies import readings
from oocyte_fe.microchannel.elastic_junction import compare_table4
from oocyte_fe.microchannel.vof.extrapolation import power_law
from oocyte_fe.microchannel.vof.junction import JunctionRun

FINEST_JITTER = 0.003  # the finest mesh's 1 - b/a moved by +-0.3 % for the limit's range


@dataclass(frozen=True)
class PressureLimit:
    """One pressure on every mesh: 1 - b/a per mesh (coarse to fine, read where all runs
    are read), the observed order and the limit of 1 - b/a (NaN when the finest three admit
    no power law), and the limit's range under the finest value's jitter."""

    pressure_hPa: float
    dx_um: tuple[float, ...]
    deformation: tuple[float, ...]
    where: str
    order: float
    limit: float
    limit_range: tuple[float, float]

    @property
    def b_over_a(self) -> float:
        """b/a of the limit (NaN without one)."""
        return 1.0 - self.limit


def pressure_limit(
    pressure_hPa: float, dx_um: list[float], runs: list[JunctionRun]
) -> PressureLimit:
    """:class:`PressureLimit` of the runs of one pressure on the meshes ``dx_um`` (um, coarse
    to fine, three or more)."""
    if len(runs) < 3 or len(runs) != len(dx_um):
        raise ValueError("expected one run per mesh, three meshes or more")
    where, ratios = readings(runs)
    e = [1.0 - v for v in ratios]
    h = dx_um[-3:]
    fit = power_law(h, e[-3:])
    spread = [power_law(h, [*e[-3:-1], e[-1] * (1 + s * FINEST_JITTER)]).limit for s in (-1.0, 1.0)]
    if not all(math.isfinite(v) for v in spread):  # a jittered fit without an order
        spread = [math.nan, math.nan]
    band = (min(spread), max(spread))
    return PressureLimit(pressure_hPa, tuple(dx_um), tuple(e), where, fit.order, fit.limit, band)


def pressure_limits(
    dx_um: float,
    pressures_hPa: list[float],
    runs: list[JunctionRun],
    extra: dict[str, JunctionRun],
    finer_um: list[float],
) -> list[PressureLimit]:
    """:func:`pressure_limit` at each pressure: its run on ``dx_um`` and its finer-mesh runs
    (labels of :func:`.mesh_label`) in ``extra``."""
    return [
        pressure_limit(p, [dx_um, *finer_um], [run, *(extra[mesh_label(p, m)] for m in finer_um)])
        for p, run in zip(pressures_hPa, runs, strict=True)
    ]


def converged_section(
    limits: list[PressureLimit], experiment: list[float], paper: list[float]
) -> tuple[str, dict[str, float | list[float]]]:
    """The table of the limits against the experiment and the paper's VOF (b/a per pressure,
    NaN where unknown), which model comes closer, and the metrics ``converged_b_over_a``,
    ``converged_order``, ``converged_mean_error_experiment_pct`` (mean |b/a / experiment - 1|
    of the limits, %) and ``converged_liquid_mae`` (mean |b/a - experiment|)."""
    meshes = " / ".join(f"{m:.4g}" for m in limits[0].dx_um)
    rows = [
        f"| p (hPa) | 1 - b/a on {meshes} um | order | **limit 1 - b/a** (finest +-"
        f"{100 * FINEST_JITTER:g} %) | **b/a limit** | experiment | paper VOF "
        f"| b/a on {limits[0].dx_um[0]:g} um | limit's 1 - b/a / experiment's |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for lim, exp, pap in zip(limits, experiment, paper, strict=True):
        es = " / ".join(f"{v:.5f}" for v in lim.deformation)
        if math.isfinite(lim.limit):
            lo, hi = lim.limit_range
            band = f"{lo:.5f}-{hi:.5f}" if math.isfinite(lo) else "no order at one end"
            rows.append(
                f"| {lim.pressure_hPa:g} | {es} | {lim.order:.2f} | **{lim.limit:.5f}** "
                f"({band}) | **{lim.b_over_a:.4f}** | {exp:.3f} | {pap:.3f} "
                f"| {1 - lim.deformation[0]:.4f} | {lim.limit / (1 - exp):.2f} |"
            )
        else:
            rows.append(
                f"| {lim.pressure_hPa:g} | {es} | none (the differences do not shrink) | - | - "
                f"| {exp:.3f} | {pap:.3f} | {1 - lim.deformation[0]:.4f} | - |"
            )
    b = np.array([lim.b_over_a for lim in limits])
    exp_a, pap_a = np.array(experiment), np.array(paper)
    coarse = np.array([1.0 - lim.deformation[0] for lim in limits])
    metrics: dict[str, float | list[float]] = {
        "converged_b_over_a": b.tolist(),
        "converged_order": [lim.order for lim in limits],
    }
    text = "\n".join(rows)
    known = np.isfinite(b) & np.isfinite(exp_a)
    if known.any():
        metrics["converged_mean_error_experiment_pct"] = float(
            100 * np.mean(np.abs(b[known] / exp_a[known] - 1))
        )
        cmp = compare_table4(
            exp_a[known],
            **{
                "liquid cell, mesh limit": b[known],
                f"liquid cell, {limits[0].dx_um[0]:g} um": coarse[known],
                "paper VOF (Fluent, 3-D)": pap_a[known],
            },
        )
        metrics["converged_liquid_mae"] = cmp.errors["liquid cell, mesh limit"]
        text += (
            f"\n\nOver the {int(known.sum())} pressures with a limit: mean |b/a / experiment - 1| "
            f"of the limits **{metrics['converged_mean_error_experiment_pct']:.2f} %**. "
            + cmp.sentence()
        )
    return text, metrics
