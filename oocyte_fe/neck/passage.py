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
from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.description import inline_table
from oocyte_fe.fe import contact as ct
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.material import Material
from oocyte_fe.fe.solver import Frame, Problem, StepLog
from oocyte_fe.neck.periphery import MaterialPoints
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.neck.suction import axial_dofs, axial_suction_force

PIPETTE = "pipette"
CAP = "rear_cap"
"""Tool names of the passage experiment (the cap's facets are the boundary ``hold:rear_cap``)."""


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


def passage_experiment(
    materials: dict[str, Material],
    settings: PassageSettings,
    pipette: NeckedPipette | None = None,
    cytoplasm_radius_um: float = 75.0,
    zona_um: float = 15.0,
) -> Experiment:
    """The passage as an FE experiment: a necked pipette above the cell, a rear cap of
    ``cap_deg`` (held axially) advancing ``advance_um`` in ``duration_s``, the suction the
    unknown that keeps the cap's net axial push at zero; refined along the side (20-160 deg)."""
    s = settings
    pip = pipette or NeckedPipette()
    refine = s.refine_factor > 1
    cell = {
        "outer_diameter_um": 2.0 * (cytoplasm_radius_um + zona_um),
        "zona_thickness_um": zona_um,
        "mesh_size_um": s.size_um,
        "curved_edges": False,  # straight-edged P2, as the passage was verified
        "materials": {name: inline_table(m) for name, m in materials.items()},
    }
    if refine:
        cell |= {
            "refine_size_um": s.size_um / s.refine_factor,
            "refine_depth_um": 20.0,
            "refine_windows_deg": [[20.0, 160.0]],
        }
    ramp = {"time_s": [0.0, s.duration_s], "value": [0.0, s.advance_um]}
    return Experiment.model_validate(
        {
            "description": "the oocyte through a necked pipette",
            "cell": cell,
            "tools": {
                PIPETTE: {
                    "type": "necked_pipette",
                    "bore_diameter_um": 2.0 * pip.bore_radius_um,
                    "neck_diameter_um": 2.0 * pip.neck_radius_um,
                    "taper_length_um": pip.taper_length_um,
                    "bore_length_um": pip.bore_length_um,
                    "neck_length_um": pip.neck_length_um,
                    "taper_points": pip.taper_points,
                    "clearance_um": s.clearance_um,
                    "seal_tol_um": s.seal_tol_um,
                    "friction": s.friction,
                    "penalty_factor": s.penalty_factor,
                    "suction_control": {"tool": CAP, "target_nN": 0.0},
                },
                CAP: {
                    "type": "holding_pipette",
                    "side": "bottom",
                    "cap_deg": s.cap_deg,
                    "components": "axial",
                    "displacement_um": ramp,
                },
            },
            # 1e-6 of the force scale: contact with friction converges only linearly near
            # stick-slip fronts, and 1e-6 is far below what the deformation figures resolve
            "time": {
                "duration_s": s.duration_s,
                "frames": s.steps,
                "rtol": 1e-6,
                "max_iterations": 20,
                "max_cutbacks": s.max_cutbacks,
            },
        }
    )


def run_passage(
    materials: dict[str, Material],
    settings: PassageSettings,
    pipette: NeckedPipette | None = None,
    cytoplasm_radius_um: float = 75.0,
    zona_um: float = 15.0,
    log: logging.Logger | None = None,
    on_frame: Callable[[PassageResult, Frame], None] | None = None,
) -> PassageResult:
    """Solve one passage through the one experiment driver
    (:func:`~oocyte_fe.experiment.run_experiment`); a driver that finds no equilibrium ends
    it early (``failure``)."""
    s = settings
    exp = passage_experiment(materials, s, pipette, cytoplasm_radius_um, zona_um)
    radius = cytoplasm_radius_um + zona_um
    placed = (pipette or NeckedPipette()).touching(radius, s.clearance_um)
    state: dict = {}

    def record(problem: Problem, frame: Frame) -> None:
        if not state:
            body = problem.body
            state.update(
                result=PassageResult(s, placed, problem, MaterialPoints.on_surface(body.mesh)),
                fb=body.facet_basis("outer_surface"),
                z_dofs=axial_dofs(body.ubasis),
                v0=problem.volume(np.zeros(body.n_dofs)),
            )
        result, body = state["result"], problem.body
        u = body.displacement(frame.x)
        applied = -problem.control_value
        suction = axial_suction_force(
            state["fb"], state["z_dofs"], u, applied, problem.applied_masks[0]
        )
        normal, friction, z_q, lam = _wall_split(problem, frame.t)
        wall = float(frame.obstacle_forces[PIPETTE][1])
        uv = body.vertex_displacement(frame.x)
        up = result.points.displacement(body.ubasis, u)
        w = centroid_advance(body, u)
        row = {
            "time_s": frame.t,
            "centroid_advance_um": w,
            "front_pole_um": float(uv[1, np.argmax(body.mesh.p[1])]),
            "suction_kPa": applied,
            "suction_force_nN": suction,
            "wall_force_nN": wall,
            "wall_normal_nN": normal,
            "wall_friction_nN": friction,
            "push_force_nN": wall - suction,
            "volume_change": frame.volume / state["v0"] - 1.0,
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

    solved = run_experiment(exp, log=log, on_frame=record)
    result = state.get("result") or PassageResult(
        s, placed, solved.problem, MaterialPoints.on_surface(solved.problem.body.mesh)
    )
    result.steps = list(solved.steps)
    result.failure = solved.reason
    return result
