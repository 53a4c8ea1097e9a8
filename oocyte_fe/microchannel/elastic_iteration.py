"""Deform and recompute: the flow around the elastic cell's deformed shape (issue 30 part 2).

One-way coupling (:mod:`.elastic_junction`) loads the elastic cell with the traction of the
flow past the undeformed (liquid, nearly round) cell. When the cell deforms by tens of per
cent the flow around it changes, so pass k runs the flow with the cell STARTED in the shape
the FE gave in pass k - 1 (a liquid cell of that outline: with the cell's viscosity it keeps
its shape within about 1 % of b/a over the half millisecond to the junction, docs), takes the
traction of each write around the junction crossing and loads the undeformed FE cell with each
again, read to x = 0 as the one-way cells are (a line through the writes' b/a and, for the
next shape, through their outlines' radii: :func:`.elastic_junction.outline_at`)::

    shape_0 = disk;   traction_k = flow(shape_k);   shape_{k+1}, (b/a)_{k+1} = FE(traction_k)

until the FE's outline at x = 0 has the b/a of the shape its flow started from within
``tolerance`` (1 %; both by principal extents, both outlines: the fixed point's residual;
without relaxation the starting shape is the pass before's FE outline). The reported b/a of
a pass stays the one-way reading (the line through the writes' b/a); the two readings of the
same writes differ by up to 3 % where the writes jitter (500 hPa, docs), which is why the
residual compares outline with outline. The FE is
loaded on its undeformed outline at each edge's polar angle (as in one-way), so the
iteration closes the flow's dependence on the shape, not the large-deformation mapping of
the load; with the keyword ``follower`` the traction's normal part is a follower pressure on
the deformed outline instead (:func:`.elastic_junction.elastic_cell_at_junction`), which
maps it too. It stops, and says so, when the FE does not carry the whole traction or the
pass budget is spent.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.experiment.analysis import polygon_extents_um, section_outline_um
from oocyte_fe.microchannel.elastic_junction import (
    ElasticAtPressure,
    ElasticCellAtJunction,
    elastic_at_writes,
    junction_tractions,
    outline_at,
    radii_at,
)
from oocyte_fe.microchannel.vof.band_traction import Fluids
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.restart import StepPair
from oocyte_fe.microchannel.vof.traction import polygon_centroid, signed_area

# run_flow(outline about the cell centre or None, folder) -> (case, layout, the flow's own
# b/a at the junction)
FlowRun = Callable[[np.ndarray | None, Path], tuple[Path, Layout, float]]


@dataclass(frozen=True)
class Pass:
    """One pass: the flow's cell shape (its b/a at the junction) and the FE cell under the
    traction of each write of that flow around the junction, read to x = 0."""

    flow_b_over_a: float
    elastic: ElasticAtPressure
    start_b_over_a: float = 1.0  # the shape the flow started from (principal extents; disk 1)
    shape_b_over_a: float = float("nan")  # the FE's outline at x = 0 (principal extents)

    @property
    def b_over_a(self) -> float:
        return self.elastic.b_over_a

    @property
    def carried(self) -> bool:
        """The FE carried the loads that b/a at x = 0 is read from."""
        return self.elastic.carried

    @property
    def residual(self) -> float:
        """The FE's outline at x = 0 against the shape the flow started from,
        ``(b/a)_outline / (b/a)_start - 1`` (principal extents of both; NaN when the FE did
        not carry the traction)."""
        if not self.carried:
            return float("nan")
        return self.shape_b_over_a / self.start_b_over_a - 1.0

    @property
    def folded(self) -> bool:
        """An FE run of the read that stopped short did so where its outline would pass
        through itself (:attr:`.experiment.driver.ExperimentResult.folded`)."""
        use = self.elastic.read_from or range(len(self.elastic.cells))
        return any(
            not c.experiment.success and c.experiment.folded
            for c in (self.elastic.cells[k] for k in use)
        )

    @property
    def load_fraction(self) -> float:
        """The smallest part of its load that an FE run of the read carried."""
        use = self.elastic.read_from or range(len(self.elastic.cells))
        return min(self.elastic.cells[k].load_fraction for k in use)


@dataclass(frozen=True)
class DeformRecompute:
    passes: tuple[Pass, ...]
    tolerance: float
    stopped: str  # why the iteration ended
    follower: bool = False  # the FE took the traction's normal part as a follower pressure
    relaxation: float = 1.0  # the weight of the FE's outline in the next shape

    @property
    def ratios(self) -> list[float]:
        return [p.b_over_a for p in self.passes]

    @property
    def carried(self) -> list[float]:
        """b/a of the passes whose FE carried its traction (:attr:`Pass.carried`)."""
        return [p.b_over_a for p in self.passes if p.carried]

    @property
    def residual(self) -> float:
        """The last pass's :attr:`Pass.residual`."""
        return self.passes[-1].residual

    @property
    def converged(self) -> bool:
        """|:attr:`residual`| < ``tolerance`` after at least two passes (the fixed point:
        the flow's starting shape is the FE's answer to that flow's traction)."""
        return len(self.passes) >= 2 and abs(self.residual) < self.tolerance


