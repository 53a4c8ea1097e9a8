"""The oocyte passing the pipette neck: quasi-static, axisymmetric, penalty contact + friction.

The driver is a prescribed advance of a small rear cap (polar angle > 180 - cap_deg) at a
constant rate, together with the suction ``dp`` solved in every step so that the cap pushes no
net axial force (:class:`~oocyte_fe.fe.loads.ReactionControl`: displacement control of the
progress, the suction the unknown load). Until the oocyte seals against the wall there is no
suction and the cap carries the (small) resistance. The suction is the physical driver, and
its history ``dp(w)`` is the suction a quasi-static passage needs at the advance ``w``. Under a
fixed suction ``dp0`` (100 Pa in the seed) the oocyte therefore stops at the first advance where
``dp(w) > dp0``; where ``dp(w)`` falls with ``w`` a fixed suction would pull the oocyte through
faster than quasi-statically (a snap into the neck). The oocyte starts ``clearance_um`` from
the taper (its free travel along the wide bore meets no resistance and is not modelled).

Coordinates: the oocyte's centre at the origin, the pipette axis along +Z (the direction of
travel). Axial force balance on the oocyte (internal forces sum to zero along Z)::

    F_push + F_suction = F_wall,   F_wall = F_normal + F_friction   (force on the glass, +Z)
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from oocyte_fe.checks import numeric_fields
from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.fe import contact as ct
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.loads import FollowerPressure, Prescribed, ReactionControl
from oocyte_fe.fe.material import Material
from oocyte_fe.fe.solver import Frame, NewtonSettings, Problem, StepLog
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh
from oocyte_fe.neck.periphery import MaterialPoints
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.neck.suction import axial_dofs, axial_suction_force, seal_mask


@dataclass(frozen=True)
class PassageSettings:
    """Mesh, time stepping, contact and driver of one passage (um, s, kPa)."""

    size_um: float = 8.0
    refine_factor: float = 2.0
    duration_s: float = 1.0
    steps: int = 50
    advance_um: float = 150.0
    friction: float = 0.2
    penalty_factor: float = 20.0
    seal_tol_um: float = 0.5
    clearance_um: float = 0.1
    cap_deg: float = 10.0
    max_cutbacks: int = 8
    lagged_seal: bool = True  # seal mask held per step (its derivative is not in the tangent)

    def __post_init__(self) -> None:
        numeric_fields(self, "PassageSettings")
        checks = {
            "size_um": self.size_um > 0,
            "refine_factor": self.refine_factor >= 1,
            "duration_s": self.duration_s > 0,
            "steps": self.steps >= 1,
            "advance_um": self.advance_um > 0,
            "friction": self.friction >= 0,
            "penalty_factor": self.penalty_factor > 0,
            "seal_tol_um": self.seal_tol_um > 0,
            "clearance_um": self.clearance_um >= 0,
            "cap_deg": 0 < self.cap_deg < 90,
        }
        for name, ok in checks.items():
            if not ok:
                raise InputError("PassageSettings", name, "a value in range", getattr(self, name))

    def mesh_geometry(self, cytoplasm_radius_um: float, zona_um: float) -> LayeredOocyte:
        """P2 layered mesh, refined by ``refine_factor`` within 20 um of the side (20-160 deg)."""
        refine = self.refine_factor > 1
        return LayeredOocyte(
            cytoplasm_radius_um=cytoplasm_radius_um,
            zona_thickness_um=zona_um,
            size_um=self.size_um,
            refine_polar_deg=(20.0, 160.0) if refine else None,
            refine_size_um=self.size_um / self.refine_factor if refine else None,
            refine_depth_um=20.0 if refine else None,
        )


@dataclass
class PassageResult:
    """Histories (one entry per output frame) and the frames of one passage."""

    settings: PassageSettings
    pipette: NeckedPipette
    problem: Problem
    points: MaterialPoints
    frames: list[Frame] = field(default_factory=list)
    steps: list[StepLog] = field(default_factory=list)
    history: dict[str, list] = field(default_factory=dict)
    wall_profiles: list[tuple[NDArray, NDArray]] = field(default_factory=list)
    failure: str = ""

    @property
    def complete(self) -> bool:
        return not self.failure

    def series(self, name: str) -> NDArray:
        return np.asarray(self.history[name], dtype=float)


def centroid_advance(body: Body, u: NDArray) -> float:
    """Volume-mean axial displacement ``int u_Z 2 pi R dA / int 2 pi R dA`` [um]."""
    b = body.ubasis
    uq = np.asarray(b.interpolate(u))
    w = 2.0 * np.pi * np.asarray(b.global_coordinates())[0] * b.dx
    return float(np.sum(uq[1] * w) / np.sum(w))


def _wall_split(problem: Problem, t: float) -> tuple[float, float, NDArray, NDArray]:
    """Axial force on the glass from normal pressure and from friction [nN]; the current Z of
    the contact quadrature points and their pressure [kPa] (for the profile along the wall)."""
    (c, fb), state = problem.contacts[0], problem.contact_states[0]
    u = problem.body.displacement(problem.x)
    X = np.asarray(fb.global_coordinates())
    uq = np.asarray(fb.interpolate(u))
    ev = ct.evaluate(c, X, uq, state, t)
    measure = 2.0 * np.pi * X[0] * fb.dx
    normal = -float(np.sum(ev.pressure * ev.normal[1] * measure))
    friction = -float(np.sum(ev.shear * ev.tangent[1] * measure))
    return normal, friction, (X + uq)[1].ravel(), ev.pressure.ravel()


def _unused_pressure(_t: float) -> float:
    return 0.0  # the suction is the unknown of the ReactionControl, not a function of time


def run_passage(
    materials: dict[str, Material],
    settings: PassageSettings,
    pipette: NeckedPipette | None = None,
    cytoplasm_radius_um: float = 75.0,
    zona_um: float = 15.0,
    log: logging.Logger | None = None,
    on_frame: Callable[[PassageResult, Frame], None] | None = None,
) -> PassageResult:
    """Solve one passage; a driver that finds no equilibrium ends it early (``failure``)."""
    s = settings
    radius = cytoplasm_radius_um + zona_um
    mesh = layered_oocyte_mesh(s.mesh_geometry(cytoplasm_radius_um, zona_um))
    cap_z = -radius * np.cos(np.deg2rad(s.cap_deg)) + 1e-9 * radius
    mesh = mesh.with_boundaries({"rear_cap": lambda x: x[1] < cap_z}, boundaries_only=True)
    body = Body(mesh, materials, "axisymmetric", order=2)
    pipette = (pipette or NeckedPipette()).touching(radius, s.clearance_um)
    e_max = max(m.E_kPa for m in materials.values())
    h = s.size_um / s.refine_factor
    contact = ct.Contact(
        "outer_surface",
        pipette.obstacle(),
        s.penalty_factor * e_max / h,
        s.friction,
        name="pipette",
    )
    where = seal_mask(pipette, s.seal_tol_um)
    rate = s.advance_um / s.duration_s
    fixed = [Prescribed("axis", 0), Prescribed("rear_cap", 1, lambda t: rate * t)]
    problem = Problem(
        body,
        fixed,
        [
            FollowerPressure(
                "outer_surface",
                _unused_pressure,
                where=where,
                name="suction",
                lagged=s.lagged_seal,
            )
        ],
        [contact],
        log=log,
        control=ReactionControl("suction", "rear_cap", 1),
    )
    fb = body.facet_basis("outer_surface")
    z_dofs = axial_dofs(body.ubasis)
    result = PassageResult(s, pipette, problem, MaterialPoints.on_surface(mesh))
    v0 = problem.volume(problem.x)

    def record(frame: Frame) -> None:
        u = body.displacement(frame.x)
        applied = -problem.control_value
        suction = axial_suction_force(fb, z_dofs, u, applied, problem.applied_masks[0])
        normal, friction, z_q, lam = _wall_split(problem, frame.t)
        wall = float(frame.obstacle_forces["pipette"][1])
        uv = body.vertex_displacement(frame.x)
        up = result.points.displacement(body.ubasis, u)
        w = centroid_advance(body, u)
        row = {
            "time_s": frame.t,
            "centroid_advance_um": w,
            "front_pole_um": float(uv[1, np.argmax(mesh.p[1])]),
            "suction_kPa": applied,
            "suction_force_nN": suction,
            "wall_force_nN": wall,
            "wall_normal_nN": normal,
            "wall_friction_nN": friction,
            "push_force_nN": wall - suction,
            "volume_change": frame.volume / v0 - 1.0,
            "max_contact_kPa": float(lam.max()) if lam.size else 0.0,
            "radial_inward_um": result.points.radial_inward(up).tolist(),
            "deformation_um": result.points.deformation(up, w).tolist(),
        }
        for key, value in row.items():
            result.history.setdefault(key, []).append(value)
        result.wall_profiles.append((z_q, lam))
        result.frames.append(frame)
        if on_frame is not None:
            on_frame(result, frame)

    times = np.linspace(s.duration_s / s.steps, s.duration_s, s.steps)
    # 1e-6 of the force scale: contact with friction converges only linearly near stick-slip
    # fronts, and 1e-6 is far below what the deformation figures resolve
    settings_newton = NewtonSettings(max_cutbacks=s.max_cutbacks, rtol=1e-6)
    try:
        solved = problem.solve(times, settings_newton, on_frame=record)
        result.steps = solved.steps
    except SolverError as exc:
        result.failure = str(exc)
    return result
