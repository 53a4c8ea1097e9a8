"""The AFM-elastic cell loaded by the flow at the junction (issue 30 part 2, one-way).

The force of the medium on the cell at the junction crossing of a VOF run, put on the cell's
``alpha = 0.5`` contour as a traction (:mod:`oocyte_fe.microchannel.vof.band_traction`: the
diffuse interface's force ``-sum sigma . grad(alpha) dA``, which balances the cell's momentum
within about 1 %, spread over the contour by polar angle) loads the
layered plane-strain FE cell (the seed's 140 um cell with a 15 um ZP; the AFM moduli, ZP 7.0
and cytoplasm 1.55 kPa, nu = 0.5) as a free cell (``support = "inertia_relief"``: the net
force accelerates it as a rigid body). One-way reading: the traction is put on the undeformed
outline at the polar angle of each contour edge about the contour's centroid; the contour's
mean pressure is removed (a uniform pressure does not deform the incompressible cell). The
answer is the aspect ratio ``b/a`` of the deformed section (principal extents, see
:func:`oocyte_fe.experiment.analysis.outline_extents_um`).

Limits: one-way (the flow is computed around the liquid, deforming VOF cell, not around the
elastic one, and not recomputed), elastic: the moduli are the instantaneous ones (``E_kPa``, the
modulus at t = 0 of the AFM route); the traction acts for about a millisecond, and the ZP's
Prony series ``G(t)/G0 = 0.5 + 0.3 exp(-t/0.2 s) + 0.2 exp(-t/1.5 s)`` has relaxed by
``0.3 (1 - e^-0.005) + 0.2 (1 - e^-0.00067) = 0.16 %`` after 1 ms, so it does not matter.
(Until 2026-12-03 the load was the traction read next to the smeared interface,
:mod:`.vof.traction`, whose net force misses the cell's momentum rate by 3-9 % on 12.5 um;
it is still reported beside.)

Given ``steps`` (a :data:`StepPair`, e.g. :func:`.vof.restart.step_pair`), each write's load
is taken two solver steps later, from the second step's fields with the transposed viscous
part from the first's velocity: the force that balances the cell's momentum over that step as
the solver integrates it (:mod:`.vof.band_traction`); without it, from the write alone.

:func:`elastic_cells_at_junction` does this for a set of runs (Table 4's pressures), and
:func:`compare_table4` sets the two models against the experiment: mean absolute error of b/a.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import outline_extents_um, smallest_stretch
from oocyte_fe.experiment.driver import ExperimentResult
from oocyte_fe.experiment.loads import write_traction_table
from oocyte_fe.io.columns import read_columns
from oocyte_fe.microchannel.vof.band_traction import Fluids, band_traction
from oocyte_fe.microchannel.vof.geometry import Layout
from oocyte_fe.microchannel.vof.post import moment_trace, time_directories
from oocyte_fe.microchannel.vof.restart import StepPair
from oocyte_fe.microchannel.vof.traction import Traction

COLUMNS = ("arc_angle_deg", "x_um", "y_um", "t_x_kPa", "t_y_kPa")


@dataclass(frozen=True)
class Attempt:
    """One FE run of the retry ladder that stopped short: its element size [um], its line
    search (halvings of a Newton step, 0: the full step), the part of the load it carried
    and whether it stopped because the next frame's surface passed through itself."""

    mesh_um: float
    line_search: int
    load_fraction: float
    folded: bool = False  # the next load step's surface passed through itself

    def __str__(self) -> str:
        why = " (then its surface passed through itself)" if self.folded else ""
        return (
            f"{run_name(self.mesh_um, self.line_search)} stopped at {self.load_fraction:.0%}{why}"
        )


def run_name(mesh_um: float, line_search: int) -> str:
    """An FE run of the ladder by its element size and line search: '3 um with line search 4'."""
    return f"{mesh_um:g} um" + (f" with line search {line_search}" if line_search else "")


