"""What an experiment's curves say against the closed forms a lab would use.

For the first tool of each type (the metrics of kind ``fe_experiment``):

* suction pipette: the slope ``s = sum(dP L) / sum(dP^2)`` of the aspiration-length change
  against suction over the frames with ``L <= 0.25 a`` (the small-strain part), the effective
  wall factor of a homogeneous cell ``Phi = 2 pi E s / (3 a)`` (Theret: 2.0-2.1), and the
  modulus a user infers with Theret's formula, ``E_app = 3 Phi a / (2 pi s)``, ``Phi = 2.1``;
* cone and sphere: the FE force over Sneddon's cone / the sphere (Hertz's problem solved
  exactly for a sphere by Sneddon, ``afm``'s ``hertz_sphere``, with the effective radius
  ``Rp R / (Rp + R)``) at the deepest frame, with the modulus of the outer layer, and the
  modulus that the same ``afm`` model fits to the FE curve (linear least squares in E over
  the loading frames);
* plates (each pressing by its advance ``d``): the force over Hertz (sphere on a rigid flat,
  radius R) at the first frame, and the force at the last;
* surface loads (a flow's traction, a pressure): the deformed section's aspect ratio ``b/a``
  at the last frame, ``a`` and ``b`` the outline's extents along the principal axes of its
  area moment (plane strain; axisymmetric: the equatorial diameter and the axial height,
  ``a >= b``), and the deformation ``1 - b/a``;
* every region: its smallest principal stretch ``lambda_min = sqrt(min eig(F^T F))`` over the
  quadrature points (how far the FE's answer reaches into compression; the instantaneous AFM
  moduli are measured at small strain).

Forces are the compressive (approach-direction) component on the tool [nN; plane strain: nN
per um of thickness], depths its advance beyond the clearance [um], pressures kPa.

What is compared (:func:`closed_form_notes` says it in the report):

* the closed forms are evaluated at the deepest frame (the first frame of the largest advance)
  and fitted over the loading segment only (frames up to it; for the pipette, up to the first
  frame of the largest suction), so a retract or a hold after the ramp does not enter;
* they are elastic: with a Prony series they are taken with the instantaneous modulus
  ``E_kPa`` of the outer layer on the loading ramp (the relaxation during a slow ramp lowers
  the apparent modulus; the hold is not used);
* they are 3-D (axisymmetric) results: in plane strain (a force per um of thickness) the
  Theret, Sneddon, Hertz metrics are withheld;
* a cone's or sphere's advance is its indentation only where the cell is held: with more than
  one tool pressing a cell that nothing holds (no holding pipette, no fixed seal) the cell
  moves as a whole and the per-probe metrics are withheld.
"""

from __future__ import annotations

import numpy as np

from afm import get_model
from oocyte_fe.experiment import tools as tl
from oocyte_fe.experiment.description import (
    Cone,
    HoldingPipette,
    Plate,
    Sphere,
    StraightPipette,
    ToolBase,
)
from oocyte_fe.experiment.driver import ExperimentResult
from oocyte_fe.experiment.outline import body_outline_um
from oocyte_fe.verification import THERET_PHI, hertz_force_nN, theret_length_um

SMALL_STRAIN = 0.25
"""Largest ``L / a`` used for the Theret slope."""


PLANE_STRAIN_NOTE = (
    "Plane strain: forces are per um of thickness (nN/um); the closed forms of Theret, "
    "Sneddon and Hertz are 3-D (axisymmetric) results, so their metrics are withheld."
)
FREE_PROBES_NOTE = (
    "Several tools press a cell that nothing holds (no holding pipette, no fixed seal): the cell "
    "moves as a whole, so a tool's advance is not its indentation and the cone/sphere metrics "
    "are withheld."
)
VISCOELASTIC_NOTE = (
    "Viscoelastic layers (a Prony series): the closed forms are elastic ones taken with the "
    "instantaneous modulus E_kPa of the outer layer, fitted on the loading ramp only (frames "
    "up to the deepest advance or the largest suction); the hold is not used."
)


def plane_strain(result: ExperimentResult) -> bool:
    """Whether the section is plane strain (forces per um of thickness)."""
    return result.experiment.cell.symmetry == "plane_strain"


def force_unit(result: ExperimentResult) -> str:
    """The unit of a force on a tool or of a load's resultant: ``nN``, plane strain ``nN/um``."""
    return "nN/um" if plane_strain(result) else "nN"


