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

import functools
import logging
from dataclasses import dataclass

import numpy as np
import skfem
from pydantic import ValidationError

from oocyte_fe.crosscheck.scenario import PressScenario
from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.cache import cached_arrays_all
from oocyte_fe.experiment.description import inline_table
from oocyte_fe.experiment.driver import cell_mesh
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.experiment.tools import obstacle
from oocyte_fe.fe.fields import stress_fields
from oocyte_fe.fe.obstacles import Polyline, wedge_tip
from oocyte_fe.runner.casefile import raise_validation_error

PIPETTE = "pipette"
HELD = "held"
"""Tool names of the press experiment (the holder's facets are the boundary ``hold:held``)."""


@dataclass(frozen=True)
class FeSettings:
    """Mesh and stepping of the FE press (um).

    ``size_um``: element size away from the contact; ``refine_size_um``: size within
    ``refine_depth_um`` of the outer arcs within ``refine_half_window_deg`` of 3 o'clock (the
    window is mirrored to 9 o'clock, where the holder sits); ``step_um``: pipette advance per
    output frame; ``max_step_um``: largest solver step; ``penalty_factor``: ``eps_N h / E_max``;
    ``rtol``: Newton tolerance on the relative residual (contact chatter: docs/cases/nmsd_vs_fe.md);
    ``contact_smoothing_um``: the C1 smoothing of the normal contact law (it stops the chatter
    of a point at the wedge corner that switched in and out of contact at 60.8 um);
    ``contact_quadrature_order``: the Gauss order of the contact on each surface facet (at the
    body's order 4, three points per facet, the wedge's mouth corner pressed between two of
    them, folded the ZP facet round it and stopped the press on 3 of 5 meshes of the case's
    sizes; at 20 it converged on every mesh of 0.71-1.2 times the case's sizes tried:
    docs/cases/nmsd_vs_fe.md, FE notes); ``edge_radius_um``: the wedge's two mouth edges
    rounded with this radius (0: sharp; a sharp edge catches the ZP's surface facets, whose
    path then differs from mesh to mesh: docs/cases/nmsd_vs_fe.md, "The mouth's edges").
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
    contact_quadrature_order: int = 20
    edge_radius_um: float = 0.0
    source: str = "FeSettings"

    def __post_init__(self) -> None:
        for name in ("size_um", "refine_size_um", "refine_depth_um", "step_um", "max_step_um"):
            if not getattr(self, name) > 0:
                raise InputError(self.source, name, "> 0 um", getattr(self, name))
        if not 0 < self.refine_half_window_deg < 90:
            raise InputError(
                self.source, "refine_half_window_deg", "in (0, 90) deg", self.refine_half_window_deg
            )
        if not self.edge_radius_um >= 0:
            raise InputError(self.source, "edge_radius_um", ">= 0 um", self.edge_radius_um)
        if not self.contact_smoothing_um >= 0:
            raise InputError(
                self.source, "contact_smoothing_um", ">= 0 um", self.contact_smoothing_um
            )
        if not 0 < self.rtol < 1e-2:
            raise InputError(self.source, "rtol", "in (0, 0.01)", self.rtol)
        if not self.penalty_factor > 0:
            raise InputError(self.source, "penalty_factor", "> 0", self.penalty_factor)
        if not 2 <= self.contact_quadrature_order <= 40:
            raise InputError(
                self.source, "contact_quadrature_order", "in [2, 40]", self.contact_quadrature_order
            )


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


def pipette_at(
    scenario: PressScenario, advance_um: float, length_um: float = 80.0, edge_radius_um: float = 0.0
) -> Polyline:
    """The wedge pipette after ``advance_um`` of travel (mouth at x = R - advance)."""
    return wedge_tip(
        (scenario.radius_um - advance_um, 0.0),
        (-1.0, 0.0),
        scenario.pipette_width_um,
        scenario.tip_angle_deg,
        length_um,
        edge_radius_um,
    )


def press_experiment(
    scenario: PressScenario,
    materials: LayerMaterials,
    settings: FeSettings,
    travel_um: float,
    points_um: np.ndarray,
) -> Experiment:
    """The press as an FE experiment: a wedge pipette on the right advancing ``travel_um`` at
    the scenario speed, a holding pipette on the left (the held rim, both components), one
    output frame every ``step_um``, the given points followed."""
    if not travel_um > 0:
        raise InputError(settings.source, "travel_um", "> 0", travel_um)
    v = scenario.speed_um_s
    n_out = output_frames(travel_um, settings.step_um)
    duration = travel_um / v
    description = {
        "description": "NMSD press scenario, plane strain",
        "cell": {
            "outer_diameter_um": 2.0 * scenario.radius_um,
            "zona_thickness_um": scenario.zona_thickness_um,
            "symmetry": "plane_strain",
            "mesh_size_um": settings.size_um,
            "refine_size_um": settings.refine_size_um,
            "refine_depth_um": settings.refine_depth_um,
            "refine_half_angle_deg": settings.refine_half_window_deg,
            "materials": {
                "zona": inline_table(materials.zona),
                "cytoplasm": inline_table(materials.cytoplasm),
            },
            "points": {f"p{i}": [float(x), float(y)] for i, (x, y) in enumerate(points_um)},
        },
        "tools": {
            PIPETTE: {
                "type": "wedge_pipette",
                "side": "right",
                "width_um": scenario.pipette_width_um,
                "tip_angle_deg": scenario.tip_angle_deg,
                "penalty_factor": settings.penalty_factor,
                "smoothing_um": settings.contact_smoothing_um,
                "quadrature_order": settings.contact_quadrature_order,
                "edge_radius_um": settings.edge_radius_um,
                "displacement_um": {"time_s": [0.0, duration], "value": [0.0, travel_um]},
            },
            HELD: {
                "type": "holding_pipette",
                "side": "left",
                "half_width_um": scenario.hold_half_width_um,
            },
        },
        "time": {
            "duration_s": duration,
            "frames": n_out,
            "at_path_knots": False,  # the press's frames are output_frames' (its arrows)
            # its figures (docs/cases/nmsd_vs_fe.md) were measured halving failed steps at
            # once; taken again from the last state its FE curve moves (3 of 9 cutbacks
            # saved) and the NMSD calibrated to it by up to 36 %: left as measured
            "retry_from_last_state": False,
            "max_step_s": settings.max_step_um / v,
            "rtol": settings.rtol,
        },
    }
    try:
        return Experiment.model_validate(description)
    except ValidationError as err:  # a setting the kind's rules let through: one line
        raise_validation_error(settings.source, err, prefix="FE press experiment: ")


def _solve(exp: Experiment, log: logging.Logger | None) -> dict[str, np.ndarray]:
    """The press's arrays (and its cost) from one run of the experiment driver."""
    result = run_experiment(exp, log=log)
    if not result.success:
        raise SolverError(result.reason, result)
    problem = result.problem
    penalty = problem.contacts[0][0].law.penalty
    frames = result.frames
    return {
        "force_nN_per_um": result.force_nN[PIPETTE][:, 0],
        "point_displacement_um": np.stack([result.tracks_um[n] for n in exp.cell.points], 1),
        "vertex_displacement_um": np.array([problem.body.vertex_displacement(f.x) for f in frames]),
        "vertex_pressure_kPa": np.array(  # the rest state, then -tr(sigma)/3 of each frame
            [np.zeros(problem.body.mesh.nvertices)]
            + [-stress_fields(problem, f.x)["mean_stress"] for f in frames[1:]]
        ),
        "penetration_um": np.array(
            [float(f.contact_pressure[PIPETTE].max()) / penalty for f in frames]
        ),
        "counts": np.array([len(result.steps), result.cutbacks, result.newton_iterations]),
        "seconds": np.array(result.seconds),
    }