@dataclass(frozen=True)
class ElasticCellAtJunction:
    """The FE result, b/a of the deformed section, the table it was loaded with, and the
    element size and line search that carried it (``stopped``: the attempts before)."""

    experiment: ExperimentResult
    b_over_a: float
    table: Path
    mesh_um: float = 4.0
    stopped: tuple[Attempt, ...] = ()
    line_search: int = 0

    @property
    def attempt(self) -> str:
        """The run that gave this answer: its element size and line search."""
        return run_name(self.mesh_um, self.line_search)

    @property
    def load_fraction(self) -> float:
        """The part of the traction carried at the last converged frame (1: all of it; the
        load ramps linearly over the FE's time)."""
        return float(self.experiment.times_s[-1] / self.experiment.experiment.time.duration_s)

    @cached_property
    def smallest_stretch(self) -> float:
        """The smallest principal stretch anywhere in the cell at the last converged frame
        (:func:`.experiment.analysis.smallest_stretch`; :data:`CREASE_STRETCH`)."""
        return min(smallest_stretch(self.experiment).values())


def read_vof_traction(path: Path) -> np.ndarray:
    """The VOF traction CSV as rows (angle deg, x um, y um, t_x kPa, t_y kPa); checked."""
    cols = read_columns(path)  # finite numbers, every fault named with its line
    if any(c not in cols for c in COLUMNS):
        raise InputError(path, "columns", ", ".join(COLUMNS), got=", ".join(cols))
    if cols["x_um"].size < 8:
        raise InputError(path, "rows", "at least 8 rows")
    return np.column_stack([cols[c] for c in COLUMNS])


def fe_traction_table(rows: np.ndarray, radius_um: float, path: Path) -> Path:
    """The FE's traction table: each edge's traction on the undeformed outline at its polar
    angle about the contour's centroid (length-weighted), less the mean normal traction."""
    x = rows[:, 1:3]
    t = rows[:, 3:5]
    closed = np.vstack([x, x[:1]])
    ds = np.linalg.norm(np.diff(closed, axis=0), axis=1)  # rows are ordered around
    centre = (x * ds[:, None]).sum(axis=0) / ds.sum()
    d = x - centre
    n = d / np.linalg.norm(d, axis=1)[:, None]
    p_mean = -np.sum(np.einsum("ij,ij->i", t, n) * ds) / ds.sum()
    t = t + p_mean * n  # the mean pressure removed
    return write_traction_table(path, radius_um * n, t, "VOF traction, mean pressure removed")


RETRY_MESH_UM = (3.0, 5.0, 2.0)  # element sizes tried when the first stops short (docs)
LINE_SEARCH = 4  # halvings of a Newton step, the second try on each size (docs)


def elastic_cell_at_junction(
    traction_csv: Path,
    folder: Path,
    zona_kPa: float = 7.0,
    cytoplasm_kPa: float = 1.55,
    diameter_um: float = 140.0,
    zona_um: float = 15.0,
    mesh_um: float = 4.0,
    frames: int = 10,
    retry_mesh_um: tuple[float, ...] = RETRY_MESH_UM,
    follower: bool = False,
    line_search: int = LINE_SEARCH,
    self_contact: bool = False,
) -> ElasticCellAtJunction:
    """Load the layered plane-strain cell with the VOF traction; its b/a (see the module) at
    the last converged of ``frames`` load steps. When Newton stops short of the whole load
    (the crushed cell of the highest pressures: a ZP element inverts, or the iterates cycle)
    the same mesh is solved again with a backtracking line search of ``line_search`` halvings
    (a Newton step that would fold an element or raise the residual is shortened), then the
    cell is meshed again with each size of ``retry_mesh_um`` in turn, each plain and with the
    line search, until one carries it: the answer does not depend on the mesh or the search
    where two carry it (0.05 % at 300 hPa, 0.1 % at 900 hPa, 0.5 % at 600 hPa in a pass,
    docs/elastic_cell_in_flow.md), the stalls do. Otherwise the run that carried the most
    (:attr:`ElasticCellAtJunction.load_fraction` says how much). ``follower``: the
    traction's normal part as a follower pressure on the deformed outline, by current polar
    angle (:mod:`oocyte_fe.experiment.loads`), instead of a dead load."""
    rows = read_vof_traction(Path(traction_csv))
    Path(folder).mkdir(parents=True, exist_ok=True)
    table = fe_traction_table(rows, diameter_um / 2, Path(folder) / "elastic_cell_traction.csv")
    searches = (0, line_search) if line_search else (0,)
    stopped: list[Attempt] = []
    best: ElasticCellAtJunction | None = None
    for size in (mesh_um, *(m for m in retry_mesh_um if m != mesh_um)):
        for search in searches:
            exp = Experiment.model_validate(
                {
                    "cell": {
                        "outer_diameter_um": diameter_um,
                        "zona_thickness_um": zona_um,
                        "symmetry": "plane_strain",
                        "mesh_size_um": size,
                        "materials": {
                            "zona": {"E_kPa": zona_kPa, "nu": 0.5},
                            "cytoplasm": {"E_kPa": cytoplasm_kPa, "nu": 0.5},
                        },
                        "self_contact": {} if self_contact else None,
                    },
                    "loads": {
                        "flow": {"type": "traction", "table": str(table), "follower": follower}
                    },
                    "support": "inertia_relief",
                    "time": {"duration_s": 1.0, "frames": frames, "line_search": search},
                }
            )
            result = run_experiment(exp)
            a, b = outline_extents_um(result)
            cell = ElasticCellAtJunction(result, b / a, table, size, tuple(stopped), search)
            if result.success:
                return cell
            stopped.append(Attempt(size, search, cell.load_fraction, result.folded))
            if best is None or cell.load_fraction > best.load_fraction:
                best = cell
    assert best is not None
    return replace(best, stopped=tuple(stopped))