def free_probes(result: ExperimentResult) -> bool:
    """More than one tool presses the cell and nothing holds it (no holding pipette, no
    pipette with a fixed seal): the cell moves as a whole, advance is not indentation."""
    tools = result.experiment.tools.values()
    held = any(
        isinstance(t, HoldingPipette) or (isinstance(t, StraightPipette) and t.seal == "fixed")
        for t in tools
    )
    pressing = [t for t in tools if isinstance(t, ToolBase) and t.displacement_um is not None]
    return len(pressing) > 1 and not held


def viscoelastic(result: ExperimentResult) -> bool:
    """Whether any layer has a Prony series."""
    return any(r.material.prony.g for r in result.problem.body.regions)


def closed_form_notes(result: ExperimentResult) -> list[str]:
    """The sentences the report gives on which closed-form metrics are withheld and why."""
    notes = []
    if plane_strain(result):
        notes.append(PLANE_STRAIN_NOTE)
    elif free_probes(result) and (_first(result, Cone) or _first(result, Sphere)):
        notes.append(FREE_PROBES_NOTE)
    notes += theret_range_notes(result)
    compared_tools = [n for n, t in result.experiment.tools.items() if _closed_form_tool(t)]
    if viscoelastic(result) and any(compared(result, n) for n in compared_tools):
        notes.append(VISCOELASTIC_NOTE)
    return notes


THERET_A_OVER_R = 0.2
"""Largest pipette radius / cell radius where the FE gives Theret's factor within 3 %
(docs/fe.md, "Micropipette aspiration"; 1.86 at a/R = 0.5)."""


def theret_range_notes(result: ExperimentResult) -> list[str]:
    """Sentences for the first suction pipette where Theret's half-space formula is read
    outside its setting: a/R above :data:`THERET_A_OVER_R`, a compressible outer layer
    (nu < 0.5), the seal ``contact`` (not Theret's punch)."""
    name = _first(result, StraightPipette)
    if name is None or name not in result.suction_kPa or plane_strain(result):
        return []
    tool, cell = result.experiment.tools[name], result.experiment.cell
    outside = []
    a_over_r = tool.inner_radius_um / cell.radius_um
    if a_over_r > THERET_A_OVER_R:
        outside.append(
            f"a/R = {a_over_r:.3g} above {THERET_A_OVER_R:g} (the FE's Phi falls with a/R: "
            "1.94 at 0.4, 1.86 at 0.5)"
        )
    nu = outer_layer_modulus(result)[1]
    if nu < 0.5:
        outside.append(f"nu = {nu:g} (Theret: incompressible)")
    if getattr(tool, "seal", "fixed") == "contact":
        outside.append("seal 'contact' (Theret's punch is the seal 'fixed'; not a result yet)")
    if not outside:
        return []
    return [
        f"Theret's formula (theret_phi, theret_modulus_kPa) is read outside the setting where "
        f"the FE reproduces it within 3 % (docs/fe.md): {'; '.join(outside)}."
    ]


def _closed_form_tool(tool) -> bool:
    """Whether a closed-form metric exists for ``tool``'s type."""
    return isinstance(tool, Cone | Sphere | Plate | StraightPipette)


def compared(result: ExperimentResult, name: str) -> bool:
    """Whether tool ``name``'s force is compared with its 3-D closed form (not in plane
    strain, nor a cone or sphere on a free cell pressed by several tools)."""
    if plane_strain(result):
        return False
    probe = isinstance(result.experiment.tools[name], Cone | Sphere)
    return not (probe and free_probes(result))


def loading_end(values: np.ndarray) -> int:
    """The end of the loading segment: the first frame where ``values`` (an advance or a
    suction) reach their largest value."""
    return int(np.argmax(values))


def push_force_nN(result: ExperimentResult, name: str) -> np.ndarray:
    """Compressive force on tool ``name`` along its approach direction [nN] per frame."""
    d = tl.approach(result.experiment.tools[name].side)
    return -result.force_nN[name] @ d


def depth_um(result: ExperimentResult, name: str) -> np.ndarray:
    """Advance of tool ``name`` beyond its clearance [um] (0 before contact)."""
    tool = result.experiment.tools[name]
    return np.maximum(result.advance_um[name] - tool.gap_um, 0.0)


def outer_layer_modulus(result: ExperimentResult) -> tuple[float, float]:
    """(E [kPa], nu) of the layer the tools touch: the ZP, or the cytoplasm without one."""
    layers = {r.name: r.material for r in result.problem.body.regions}
    m = layers.get("zona", layers["cytoplasm"])
    return m.E_kPa, m.nu