def run_fe_press(
    scenario: PressScenario,
    materials: LayerMaterials,
    settings: FeSettings,
    travel_um: float,
    points_um: np.ndarray,
    log: logging.Logger | None = None,
) -> FePress:
    """Press the FE disc ``travel_um`` at the scenario speed through the one experiment
    driver (:func:`~oocyte_fe.experiment.run_experiment`); record every ``step_um``.

    The result is cached by its inputs (:mod:`oocyte_fe.experiment.cache`): a second case with
    the same FE inputs reads it instead of solving again (``seconds`` is the solve's own)."""
    return run_fe_presses([scenario], materials, settings, travel_um, points_um, log)[0]


def run_fe_presses(
    scenarios: list[PressScenario],
    materials: LayerMaterials,
    settings: FeSettings,
    travel_um: float,
    points_um: np.ndarray,
    log: logging.Logger | None = None,
) -> list[FePress]:
    """:func:`run_fe_press` of each scenario (speeds, say); presses another process is solving
    are read after this one has solved the others (:func:`cached_arrays_all`)."""
    exps = [press_experiment(s, materials, settings, travel_um, points_um) for s in scenarios]
    found = cached_arrays_all([(exp, "press", functools.partial(_solve, exp, log)) for exp in exps])
    presses = []
    for exp, (arrays, hit) in zip(exps, found, strict=True):
        if hit and log is not None:
            log.info("FE press read from the cache (equal FE inputs solved before)")
        presses.append(_press(exp, arrays, travel_um, points_um))
    return presses


def output_frames(travel_um: float, step_um: float) -> int:
    """Output frames of a press of ``travel_um``: one every ``step_um`` (the last frame at the
    travel's end, so the frames are ``travel_um / n`` apart), at least one. A ratio within a
    relative 1e-6 above a whole number is that number: a step written to fit the travel (62.5 /
    2.5) keeps its 25 frames when either is off by round-off (an absolute 1e-9 gave 26 frames,
    2.4 um apart, for a relative 1e-9 on both)."""
    ratio = travel_um / step_um
    return max(1, int(np.ceil(ratio * (1.0 - 1e-6))))


def _press(
    exp: Experiment, arrays: dict[str, np.ndarray], travel_um: float, points_um: np.ndarray
) -> FePress:
    """The :class:`FePress` of ``exp`` from its stored arrays."""
    steps, cutbacks, iterations = (int(n) for n in arrays["counts"])
    return FePress(
        mesh=cell_mesh(exp),
        pipette=obstacle(exp.tools[PIPETTE], PIPETTE, exp.cell.radius_um, axisym=False),
        advance_um=np.linspace(0.0, travel_um, exp.time.frames + 1),
        force_nN_per_um=arrays["force_nN_per_um"],
        points_um=np.asarray(points_um, dtype=float),
        point_displacement_um=arrays["point_displacement_um"],
        vertex_displacement_um=arrays["vertex_displacement_um"],
        vertex_pressure_kPa=arrays["vertex_pressure_kPa"],
        penetration_um=arrays["penetration_um"],
        steps=steps,
        cutbacks=cutbacks,
        newton_iterations=iterations,
        seconds=float(arrays["seconds"]),
    )