def write_traction(
    write: Path, layout: Layout, fluids: Fluids, steps: StepPair | None = None, cell: str = "cell"
) -> Traction:
    """The load of the written time ``write`` (:func:`.vof.band_traction.band_traction`):
    from its own fields, or with ``steps`` from the second step after it with the transposed
    viscous part from the first (module docstring)."""
    if steps is None:
        return band_traction(write, layout, fluids, cell)
    first, second = steps(write)
    return band_traction(second, layout, fluids, cell, start=first)


def centroid_x(case: Path, time: float, cell: str = "cell") -> float:
    """The cell's centroid x (um) at ``time`` (s) from the run's per-step moments."""
    trace = moment_trace(case, [cell])
    return float(np.interp(time, trace.time, trace.centroid[:, 0]))


CREASE_STRETCH = 0.65
"""The principal stretch below which the surface of a compressed neo-Hookean solid creases
(plane strain, compressive strain 0.35: Hong, Zhao & Suo 2009, Appl. Phys. Lett. 95, 111901;
Biot's wrinkles follow at 0.54). The FE follows the smooth solution past it: an elastic
answer there is one the solid need not keep, far outside the small strains of the AFM
indentations that gave the moduli."""

READ_WINDOW_UM = 12.5  # the elastic b/a at x = 0: a line through the writes within +-12.5 um


def writes_around(
    case: Path, x: float = 0.0, half_window: float = READ_WINDOW_UM, cell: str = "cell"
) -> list[tuple[Path, float]]:
    """The written times of ``case`` whose centroid (per-step moments) lies within
    ``half_window`` um of ``x``, as (folder, centroid x); when fewer than two do, the last
    write before and the first after ``x`` (the nearest one alone when the run does not
    cross it)."""
    folders = time_directories(case)[1:]
    if not folders:
        raise InputError(case, "time folders", "a written time after t = 0")
    trace = moment_trace(case, [cell])
    xs = [float(np.interp(t, trace.time, trace.centroid[:, 0])) for t, _ in folders]
    inside = [k for k, xk in enumerate(xs) if abs(xk - x) <= half_window]
    if len(inside) >= 2:
        return [(folders[k][1], xs[k]) for k in inside]
    before = [k for k, xk in enumerate(xs) if xk <= x]
    after = [k for k, xk in enumerate(xs) if xk > x]
    if before and after:
        return [(folders[k][1], xs[k]) for k in (before[-1], after[0])]
    k = min(range(len(xs)), key=lambda k: abs(xs[k] - x))
    return [(folders[k][1], xs[k])]


