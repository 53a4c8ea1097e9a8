"""One driver for every FE experiment on a layered cell: description in, result out.

:func:`run_experiment` builds the cell's mesh (refined at each tool), the body with a material
per layer, one :class:`~oocyte_fe.fe.contact.Contact` per rigid tool (penalty
``eps_N = penalty_factor E_max / h``, ``h`` the refined element size: the one place the penalty
is chosen), the suction of each pipette as a lagged follower pressure on the surface inside its
bore, the holds, and solves the time path with Newton and cutbacks. A step that fails after
its cutbacks ends the experiment early: the result keeps every frame solved before, with
``success = False`` and the solver's reason (FElupe's NewtonResult is the model).

Records per output frame (the first is the rest state at t = 0): the force on each tool
[nN, axisymmetric: the ring sum; plane strain: per um of thickness], its advance [um], the
contact radius [um] (largest distance from the tool's axis of a loaded contact point), for a
pipette the suction [kPa] and the aspiration length (the tongue's apex above the mouth plane,
and its change since t = 0) [um], the tracks of the material points [um], the volume change,
and the reaction of the holds [nN] (from the balance of the tools' and suction forces).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
import skfem
from numpy.typing import NDArray

from oocyte_fe.errors import InadmissibleState, SolverError
from oocyte_fe.experiment import tools as tl
from oocyte_fe.experiment.description import (
    Experiment,
    HoldingPipette,
    NeckedPipette,
    StraightPipette,
    to_material,
)
from oocyte_fe.experiment.outline import body_outline_um, crossing_points, facet_length_um
from oocyte_fe.experiment.surface_loads import inertia_relief, rigid_pins, surface_loads
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.contact import Contact, ContactLaw
from oocyte_fe.fe.fields import point_probes
from oocyte_fe.fe.loads import (
    FollowerPressure,
    Prescribed,
    ReactionControl,
    TorqueRelief,
)
from oocyte_fe.fe.obstacles import Linearised
from oocyte_fe.fe.self_contact import SelfContact
from oocyte_fe.fe.solver import Frame, NewtonSettings, Problem, StepLog, dead_load_vector
from oocyte_fe.fe.vectorized import FacetOperators
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
from oocyte_fe.neck.suction import seal_mask


@dataclass(frozen=True)
class ExperimentResult:
    """Histories of an experiment, one row per output frame (the first at t = 0).

    ``force_nN[tool]`` (k, 2) is the force on the tool (global x, y components);
    ``advance_um[tool]`` (k,) its advance towards the cell; ``contact_radius_um[tool]`` (k,);
    ``suction_kPa``, ``aspiration_um`` (apex above the mouth plane) and
    ``aspiration_change_um`` (since t = 0) per pipette with suction; ``load_force_nN[load]``
    (k, 2) the resultant of each surface load on the cell (with a follower traction also
    ``"translation relief"``: the body force that takes the change of its resultant as the
    cell deforms, :class:`~oocyte_fe.fe.loads.TorqueRelief`); ``tracks_um[point]`` (k, 2)
    displacement of each material point; ``hold_reaction_nN`` (k, 2) the reaction of the
    holds (of the pins of a free cell: the loads' imbalance left after inertia relief).
    ``folded``: the run stopped because the next frame's outline passed through itself.
    """

    experiment: Experiment
    times_s: NDArray
    force_nN: dict[str, NDArray]
    advance_um: dict[str, NDArray]
    contact_radius_um: dict[str, NDArray]
    suction_kPa: dict[str, NDArray]
    aspiration_um: dict[str, NDArray]
    aspiration_change_um: dict[str, NDArray]
    tracks_um: dict[str, NDArray]
    load_force_nN: dict[str, NDArray]
    hold_reaction_nN: NDArray
    volume_change: NDArray
    frames: tuple[Frame, ...]
    steps: tuple[StepLog, ...]
    problem: Problem
    success: bool
    reason: str
    seconds: float
    n_dofs: int = field(default=0)
    folded: bool = False  # stopped where the outer surface would pass through itself

    @property
    def newton_iterations(self) -> int:
        return sum(s.iterations for s in self.steps)

    @property
    def cutbacks(self) -> int:
        return sum(s.cutbacks for s in self.steps)


def _refined_mesh(exp: Experiment) -> skfem.Mesh:
    """The cell's P2 mesh, refined in a polar window at each tool's pole."""
    cell, s = exp.cell, exp.mesh_scale
    size = cell.mesh_size_um * s
    fine = (cell.refine_size_um or cell.mesh_size_um) * s
    half = cell.refine_half_angle_deg
    if cell.refine_windows_deg is not None:  # the user's windows instead of the tools'
        windows = sorted({(float(lo), float(hi)) for lo, hi in cell.refine_windows_deg})
    else:
        windows = sorted({w for t in exp.tools.values() for w in _windows(t, cell.radius_um, half)})
    refine = fine < size and bool(windows)
    geom = LayeredOocyte(
        cytoplasm_radius_um=cell.radius_um - cell.zona_thickness_um,
        zona_thickness_um=cell.zona_thickness_um,
        form=cell.symmetry,
        size_um=size,
        refine_polar_deg=windows[0] if refine else None,
        refine_windows_deg=tuple(windows[1:]) if refine else (),
        refine_size_um=fine if refine else None,
        refine_depth_um=(cell.refine_depth_um or max(cell.zona_thickness_um, 4 * fine))
        if refine
        else None,
        order=2 if cell.curved_edges else 1,  # P2 either way; curved or straight edges
    )
    return layered_oocyte_mesh(geom)


def _windows(tool: object, radius_um: float, half_deg: float) -> list[tuple[float, float]]:
    """Polar windows refined at a tool; a pipette's seal edges (r = a + f and a + w) split
    them, so that mesh vertices sit there and the sealed facets are exactly those under the
    end face (a facet straddling the edge would move the punch's radius by half an element)."""
    if isinstance(tool, HoldingPipette | NeckedPipette):  # a necked pipette: along the side
        return []
    pole = {"top": 0.0, "bottom": 180.0, "left": 90.0, "right": 90.0}[tool.side]
    lo, hi = max(0.0, pole - half_deg), min(180.0, pole + half_deg)
    cuts = []
    if isinstance(tool, StraightPipette) and tool.seal == "fixed":
        for r in (tool.inner_radius_um + tool.mouth_fillet_um, tool.inner_radius_um + tool.wall_um):
            theta = float(np.degrees(np.arcsin(min(1.0, r / radius_um))))
            cuts.append(theta if pole == 0.0 else 180.0 - theta)
    edges = sorted({lo, hi, *[c for c in cuts if lo < c < hi]})
    return list(zip(edges[:-1], edges[1:], strict=True))


def _with_holds(mesh: skfem.Mesh, exp: Experiment) -> skfem.Mesh:
    """``mesh`` with a boundary ``hold:<name>`` per holding pipette (outer-surface facets)."""
    outer = mesh.boundaries["outer_surface"]
    mid = mesh.p[:, mesh.facets[:, outer]].mean(axis=1)
    holds = {}
    for name, tool in exp.tools.items():
        if isinstance(tool, HoldingPipette):
            holds[f"hold:{name}"] = outer[tl.held_facets(tool, mid, exp.cell.radius_um)]
        elif isinstance(tool, StraightPipette) and tool.seal == "fixed":
            holds[f"seal:{name}"] = outer[tl.sealed_facets(tool, mid)]
    return mesh.with_boundaries(holds) if holds else mesh


def _supports(exp: Experiment, mesh: skfem.Mesh) -> list[Prescribed]:
    axisym = exp.cell.symmetry == "axisymmetric"
    fixed = [Prescribed("axis", 0)] if axisym else []
    holds = [(n, t) for n, t in exp.tools.items() if isinstance(t, HoldingPipette)]
    for name, tool in holds:
        if mesh.boundaries[f"hold:{name}"].size == 0:
            raise SolverError(f"tools.{name}: the holding pipette holds no facet of the surface")
        axial = 0 if tool.side in ("left", "right") else 1
        components = (0, 1) if tool.components == "both" else (axial,)
        move = tl.motion(tool)
        fixed += [
            Prescribed(f"hold:{name}", c, lambda t, c=c, move=move: move(t)[c])
            for c in components
            if not (axisym and c == 0)
        ]
    seals = [n for n, t in exp.tools.items() if getattr(t, "seal", "") == "fixed"]
    for name in seals:
        if mesh.boundaries[f"seal:{name}"].size == 0:
            raise SolverError(f"tools.{name}: no surface facet under the pipette's end face")
        tool = exp.tools[name]
        fixed.append(Prescribed(f"seal:{name}", 0 if tool.side in ("left", "right") else 1))
    if exp.support == "inertia_relief":
        fixed += rigid_pins(mesh, axisym)
    # without holds or seals the tools on top and bottom hold the cell by their contacts
    # (validated); a point pin at the centre would be a point force in 3-D, singular as soon
    # as the mesh's asymmetry loads it (it inverted elements at 1 % compression)
    return fixed


def _controlled(_t: float) -> float:
    return 0.0  # the suction is the unknown of a ReactionControl, not a function of time


def cell_mesh(exp: Experiment) -> skfem.Mesh:
    """The experiment's mesh: refined at each tool, with a boundary ``hold:<tool>`` per holding
    pipette and ``seal:<tool>`` per fixed pipette seal (outer-surface facets only)."""
    return _with_holds(_refined_mesh(exp), exp)


def run_experiment(
    exp: Experiment,
    log: logging.Logger | None = None,
    on_frame: Callable[[Problem, Frame], None] | None = None,
) -> ExperimentResult:
    """Solve the experiment ``exp`` over its time path; see the module docstring."""
    tic = time.perf_counter()
    cell = exp.cell
    R = cell.radius_um
    axisym = cell.symmetry == "axisymmetric"
    mesh = cell_mesh(exp)
    materials = {}  # the ZP first: its pressure block comes first in x
    if cell.zona_thickness_um > 0:
        materials["zona"] = to_material(cell.materials.zona, "materials.zona")
    materials["cytoplasm"] = to_material(cell.materials.cytoplasm, "materials.cytoplasm")
    small = exp.kinematics == "small_strain"
    body = Body(mesh, materials, cell.symmetry, order=2, source="cell", kinematics=exp.kinematics)
    e_max = max(m.E_kPa for m in materials.values())
    h = (cell.refine_size_um or cell.mesh_size_um) * exp.mesh_scale
    contacts, pressures, pipettes = [], [], {}
    control = None
    for name, tool in exp.tools.items():
        rigid = tl.obstacle(tool, name, R, axisym)
        if rigid is None:
            continue
        if small:  # Sneddon's contact: a pressure along the tool's axis
            rigid = Linearised(rigid, tuple(float(c) for c in tl.approach(tool.side)), name)
        contacts.append(
            Contact(
                "outer_surface",
                rigid,
                ContactLaw(
                    tool.penalty_factor * e_max / h,
                    friction=tool.friction,
                    smoothing_um=tool.smoothing_um,
                ),
                motion=tl.motion(tool),
                name=name,
                quadrature_order=tool.quadrature_order,
            )
        )
        if isinstance(tool, StraightPipette) and tool.suction_Pa is not None:
            path = tool.suction_Pa
            pipettes[name] = tool
            pressures.append(
                FollowerPressure(
                    "outer_surface",
                    lambda t, path=path: -1e-3 * path(t),  # Pa -> kPa; suction pulls outwards
                    where=tl.SuctionMask(tool, R),
                    name=name,
                    lagged=True,
                )
            )
        if isinstance(tool, NeckedPipette):
            path = tool.suction_Pa
            pipettes[name] = tool
            pressures.append(
                FollowerPressure(
                    "outer_surface",
                    (lambda t, path=path: -1e-3 * path(t)) if path else _controlled,
                    where=seal_mask(tl.necked_pipette(tool, R), tool.seal_tol_um),
                    name=name,
                    lagged=True,
                )
            )
            if tool.suction_control is not None:
                ctl = tool.suction_control
                control = ReactionControl(name, f"hold:{ctl.tool}", 1, ctl.target_nN)
    load_pressures, tractions = surface_loads(exp)
    follows = any(getattr(load, "follower", False) for load in exp.loads.values())
    dead: list = list(tractions)
    if exp.support == "inertia_relief":
        vectors = [(t.name, dead_load_vector(body, t), t.scale) for t in tractions]
        ops = FacetOperators.of(body.facet_basis("outer_surface"))
        for pl in load_pressures:
            pn = np.ones(ops.dS.shape) if pl.where is None else pl.where(ops.X).astype(float)
            f = ops.pressure_force(np.zeros(body.n_u), pn, axisym)
            vectors.append((pl.name, f, pl.pressure))
        dead += inertia_relief(body, vectors)
    problem = Problem(
        body,
        _supports(exp, mesh),
        pressures + load_pressures,
        contacts,
        log=log,
        control=control,
        dead_loads=dead,
        torque_relief=TorqueRelief(translation=follows)
        if exp.support == "inertia_relief" and not axisym
        else None,
        self_contact=None
        if cell.self_contact is None
        else SelfContact(
            "outer_surface",
            cell.self_contact.penalty_factor * e_max / h,
            cell.self_contact.range_um or 0.1 * h,
            depth_um=h,
        ),
    )
    probes = point_probes(body, np.array(list(cell.points.values()))) if cell.points else None
    rows: list[dict] = []
    v0 = problem.volume(problem.x)
    outer_vertices = np.unique(mesh.facets[:, mesh.boundaries["outer_surface"]])

    contact_points = [np.asarray(fb.global_coordinates()) for _, fb in problem.contacts]
    split = body.ubasis.split_indices()
    ring = np.array([0.0, 1.0]) if axisym else np.ones(2)  # axisymmetric: x sums are not forces

    def record(frame: Frame, notify: bool = True) -> None:
        u = body.displacement(frame.x)
        row: dict = {"t": frame.t, "volume": frame.volume / v0 - 1.0}
        current = mesh.p[:, outer_vertices] + body.vertex_displacement(frame.x)[:, outer_vertices]
        net = np.zeros(2)
        for (c, fb), X in zip(problem.contacts, contact_points, strict=True):
            tool = exp.tools[c.name]
            force = np.asarray(frame.obstacle_forces[c.name], dtype=float)
            net += force
            row[("force", c.name)] = force
            path = getattr(tool, "displacement_um", None)
            row[("advance", c.name)] = 0.0 if path is None else path(frame.t)
            xq = X + np.asarray(fb.interpolate(u))
            lateral = np.abs((tl.rotation(tool.side).T @ xq.reshape(2, -1))[0])
            loaded = frame.contact_pressure[c.name].ravel() > 0
            row[("radius", c.name)] = float(lateral[loaded].max()) if loaded.any() else 0.0
        for k, (pl, _) in enumerate(problem.pressures):
            if pl.name in exp.loads:  # a surface load: its pull on the cell
                force = pl.pressure(frame.t) * problem.unit_load(k, frame.x)
                row[("load", pl.name)] = np.array([np.sum(force[d]) for d in split]) * ring
                net -= row[("load", pl.name)]
                continue
            tool = pipettes[pl.name]
            controlled = problem.control is not None and problem.control.load == pl.name
            p = -problem.control_value if controlled else -pl.pressure(frame.t)
            suction = -p * problem.unit_load(k, frame.x)
            net -= [np.sum(suction[dofs]) for dofs in split]
            row[("suction", pl.name)] = p
            if isinstance(tool, StraightPipette):
                local = tl.rotation(tool.side).T @ current
                inside = np.abs(local[0]) < tool.inner_radius_um
                apex = float(local[1][inside].max()) if inside.any() else np.nan
                row[("aspiration", pl.name)] = apex - tl.mouth_height(tool, R)
        for load, _ in problem.dead_loads:
            force = problem.dead_load_force(load.name, frame.t)
            if load.name in exp.loads:  # a follower traction: its normal part is above
                row[("load", load.name)] = row.get(("load", load.name), 0.0) + force
            net -= force
        if follows:  # the translation relief takes the follower's change of resultant
            row[("load", "translation relief")] = net.copy()
            net = np.zeros(2)
        # the cell's balance: forces on tools + on holds = pull of the suction on the cell
        row["hold"] = -net * ([0.0, 1.0] if axisym else [1.0, 1.0])  # axisym: z is net
        if probes is not None:
            row["tracks"] = (probes @ u).reshape(2, -1).T
        rows.append(row)
        if notify and on_frame is not None:
            on_frame(problem, frame)

    record(problem.frame(), notify=False)  # the rest state
    times = exp.output_times()
    success, reason, steps, folded = True, "", [], False
    frames = [problem.frame()]
    try:
        solved = problem.solve(
            times,
            NewtonSettings(
                max_iterations=exp.time.max_iterations,
                rtol=exp.time.rtol,
                max_cutbacks=exp.time.max_cutbacks,
                line_search=exp.time.line_search,
                retry_from_last_state=exp.time.retry_from_last_state,
            ),
            on_frame=lambda f: (frames.append(f), record(f)),
            max_dt=exp.time.max_step_s,
            admissible=lambda f: _surface_check(problem, f),
        )
        steps = solved.steps
    except SolverError as exc:
        success, reason = False, str(exc)
        steps = list(getattr(exc.result, "steps", []))
        folded = isinstance(exc, InadmissibleState)
    result = _result(exp, rows, frames, steps, problem, success, reason, tic)
    return replace(result, folded=folded)


def _surface_check(problem: Problem, frame: Frame) -> str:
    """What is wrong with the frame's outline: "" unless it passes through itself away from
    the tools. Within a facet's length of a tool a crossing is the contact's give (the two
    sides of a blade's tip pressed into it) or a facet turned round the tool's corner, a
    wrinkle below the mesh's resolution there; not a fold."""
    body = problem.body
    points = crossing_points(body_outline_um(body, frame.x, nodes=True))  # (n, 2)
    if len(points) and problem.contacts:
        h = facet_length_um(body, frame.x, points)
        for c, _ in problem.contacts:
            gap, _ = c.obstacle.distance(points.T - np.asarray(c.motion(frame.t))[:, None])
            points, h = points[gap >= h], h[gap >= h]
    n = len(points)
    if n == 0:
        return ""
    return (
        f"the outer surface passes through itself ({n} crossing{'s' if n > 1 else ''} of the "
        "outline: a fold; cell.self_contact makes it touch instead)"
    )


def _result(exp, rows, frames, steps, problem, success, reason, tic) -> ExperimentResult:
    def series(kind: str) -> dict[str, NDArray]:
        names = [key[1] for key in rows[0] if isinstance(key, tuple) and key[0] == kind]
        return {n: np.array([r[(kind, n)] for r in rows]) for n in names}

    aspiration = series("aspiration")
    tracks = {}
    if "tracks" in rows[0]:
        stack = np.array([r["tracks"] for r in rows])
        tracks = {name: stack[:, i] for i, name in enumerate(exp.cell.points)}
    return ExperimentResult(
        experiment=exp,
        times_s=np.array([r["t"] for r in rows]),
        force_nN=series("force"),
        advance_um=series("advance"),
        contact_radius_um=series("radius"),
        suction_kPa=series("suction"),
        aspiration_um=aspiration,
        aspiration_change_um={n: a - a[0] for n, a in aspiration.items()},
        tracks_um=tracks,
        load_force_nN=series("load"),
        hold_reaction_nN=np.array([r["hold"] for r in rows]),
        volume_change=np.array([r["volume"] for r in rows]),
        frames=tuple(frames),
        steps=tuple(steps),
        problem=problem,
        success=success,
        reason=reason,
        seconds=time.perf_counter() - tic,
        n_dofs=problem.body.n_dofs,
    )
