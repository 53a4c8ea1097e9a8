"""The pipette press in plane strain: layered disc, wedge pipette, held far-side rim.

Finite-strain, nearly incompressible neo-Hookean layers with a Prony series on the ZP
(:mod:`oocyte_fe.fe.material`), P2/P1 Taylor-Hood, bonded ZP/cytoplasm; quasi-static Newton
steps (:mod:`oocyte_fe.fe.solver`), the viscous history advancing with the pipette time
``t = s / v`` (advance ``s`` um, speed ``v`` um/s). The pipette is the rigid
:func:`~oocyte_fe.fe.obstacles.wedge_tip` (flat mouth, flanks at the included tip angle),
frictionless penalty contact on the outer surface with ``eps_N = penalty_factor * E_max / h``
(kPa/um, ``h`` the element size at the contact). The outer-surface facets with ``x < 0`` and
``|y| <= hold_half_width`` are fixed in x and y (the holding pipette, as the NMSD's held
rim nodes); that also removes the rigid-body motion.

Plane strain gives forces per unit thickness: ``f`` [nN/um] is the x component of the force
on the pipette (positive: the cell pushes back against the motion). Displacements at given
reference points are interpolated in the P2 field (:meth:`skfem.Basis.probes`).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
import skfem

from oocyte_fe.crosscheck.scenario import PressScenario
from oocyte_fe.crosscheck.zp_material import LayerMaterials
from oocyte_fe.errors import InputError
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.contact import Contact
from oocyte_fe.fe.fields import point_probes, stress_fields
from oocyte_fe.fe.loads import Prescribed
from oocyte_fe.fe.obstacles import Polyline, wedge_tip
from oocyte_fe.fe.solver import Frame, NewtonSettings, Problem
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh

PIPETTE = "pipette"
HELD = "held"


@dataclass(frozen=True)
class FeSettings:
    """Mesh and stepping of the FE press (um).

    ``size_um``: element size away from the contact; ``refine_size_um``: size within
    ``refine_depth_um`` of the outer arcs within ``refine_half_window_deg`` of 3 o'clock (the
    window is mirrored to 9 o'clock, where the holder sits); ``step_um``: pipette advance per
    output frame; ``max_step_um``: largest solver step; ``penalty_factor``: ``eps_N h / E_max``;
    ``rtol``: Newton tolerance on the relative residual (contact chatter: docs/cases/nmsd_vs_fe.md);
    ``contact_smoothing_um``: the C1 smoothing of the normal contact law (it stops the chatter
    of a point at the wedge corner that switched in and out of contact at 60.8 um).
    """

    size_um: float = 6.0
    refine_size_um: float = 2.5
    refine_half_window_deg: float = 30.0
    refine_depth_um: float = 20.0
    step_um: float = 2.5
    max_step_um: float = 1.25
    penalty_factor: float = 30.0
    rtol: float = 1e-6
    contact_smoothing_um: float = 0.2
    source: str = "FeSettings"

    def __post_init__(self) -> None:
        for name in ("size_um", "refine_size_um", "refine_depth_um", "step_um", "max_step_um"):
            if not getattr(self, name) > 0:
                raise InputError(self.source, name, "> 0 um", getattr(self, name))
        if not 0 < self.refine_half_window_deg < 90:
            raise InputError(
                self.source, "refine_half_window_deg", "in (0, 90) deg", self.refine_half_window_deg
            )
        if not self.contact_smoothing_um >= 0:
            raise InputError(
                self.source, "contact_smoothing_um", ">= 0 um", self.contact_smoothing_um
            )
        if not 0 < self.rtol < 1e-2:
            raise InputError(self.source, "rtol", "in (0, 0.01)", self.rtol)
        if not self.penalty_factor > 0:
            raise InputError(self.source, "penalty_factor", "> 0", self.penalty_factor)


@dataclass(frozen=True, eq=False)
class FePress:
    """FE press history at the output advances (the first entry is the rest state).

    ``advance_um`` (k,), ``force_nN_per_um`` (k,), ``point_displacement_um`` (k, p, 2) at the
    reference ``points_um`` (p, 2), ``vertex_displacement_um`` (k, 2, nverts),
    ``vertex_pressure_kPa`` (k, nverts) = ``-tr(sigma)/3``, maximum penetration (k,) um,
    solver steps, cutbacks, Newton iterations and wall time (s).
    """

    mesh: skfem.Mesh
    pipette: Polyline
    advance_um: np.ndarray
    force_nN_per_um: np.ndarray
    points_um: np.ndarray
    point_displacement_um: np.ndarray
    vertex_displacement_um: np.ndarray
    vertex_pressure_kPa: np.ndarray
    penetration_um: np.ndarray
    steps: int
    cutbacks: int
    newton_iterations: int
    seconds: float

    def displacement_at(self, advance_um: float) -> np.ndarray:
        """Point displacements (p, 2) um at an output advance."""
        k = int(np.argmin(np.abs(self.advance_um - advance_um)))
        if abs(self.advance_um[k] - advance_um) > 1e-9:
            raise InputError("FePress", "advance_um", "an output advance", advance_um)
        return self.point_displacement_um[k]


def held_mesh(scenario: PressScenario, settings: FeSettings) -> skfem.Mesh:
    """Layered plane-strain disc (P2, curved) with the extra boundary ``held``."""
    half = settings.refine_half_window_deg
    geom = LayeredOocyte(
        cytoplasm_radius_um=0.5 * scenario.cytoplasm_diameter_um,
        zona_thickness_um=scenario.zona_thickness_um,
        form="plane_strain",
        size_um=settings.size_um,
        refine_polar_deg=(90.0 - half, 90.0 + half),
        refine_size_um=settings.refine_size_um,
        refine_depth_um=settings.refine_depth_um,
        order=2,
    )
    mesh = layered_oocyte_mesh(geom)
    w = scenario.hold_half_width_um
    return mesh.with_boundaries({HELD: lambda x: (x[0] < 0.0) & (np.abs(x[1]) <= w)})


def pipette_at(scenario: PressScenario, advance_um: float, length_um: float = 80.0) -> Polyline:
    """The wedge pipette after ``advance_um`` of travel (mouth at x = R - advance)."""
    return wedge_tip(
        (scenario.radius_um - advance_um, 0.0),
        (-1.0, 0.0),
        scenario.pipette_width_um,
        scenario.tip_angle_deg,
        length_um,
    )


def run_fe_press(
    scenario: PressScenario,
    materials: LayerMaterials,
    settings: FeSettings,
    travel_um: float,
    points_um: np.ndarray,
    log: logging.Logger | None = None,
) -> FePress:
    """Press the FE disc ``travel_um`` at the scenario speed; record every ``step_um``."""
    if not travel_um > 0:
        raise InputError(settings.source, "travel_um", "> 0", travel_um)
    tic = time.perf_counter()
    mesh = held_mesh(scenario, settings)
    body = Body(
        mesh, {"zona": materials.zona, "cytoplasm": materials.cytoplasm}, "plane_strain", order=2
    )
    v = scenario.speed_um_s
    e_max = max(materials.zona.E_kPa, materials.cytoplasm.E_kPa)
    penalty = settings.penalty_factor * e_max / settings.refine_size_um
    pipette = pipette_at(scenario, 0.0)
    contact = Contact(
        "outer_surface",
        pipette,
        penalty,
        motion=lambda t: (-v * t, 0.0),
        name=PIPETTE,
        smoothing_um=settings.contact_smoothing_um,
    )
    problem = Problem(body, [Prescribed(HELD, 0), Prescribed(HELD, 1)], contacts=[contact], log=log)
    n_out = max(1, int(np.ceil(travel_um / settings.step_um - 1e-9)))
    advances = np.linspace(0.0, travel_um, n_out + 1)
    probes = point_probes(body, points_um)
    frames: list[Frame] = []
    solved = problem.solve(
        advances[1:] / v,
        NewtonSettings(max_iterations=25, rtol=settings.rtol, max_cutbacks=8),
        on_frame=frames.append,
        max_dt=settings.max_step_um / v,
    )
    n_p = len(points_um)
    u_pts = [np.zeros((n_p, 2))]
    u_vert = [np.zeros((2, mesh.nvertices))]
    p_vert = [np.zeros(mesh.nvertices)]
    force, pen = [0.0], [0.0]
    for f in frames:
        u = body.displacement(f.x)
        u_pts.append((probes @ u).reshape(2, n_p).T)
        u_vert.append(body.vertex_displacement(f.x))
        p_vert.append(-stress_fields(problem, f.x)["mean_stress"])
        force.append(float(f.obstacle_forces[PIPETTE][0]))
        pen.append(float(f.contact_pressure[PIPETTE].max()) / penalty)
    return FePress(
        mesh=mesh,
        pipette=pipette,
        advance_um=advances,
        force_nN_per_um=np.array(force),
        points_um=np.asarray(points_um, dtype=float),
        point_displacement_um=np.array(u_pts),
        vertex_displacement_um=np.array(u_vert),
        vertex_pressure_kPa=np.array(p_vert),
        penetration_um=np.array(pen),
        steps=len(solved.steps),
        cutbacks=solved.cutbacks,
        newton_iterations=sum(s.iterations for s in solved.steps),
        seconds=time.perf_counter() - tic,
    )