def _extents_ratio(outline: np.ndarray) -> float:
    """b/a of an outline (k, 2) by its principal extents (the FE's measure)."""
    a, b = polygon_extents_um(outline.T)
    return min(a, b) / max(a, b)


def _centred_outline(cell: ElasticCellAtJunction) -> np.ndarray:
    """The FE's deformed outline about its area centroid (um)."""
    x = section_outline_um(cell.experiment)
    ring = np.vstack([x, x[:1]])
    return x - polygon_centroid(ring, signed_area(ring))


def relaxed_outline(new: np.ndarray, old: np.ndarray | None, weight: float) -> np.ndarray:
    """The next pass's shape: ``weight`` of the FE's outline ``new`` and ``1 - weight`` of the
    last flow's shape ``old`` (None: the disk of the same area), blended in radius at each
    polar angle of ``new`` (both outlines about their centroids, star-shaped)::

        r_{k+1}(theta) = w r_FE(theta) + (1 - w) r_k(theta)

    (under-relaxation of the fixed-point iteration, as in partitioned fluid-structure
    solvers: ``w = 1`` is the plain pass)."""
    if weight >= 1.0:
        return new
    theta = np.arctan2(new[:, 1], new[:, 0])
    r_new = np.hypot(new[:, 0], new[:, 1])
    if old is None:
        area = abs(signed_area(np.vstack([new, new[:1]])))
        r_old = np.full_like(r_new, np.sqrt(area / np.pi))
    else:
        r_old = radii_at(old, theta)
    r = weight * r_new + (1.0 - weight) * r_old
    return r[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])


def deform_recompute(
    run_flow: FlowRun,
    folder: Path,
    fluids: Fluids,
    max_passes: int = 6,
    tolerance: float = 0.01,
    steps: StepPair | None = None,
    relaxation: float = 1.0,
    pressure_hPa: float = float("nan"),
    first: ElasticAtPressure | None = None,
    **cell: float | bool,
) -> DeformRecompute:
    """The passes of the module docstring; ``cell``: keywords of
    :func:`.elastic_junction.elastic_cell_at_junction`; ``fluids`` what the traction needs
    (:class:`.vof.band_traction.Fluids`); ``steps`` as in
    :func:`.elastic_junction.junction_tractions`; ``relaxation`` the weight of
    :func:`relaxed_outline` (0 < w <= 1); ``pressure_hPa`` the flows' (a label). ``first``:
    pass 0 already computed (the one-way cell under the flow past the disk, read as
    ``cell['follower']`` says: :func:`.elastic_junction.elastic_cells_at_junction`), taken
    as it is instead of loading the FE again; ``run_flow`` is then first called for pass 1."""
    if not 0.0 < relaxation <= 1.0:
        raise InputError("deform_recompute", "relaxation", "0 < w <= 1", relaxation)
    passes: list[Pass] = []
    follows = bool(cell.get("follower", False))
    outline = None
    stopped = f"{max_passes} passes spent"
    for k in range(max_passes):
        if k == 0 and first is not None:
            elastic, flow_ratio = first, first.liquid_b_over_a
        else:
            sub = Path(folder) / f"pass{k}"
            sub.mkdir(parents=True, exist_ok=True)
            case, layout, flow_ratio = run_flow(outline, sub / "flow")
            tractions = junction_tractions(case, layout, fluids, sub, steps)
            elastic = elastic_at_writes(pressure_hPa, flow_ratio, tractions, **cell)
        start = 1.0 if outline is None else _extents_ratio(outline)
        if not elastic.carried:
            passes.append(Pass(flow_ratio, elastic, start))
            stopped = f"pass {k}: the FE carries {passes[-1].load_fraction:.0%} of the traction"
            if passes[-1].folded:
                stopped += " (beyond it the cell's surface passes through itself: a ZP fold)"
            break
        use = elastic.read_from
        shapes = [_centred_outline(elastic.cells[i]) for i in use]
        fe_shape = outline_at(shapes, [elastic.traction_x_um[i] for i in use])
        passes.append(Pass(flow_ratio, elastic, start, _extents_ratio(fe_shape)))
        result = DeformRecompute(tuple(passes), tolerance, "", follows, relaxation)
        if result.converged:
            stopped = f"converged after {k + 1} passes"
            break
        outline = relaxed_outline(fe_shape, outline, relaxation)
    return DeformRecompute(tuple(passes), tolerance, stopped, follows, relaxation)