def _first(result: ExperimentResult, kind: type) -> str | None:
    return next((n for n, t in result.experiment.tools.items() if isinstance(t, kind)), None)


def _model_of(result: ExperimentResult, name: str) -> tuple[str, dict[str, float]]:
    """``afm``'s model key and tip geometry for a cone or sphere tool (sphere: radius R*)."""
    tool, R = result.experiment.tools[name], result.experiment.cell.radius_um
    if isinstance(tool, Cone):
        return "sneddon_cone", {"half_angle_deg": tool.half_angle_deg}
    return "hertz_sphere", {"radius_um": tool.radius_um * R / (tool.radius_um + R)}


def closed_form_force_nN(result: ExperimentResult, name: str, depth: np.ndarray) -> np.ndarray:
    """The closed form a tool's force is compared with, at advances ``depth`` [um], with the
    outer layer's modulus: Sneddon's cone, Sneddon's exact sphere (radius R*), or Hertz for a
    plate (a sphere of radius R on a flat); NaN for other tools."""
    E, nu = outer_layer_modulus(result)
    tool = result.experiment.tools[name]
    if isinstance(tool, Cone | Sphere):
        model, geometry = _model_of(result, name)
        return E * get_model(model).shape(np.asarray(depth, dtype=float), geometry, nu)
    if isinstance(tool, Plate):
        return hertz_force_nN(E, nu, result.experiment.cell.radius_um, depth)
    return np.full(np.shape(depth), np.nan)


def theret_slope(result: ExperimentResult, name: str) -> float:
    """Least-squares slope of the aspiration change [um] against suction [kPa], L <= 0.25 a,
    over the loading segment (frames up to the first of the largest suction)."""
    a = result.experiment.tools[name].inner_radius_um
    k = loading_end(result.suction_kPa[name]) + 1
    p, L = result.suction_kPa[name][:k], result.aspiration_change_um[name][:k]
    use = (p > 0) & (L <= SMALL_STRAIN * a)
    if not use.any():
        use = p > 0
    return float(np.sum(p[use] * L[use]) / np.sum(p[use] ** 2))


def polygon_extents_um(x: np.ndarray) -> tuple[float, float]:
    """The extents [um] of a closed polygon ``x`` (2, n), ordered around it, along the
    principal axes of its area moment (shoelace sums), in the order of those axes."""
    xn, yn = np.roll(x[0], -1), np.roll(x[1], -1)
    cross = x[0] * yn - xn * x[1]
    area = cross.sum() / 2.0
    c = np.array([((x[0] + xn) * cross).sum(), ((x[1] + yn) * cross).sum()]) / (6.0 * area)
    d, dn = x - c[:, None], np.array([xn, yn]) - c[:, None]
    cr = d[0] * dn[1] - dn[0] * d[1]
    Ixx = ((d[1] ** 2 + d[1] * dn[1] + dn[1] ** 2) * cr).sum() / 12.0
    Iyy = ((d[0] ** 2 + d[0] * dn[0] + dn[0] ** 2) * cr).sum() / 12.0
    Ixy = ((d[0] * dn[1] + 2 * d[0] * d[1] + 2 * dn[0] * dn[1] + dn[0] * d[1]) * cr).sum() / 24
    _, axes = np.linalg.eigh(np.array([[Iyy, Ixy], [Ixy, Ixx]]))
    proj = axes.T @ d
    e = proj.max(axis=1) - proj.min(axis=1)
    return float(e[0]), float(e[1])


def outline_extents_um(result: ExperimentResult, frame: int = -1) -> tuple[float, float]:
    """(a, b) [um], a >= b: the deformed outline's extents along the principal axes of the
    section's area moment (plane strain), or its equatorial diameter and axial height
    (axisymmetric), at output ``frame``."""
    body = result.problem.body
    mesh = body.mesh
    vertices = np.unique(mesh.facets[:, mesh.boundaries["outer_surface"]])
    X = mesh.p[:, vertices]
    x = X + body.vertex_displacement(result.frames[frame].x)[:, vertices]
    if body.axisym:
        extents = [2.0 * x[0].max(), x[1].max() - x[1].min()]
    else:
        extents = list(polygon_extents_um(x[:, np.argsort(np.arctan2(X[1], X[0]))]))
    return max(extents), min(extents)


