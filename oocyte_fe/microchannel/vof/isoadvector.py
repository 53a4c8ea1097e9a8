"""The two-phase geometric-VOF path: ``interIsoFoam`` (isoAdvector, OpenFOAM v1912).

The cell is ONE phase (its own viscosity curve) in the medium; one volume fraction alpha of
the cell, advected geometrically: in each step isoAdvector cuts every interface cell by the
alpha isosurface and moves, across each face, the volume of the cell phase that the face's
sub-step motion of that isoface sweeps (Roenby, Bredmose & Jasak 2016)::

    alpha_P(t + dt) = alpha_P(t) - 1/V_P sum_f  integral_t^{t+dt} alpha_f(tau) phi_f dtau

no interface compression and no flux limiter; ``nAlphaBounds`` passes of a local bounding
redistribute any over/undershoot, ``clip`` then clips alpha to [0, 1] and ``snapTol`` snaps
alpha within that of 0 or 1. The momentum equation is the mixture's, as in
:mod:`.casewriter` (rho = alpha rho_cell + (1 - alpha) rho_medium, the same for rho nu).

The alpha controls (:class:`IsoControls`) default to those of v1912's ``interIsoFoam``
``damBreak`` tutorial. The field OpenFOAM reads is ``alpha.<cell phase>``; the medium's
fraction is ``1 - alpha`` and is not written.
"""

from __future__ import annotations

from dataclasses import dataclass

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.vof.rheology import foam_viscosity

INTER_ISO_FOAM = "interIsoFoam"
MULTIPHASE = "multiphaseInterFoam"
SOLVERS = (MULTIPHASE, INTER_ISO_FOAM)
LIQUID_CELL = "liquid_cell_isoadvector"  # the cell as one liquid, interIsoFoam
THREE_PHASE = "three_phase_mules"  # medium, ZP, cytoplasm, multiphaseInterFoam (the seed)
MODEL_SOLVER = {LIQUID_CELL: INTER_ISO_FOAM, THREE_PHASE: MULTIPHASE}
_DENSITY_SI = 1e15  # nN s^2/um^4 -> kg/m^3


@dataclass(frozen=True)
class IsoControls:
    """isoAdvector's alpha controls (the ``damBreak`` tutorial's values, module docstring)."""

    iso_face_tol: float = 1e-6
    surf_cell_tol: float = 1e-6
    n_alpha_bounds: int = 3
    snap_tol: float = 1e-12
    clip: bool = True


def alpha_controls(iso: IsoControls, subcycles: int) -> dict:
    """The ``solvers { "alpha.<cell>.*" }`` entry of ``fvSolution`` for ``interIsoFoam``."""
    return {
        "isoFaceTol": iso.iso_face_tol,
        "surfCellTol": iso.surf_cell_tol,
        "nAlphaBounds": iso.n_alpha_bounds,
        "snapTol": iso.snap_tol,
        "clip": iso.clip,
        "nAlphaCorr": 1,
        "nAlphaSubCycles": subcycles,
        "cAlpha": 1,
    }


def two_phase_transport(phases: tuple, surface_tension: float) -> dict:
    """``constant/transportProperties`` of ``interIsoFoam`` for (medium, cell): the phase list
    names the cell first (its alpha is the one solved), each phase's ``transportModel`` and
    rho (SI); one surface tension sigma (N/m)."""
    if len(phases) != 2:
        raise InputError(
            "VOF case", "phases", f"two phases (medium, cell) for {INTER_ISO_FOAM}", len(phases)
        )
    medium, cell = phases
    entries: dict = {"phases": f"({cell.name} {medium.name})"}
    for p in (cell, medium):
        visc = foam_viscosity(p.rheology, p.density)
        body: dict = {"transportModel": visc.model}
        if visc.model == "Newtonian":
            body["nu"] = visc.coeffs["nu"]
        else:
            body[f"{visc.model}Coeffs"] = dict(visc.coeffs)
        body["rho"] = p.density * _DENSITY_SI
        entries[p.name] = body
    entries["sigma"] = float(surface_tension)
    return entries


def check_solver(solver: str) -> str:
    """``solver`` when it is one the case writer knows, else :class:`InputError`."""
    if solver not in SOLVERS:
        raise InputError("VOF case", "solver", " or ".join(SOLVERS), solver)
    return solver