@dataclass(frozen=True)
class ElasticAtPressure:
    """One pressure: the liquid run's b/a, the elastic cell under the traction of each write
    around the junction crossing (:func:`writes_around`) and its b/a at x = 0."""

    pressure_hPa: float
    liquid_b_over_a: float
    cells: tuple[ElasticCellAtJunction, ...]  # one per write
    traction_x_um: tuple[float, ...]  # the centroid's x at those writes
    follower: ElasticAtPressure | None = None  # the same with the follower reading

    @property
    def read_from(self) -> tuple[int, ...]:
        """The writes that b/a at x = 0 is read from: all of them when every FE run carried
        its whole traction; else those that did, when at least two did and they lie on both
        sides of x = 0 (a stall between two writes that carried: the crushed cell of the
        highest pressures, where a ZP element inverts or Newton cycles at one load shape and
        not at its neighbours'); else none."""
        ok = [k for k, c in enumerate(self.cells) if c.experiment.success]
        if len(ok) == len(self.cells):
            return tuple(ok)
        xs = [self.traction_x_um[k] for k in ok]
        return tuple(ok) if len(ok) >= 2 and min(xs) <= 0.0 <= max(xs) else ()

    @property
    def carried(self) -> bool:
        """b/a at x = 0 is known: every FE run carried its whole traction, or writes on both
        sides of x = 0 did (:attr:`read_from`)."""
        return bool(self.read_from)

    @property
    def left_out(self) -> tuple[int, ...]:
        """Writes whose FE run stopped short while the others give b/a (:attr:`read_from`)."""
        use = self.read_from
        return tuple(k for k in range(len(self.cells)) if use and k not in use)

    @property
    def b_over_a(self) -> float:
        """b/a at x = 0 from a straight line through the writes' b/a against their x (the
        traction, like the liquid's per-step b/a, jitters from one write to the next as the
        interface crosses the grid), over :attr:`read_from` (all writes when none is known);
        the single write's when there is one."""
        use = self.read_from or tuple(range(len(self.cells)))
        if len(use) == 1:
            return self.cells[use[0]].b_over_a
        ratios = [self.cells[k].b_over_a for k in use]
        x = np.array([self.traction_x_um[k] for k in use])
        slope, intercept = np.polyfit(x, ratios, 1)
        return float(intercept)

    @cached_property
    def smallest_stretch(self) -> float:
        """The smallest principal stretch of the FE runs b/a is read from
        (:attr:`ElasticCellAtJunction.smallest_stretch`)."""
        use = self.read_from or tuple(range(len(self.cells)))
        return min(self.cells[k].smallest_stretch for k in use)


def junction_tractions(
    case: Path,
    layout: Layout,
    fluids: Fluids,
    folder: Path,
    steps: StepPair | None = None,
    cell: str = "cell",
) -> list[tuple[Path, float]]:
    """The load of each write of ``case`` around the junction crossing
    (:func:`writes_around`; :func:`write_traction`) as a table ``folder/write<k>/
    vof_traction.csv``, with the centroid's x (um) at the load's time (with ``steps`` two
    steps after the write)."""
    out = []
    for k, (write, x_um) in enumerate(writes_around(case, cell=cell)):
        traction = write_traction(write, layout, fluids, steps, cell)
        sub = Path(folder) / f"write{k}"
        sub.mkdir(parents=True, exist_ok=True)
        x = x_um if steps is None else centroid_x(case, traction.time, cell)
        out.append((traction.write_csv(sub / "vof_traction.csv"), x))
    return out


def elastic_at_writes(
    pressure_hPa: float,
    liquid_b_over_a: float,
    tractions: list[tuple[Path, float]],
    subfolder: str = "",
    **cell: float | bool,
) -> ElasticAtPressure:
    """The elastic cell under each load of :func:`junction_tractions` (``cell``: keywords of
    :func:`elastic_cell_at_junction`; its folder ``<write>/<subfolder>``), read to x = 0 by
    :attr:`ElasticAtPressure.b_over_a`."""
    cells = tuple(
        elastic_cell_at_junction(csv, csv.parent / subfolder, **cell) for csv, _ in tractions
    )
    xs = tuple(x for _, x in tractions)
    return ElasticAtPressure(pressure_hPa, liquid_b_over_a, cells, xs)