def smallest_stretch(result: ExperimentResult, frame: int = -1) -> dict[str, float]:
    """Each region's smallest principal stretch [-] at output ``frame``: the square root of
    the smallest eigenvalue of ``C = F^T F`` over its quadrature points (plane strain: the
    in-plane pair and ``F_zz = 1``; axisymmetric: with the hoop stretch ``F_zz = r / R``).
    A homogeneous plane-strain pure shear ``F = diag(lambda, 1 / lambda)`` gives
    ``1 / lambda``."""
    problem, x = result.problem, result.frames[frame].x
    out = {}
    for k, region in enumerate(problem.body.regions):
        F = problem.region_kinematics(x, k)[0].F  # (3, 3, nel, nqp)
        C = np.einsum("kiEq,kjEq->Eqij", F, F)
        out[region.name] = float(np.sqrt(np.linalg.eigvalsh(C)[..., 0].min()))
    return out


def section_outline_um(result: ExperimentResult, frame: int = -1) -> np.ndarray:
    """The deformed outline of the whole section (k, 2) [um] at output ``frame``, closed and
    ordered around it, at the outer surface's quadrature points (axisymmetric: the meridional
    half mirrored about the axis)."""
    return body_outline_um(result.problem.body, result.frames[frame].x)


def contour_deformation(result: ExperimentResult, frame: int = -1) -> tuple[float, float]:
    """(deformation, area [um^2]) of the section's outline, as real-time deformability
    cytometry defines them: ``d = 1 - 2 sqrt(pi A) / P`` (1 - circularity; ``A`` the area and
    ``P`` the perimeter of the outline polygon). The polygon's own defect (the same formula on
    the undeformed outline, O(1 / n^2) for n points) is subtracted."""

    def shape(x: np.ndarray) -> tuple[float, float]:
        xn = np.roll(x, -1, axis=0)
        area = 0.5 * abs(np.sum(x[:, 0] * xn[:, 1] - xn[:, 0] * x[:, 1]))
        perimeter = float(np.sum(np.hypot(*(xn - x).T)))
        return 1.0 - 2.0 * np.sqrt(np.pi * area) / perimeter, area

    d, area = shape(section_outline_um(result, frame))
    d0, _ = shape(section_outline_um(result, 0))
    return d - d0, area


def closed_form_metrics(result: ExperimentResult) -> dict[str, float]:
    """The metrics of the module docstring for the tools present (the 3-D closed forms
    withheld in plane strain, the cone/sphere ones on a free cell pressed by several tools)."""
    out: dict[str, float] = {}
    E, nu = outer_layer_modulus(result)
    homogeneous = result.experiment.cell.zona_thickness_um == 0
    three_d = not plane_strain(result)
    pipette = _first(result, StraightPipette)
    if three_d and pipette is not None and pipette in result.suction_kPa:
        a = result.experiment.tools[pipette].inner_radius_um
        s = theret_slope(result, pipette)
        out["theret_modulus_kPa"] = 3 * THERET_PHI * a / (2 * np.pi * s)
        if homogeneous:
            out["theret_phi"] = s / theret_length_um(1.0, a, E, 1.0)
    for kind, label in ((Cone, "cone"), (Sphere, "sphere")):
        name = _first(result, kind)
        if name is None or not compared(result, name):
            continue
        d, F = depth_um(result, name), push_force_nN(result, name)
        k = loading_end(d)
        out[f"{label}_force_ratio"] = float(
            F[k] / closed_form_force_nN(result, name, d[k : k + 1])[0]
        )
        model, geometry = _model_of(result, name)
        shape = get_model(model).shape(d[: k + 1], geometry, nu)
        out[f"{label}_fit_modulus_kPa"] = float(np.sum(F[: k + 1] * shape) / np.sum(shape**2))
    plate = _first(result, Plate)
    if plate is not None:
        d, F = depth_um(result, plate), push_force_nN(result, plate)
        if three_d:
            k = int(np.argmax(d > 0))
            out["plate_hertz_ratio"] = float(F[k] / closed_form_force_nN(result, plate, d[k]))
        out["plate_force_nN"] = float(F[-1])
    if result.experiment.loads:
        a, b = outline_extents_um(result)
        out["aspect_ratio"] = b / a
        out["deformation"] = 1.0 - b / a
    out["completed_fraction"] = float(result.times_s[-1] / result.experiment.time.duration_s)
    out["volume_change"] = float(np.max(np.abs(result.volume_change)))
    return out