def elastic_cells_at_junction(
    runs: list[tuple[float, Path, float]],
    layout_of: Callable[[float], Layout],
    fluids: Fluids,
    folder: Path,
    steps: StepPair | None = None,
    follower: bool = False,
    **cell: float | bool,
) -> list[ElasticAtPressure]:
    """For each run ``(pressure hPa, case, liquid b/a)``: the load of each write around the
    junction crossing (:func:`junction_tractions`, ``steps`` as there) on the elastic cell
    (:func:`elastic_at_writes`); ``layout_of(pressure)`` the run's mesh layout. One FE folder
    per pressure and write under ``folder``; with ``follower`` also the cell under the same
    traction's normal part as a follower pressure (``ElasticAtPressure.follower``; in
    ``<write>/follower``). The elastic cell's 1 - b/a grows by about 0.004 per um of travel
    there (300 hPa) and jitters by about 0.01 from write to write, hence the line through the
    writes to x = 0."""
    out = []
    for pressure, case, liquid in runs:
        where = Path(folder) / f"elastic_p{pressure:g}hPa"
        tractions = junction_tractions(case, layout_of(pressure), fluids, where, steps)
        dead = elastic_at_writes(pressure, liquid, tractions, **cell)
        if follower:
            other = elastic_at_writes(
                pressure, liquid, tractions, "follower", follower=True, **cell
            )
            dead = replace(dead, follower=other)
        out.append(dead)
    return out


def outline_at(outlines: list[np.ndarray], xs: list[float], x: float = 0.0) -> np.ndarray:
    """The outline at the centroid position ``x`` (um) from outlines (k, 2) about their
    centroids taken at positions ``xs``: at each polar angle of the outline nearest ``x``, a
    straight line through the radii against position, evaluated at ``x`` (the read of
    :attr:`ElasticAtPressure.b_over_a` applied to the shape); the nearest outline when
    there is one."""
    near = int(np.argmin(np.abs(np.asarray(xs) - x)))
    if len(outlines) == 1:
        return outlines[near]
    theta = np.arctan2(outlines[near][:, 1], outlines[near][:, 0])
    radii = np.array([radii_at(o, theta) for o in outlines])
    slope, intercept = np.polyfit(np.asarray(xs, dtype=float) - x, radii, 1)
    return intercept[:, None] * np.column_stack([np.cos(theta), np.sin(theta)])


def radii_at(outline: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The radius (um) of a star-shaped outline (k, 2) about its origin at the polar angles
    ``theta`` (rad): linear between its points, periodic in the angle."""
    at = np.arctan2(outline[:, 1], outline[:, 0])
    order = np.argsort(at)
    r = np.hypot(outline[:, 0], outline[:, 1])
    return np.interp(theta, at[order], r[order], period=2 * np.pi)


@dataclass(frozen=True)
class Table4Comparison:
    """Mean absolute error of b/a against the experiment, per model (over the given pressures)."""

    errors: dict[str, float]

    @property
    def closer(self) -> str:
        """The model with the smaller mean absolute error."""
        return min(self.errors, key=self.errors.get)  # type: ignore[arg-type]

    def sentence(self) -> str:
        """Which model comes closer to the experiment and by how much."""
        ranked = sorted(self.errors.items(), key=lambda kv: kv[1])
        best, rest = ranked[0], ranked[1:]
        others = ", ".join(f"{k} {v:.4f}" for k, v in rest)
        return (
            f"Closer to the experiment: **{best[0]}** (mean |b/a - experiment| = {best[1]:.4f}; "
            f"{others})."
        )


def compare_table4(experiment: np.ndarray, **models: np.ndarray) -> Table4Comparison:
    """Mean ``|b/a - experiment|`` of each model (keyword: name = its b/a per pressure)."""
    exp = np.asarray(experiment, dtype=float)
    return Table4Comparison(
        {
            name: float(np.mean(np.abs(np.asarray(v, dtype=float) - exp)))
            for name, v in models.items()
        }
    )
