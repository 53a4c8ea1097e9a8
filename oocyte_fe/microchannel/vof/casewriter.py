"""Writing a complete ``multiphaseInterFoam`` or ``interIsoFoam`` case (OpenFOAM v1912).

The solver advances, for N immiscible phases with volume fractions alpha_i (sum 1), one
velocity and one pressure for the mixture::

    d(alpha_i)/dt + div(U alpha_i) + div(U_r alpha_i (1 - alpha_i)) = 0     (MULES, compression)
    d(rho U)/dt + div(rho U U) = -grad p + div(rho nu (grad U + grad U^T)) + f_sigma
    div U = 0,       rho = sum alpha_i rho_i,      rho nu = sum alpha_i rho_i nu_i(gamma)

with each phase's kinematic viscosity from its own model (:mod:`.rheology`). Gravity is zero
(a horizontal device). Internal units (um, s, kPa s, nN s^2/um^4) are converted to SI here,
at the file boundary. The initial volume fractions are sampled per cell from the disks of the
cell and its cytoplasm (:func:`.geometry.disk_fraction`); the velocity starts at the fully
developed profile of each arm (inlet A's upstream, their sum downstream, B's in the branch), so
the first pressure solve only repairs the junction; cells of the non-background phases start
in rigid translation at their mean velocity. With ``Numerics.solver = "interIsoFoam"`` the
case has two phases (medium, cell) and the alpha equation is isoAdvector's geometric
advection instead of MULES (:mod:`.isoadvector`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.foamfile import field_values, write_dictionary, write_field
from oocyte_fe.microchannel.vof.geometry import Layout, disk_fraction, polygon_fraction
from oocyte_fe.microchannel.vof.isoadvector import (
    INTER_ISO_FOAM,
    MULTIPHASE,
    IsoControls,
    alpha_controls,
    check_solver,
    two_phase_transport,
)
from oocyte_fe.microchannel.vof.rheology import foam_viscosity

UM = 1e-6  # um -> m
_DENSITY_SI = 1e15  # nN s^2/um^4 -> kg/m^3


@dataclass(frozen=True)
class Phase:
    """A phase: name (OpenFOAM's ``alpha.<name>``), viscosity model, density (nN s^2/um^4)."""

    name: str
    rheology: Rheology
    density: float


@dataclass(frozen=True)
class Disk:
    """A region of one phase at t = 0: centre and radius (um); later disks overwrite earlier."""

    phase: str
    centre: tuple[float, float]
    radius: float

    def fraction(self, centres: np.ndarray, dx: float) -> np.ndarray:
        return disk_fraction(centres, dx, self.centre, self.radius)


@dataclass(frozen=True)
class Outline:
    """A region of one phase at t = 0 bounded by a closed polygon (k, 2) in um (e.g. the
    deformed outline of the elastic cell), used like a :class:`Disk`."""

    phase: str
    points: np.ndarray

    def fraction(self, centres: np.ndarray, dx: float) -> np.ndarray:
        return polygon_fraction(centres, dx, self.points)


@dataclass(frozen=True)
class Numerics:
    """Time stepping and PIMPLE controls (see docs/microchannel.md, VOF numerics)."""

    time_step: float = 1e-6  # s
    end_time: float = 1e-4  # s
    write_interval: float = 2e-5  # s
    adjustable: bool = False
    max_courant: float = 0.3
    outer_correctors: int = 1
    correctors: int = 3
    alpha_subcycles: int = 1
    compression: float = 1.0
    surface_tension: float = 0.0  # N/m, every pair
    momentum_predictor: bool = False
    ddt: str = "Euler"  # fvSchemes ddtSchemes default, e.g. "CrankNicolson 0.9"
    pressure_rel_tol: float = 0.0  # p_rgh relTol of the correctors before the last
    solver: str = MULTIPHASE  # or "interIsoFoam" (two phases, isoAdvector)
    iso: IsoControls = IsoControls()  # interIsoFoam's alpha controls
    moments: tuple[str, ...] = ()  # phases whose shape moments are recorded every step


@dataclass(frozen=True)
class VofSetup:
    """Everything the case needs: the mesh layout, phases (first = background), disks."""

    layout: Layout
    phases: tuple[Phase, ...]
    disks: tuple[Disk | Outline, ...]
    numerics: Numerics

    def alpha(self) -> dict[str, np.ndarray]:
        """Initial volume fractions per phase (sum 1 in every cell)."""
        centres = self.layout.cell_centres()
        alpha = {p.name: np.zeros(len(centres)) for p in self.phases}
        alpha[self.phases[0].name][:] = 1.0
        for disk in self.disks:
            f = disk.fraction(centres, self.layout.dx)
            for name in alpha:
                alpha[name] *= 1.0 - f
            alpha[disk.phase] += f
        return alpha


def phases_text(phases: tuple[Phase, ...]) -> str:
    """The ``phases`` list of ``transportProperties``: each phase's viscosity model, rho."""
    lines = ["("]
    for p in phases:
        visc = foam_viscosity(p.rheology, p.density)
        lines.append(f"    {p.name}\n    {{\n        transportModel {visc.model};")
        if visc.model == "Newtonian":
            lines.append(f"        nu {visc.coeffs['nu']:.10g};")
        else:
            body = " ".join(f"{k} {v:.10g};" for k, v in visc.coeffs.items())
            lines.append(f"        {visc.model}Coeffs {{ {body} }}")
        lines.append(f"        rho {p.density * _DENSITY_SI:.10g};\n    }}")
    lines.append(")")
    return "\n".join(lines)


def initial_velocity(layout: Layout) -> np.ndarray:
    """(n_cells, 3) developed profiles (um/s): each arm carries what flows through it."""
    centres = layout.cell_centres()
    u = np.zeros((len(centres), 3))
    inflow = sum(i.velocity * _width(layout, i.block, i.side) for i in layout.inlets.values())
    start = 0
    for index, b in enumerate(layout.blocks):
        stop = start + b.nx * b.ny
        x, y = centres[start:stop, 0], centres[start:stop, 1]
        fed = [i for i in layout.inlets.values() if i.block == index]
        along_x = fed[0].side.startswith("x") if fed else True
        if fed:
            flow = fed[0].velocity * _width(layout, index, fed[0].side)
            sign = 1.0 if fed[0].side in ("xmin", "ymin") else -1.0
        else:
            upstream = [i for i in layout.inlets.values() if i.side == "xmin"]
            through = index == layout.outlet[0]
            flow = inflow if through else upstream[0].velocity * (b.y1 - b.y0) if upstream else 0.0
            sign = 1.0
        lo, hi = (b.y0, b.y1) if along_x else (b.x0, b.x1)
        s = ((y if along_x else x) - 0.5 * (lo + hi)) / (0.5 * (hi - lo))
        speed = sign * 1.5 * flow / (hi - lo) * (1.0 - s**2)
        u[start:stop, 0 if along_x else 1] = speed
        start = stop
    return u


def _width(layout: Layout, block: int, side: str) -> float:
    _, a, b = layout.blocks[block].side_span(side)
    return b - a


def write_case(setup: VofSetup, directory: Path, ranks: int = 1) -> Path:
    """Write the OpenFOAM case into ``directory`` (created); return it."""
    d = Path(directory)
    layout, num = setup.layout, setup.numerics
    write_dictionary(d / "system" / "blockMeshDict", layout.block_mesh_dict())
    write_dictionary(d / "system" / "controlDict", control_dict(num))
    write_dictionary(d / "system" / "fvSchemes", schemes(num.ddt))
    write_dictionary(d / "system" / "fvSolution", solution(num))
    write_dictionary(
        d / "system" / "decomposeParDict",
        {"numberOfSubdomains": ranks, "method": "simple", "coeffs": {"n": f"({ranks} 1 1)"}},
    )
    write_dictionary(
        d / "constant" / "g",
        {"dimensions": "[0 1 -2 0 0 0 0]", "value": "(0 0 0)"},
        "uniformDimensionedVectorField",
    )
    write_dictionary(d / "constant" / "turbulenceProperties", {"simulationType": "laminar"})
    names = [p.name for p in setup.phases]
    two_phase = check_solver(num.solver) == INTER_ISO_FOAM
    if two_phase:
        transport = two_phase_transport(setup.phases, num.surface_tension)
    else:
        sigmas = [
            f"({a} {b}) {num.surface_tension:.10g}"
            for i, a in enumerate(names)
            for b in names[i + 1 :]
        ]
        transport = {
            "phases": phases_text(setup.phases),
            "sigmas": "(\n" + "\n".join(sigmas) + "\n)",
        }
    write_dictionary(d / "constant" / "transportProperties", transport)
    inlets = list(layout.inlets)
    outlet = layout.outlet_name
    empty = {"frontAndBack": {"type": "empty"}}
    velocity = {
        n: {"type": "fixedValue", "value": field_values(layout.inlet_velocity(n) * UM)}
        for n in inlets
    }
    alpha = setup.alpha()
    u0 = initial_velocity(layout)
    inside = alpha[setup.phases[0].name] < 0.5  # the cell starts in rigid translation
    if inside.any():
        u0[inside] = u0[inside].mean(axis=0)
    write_field(
        d / "0" / "U",
        "[0 1 -1 0 0 0 0]",
        u0 * UM,
        {**velocity, outlet: {"type": "zeroGradient"}, "walls": {"type": "noSlip"}, **empty},
    )
    flux = {"type": "fixedFluxPressure", "value": "uniform 0"}
    write_field(
        d / "0" / "p_rgh",
        "[1 -1 -2 0 0 0 0]",
        "uniform 0",
        {
            **{n: flux for n in inlets},
            outlet: {"type": "fixedValue", "value": "uniform 0"},
            "walls": flux,
            **empty,
        },
    )
    for name, values in alpha.items():
        if two_phase and name == names[0]:
            continue  # interIsoFoam solves the cell's fraction; the medium's is 1 - alpha
        inflow = {
            n: {"type": "fixedValue", "value": f"uniform {float(layout.inlets[n].phase == name):g}"}
            for n in inlets
        }
        out = {
            "type": "inletOutlet",
            "inletValue": f"uniform {float(name == names[0]):g}",
            "value": f"uniform {float(name == names[0]):g}",
        }
        write_field(
            d / "0" / f"alpha.{name}",
            "[0 0 0 0 0 0 0]",
            values,
            {**inflow, outlet: out, "walls": {"type": "zeroGradient"}, **empty},
        )
    if num.moments:
        write_moment_fields(d, layout, [*inlets, outlet])
    if two_phase:
        (d / "case.foam").write_text("")
        return d
    write_field(
        d / "0" / "alphas",
        "[0 0 0 0 0 0 0]",
        "uniform 0",
        {**{n: {"type": "zeroGradient"} for n in [*inlets, outlet, "walls"]}, **empty},
    )
    (d / "case.foam").write_text("")  # ParaView opens the series through this file
    return d


MOMENT_FIELDS = ("mOne", "mX", "mY", "mXX", "mYY", "mXY")  # 1, x, y, x^2, y^2, xy (SI)


def write_moment_fields(d: Path, layout: Layout, patches: list[str]) -> None:
    """The static fields ``1, x, y, x^2, y^2, xy`` (m, m^2) of the cell centres, in ``0/``:
    their alpha-weighted volume integrals each step give the cell's shape moments
    (:func:`moment_functions`)."""
    x, y = (layout.cell_centres() * UM).T
    boundary = {n: {"type": "calculated", "value": "uniform 0"} for n in [*patches, "walls"]}
    boundary["frontAndBack"] = {"type": "empty"}
    values = (np.ones_like(x), x, y, x * x, y * y, x * y)
    for name, v in zip(MOMENT_FIELDS, values, strict=True):
        write_field(d / "0" / name, "[0 0 0 0 0 0 0]", v, boundary)


def moment_functions(phases: tuple[str, ...]) -> dict:
    """Function objects: load the moment fields once, and each step write
    ``sum_k alpha_k V_k f_k`` for f in :data:`MOMENT_FIELDS`, per phase, to
    ``postProcessing/moments_<phase>/0/volFieldValue.dat`` (read by :func:`.post.moment_trace`)."""
    lib = '("libfieldFunctionObjects.so")'
    out: dict = {
        "loadMoments": {"type": "readFields", "libs": lib, "fields": f"({' '.join(MOMENT_FIELDS)})"}
    }
    for phase in phases:
        out[f"moments_{phase}"] = {
            "type": "volFieldValue",
            "libs": lib,
            "fields": f"({' '.join(MOMENT_FIELDS)})",
            "operation": "weightedVolIntegrate",
            "weightField": f"alpha.{phase}",
            "regionType": "all",
            "writeFields": "false",
            "writeControl": "timeStep",
            "writeInterval": 1,
            "log": "false",
        }
    return out


def control_dict(num: Numerics) -> dict:
    """``system/controlDict``: fixed or adaptive step, ASCII writes, |U| logged each step."""
    return {
        "application": num.solver,
        "startFrom": "startTime",
        "startTime": 0,
        "stopAt": "endTime",
        "endTime": num.end_time,
        "deltaT": num.time_step,
        "writeControl": "adjustableRunTime" if num.adjustable else "runTime",
        "writeInterval": num.write_interval,
        "purgeWrite": 0,
        "writeFormat": "ascii",
        "writePrecision": 10,
        "writeCompression": "off",
        "timeFormat": "general",
        "timePrecision": 10,
        "runTimeModifiable": "false",
        "adjustTimeStep": "yes" if num.adjustable else "no",
        "maxCo": num.max_courant,
        "maxAlphaCo": num.max_courant,
        "maxDeltaT": num.time_step,
        "functions": {
            "speed": {
                "type": "fieldMinMax",
                "libs": '("libfieldFunctionObjects.so")',
                "fields": "(U)",
                "mode": "magnitude",
                "log": "true",
                "writeToFile": "false",
            },
            **(moment_functions(num.moments) if num.moments else {}),
        },
    }


def schemes(ddt: str = "Euler") -> dict:
    """``system/fvSchemes``: ``ddt`` (Euler), vanLeer alpha, linearUpwind U (docs, VOF numerics)."""
    return {
        "ddtSchemes": {"default": ddt},
        "gradSchemes": {"default": "Gauss linear"},
        "divSchemes": {
            "div(rhoPhi,U)": "Gauss linearUpwind grad(U)",
            "div(phi,alpha)": "Gauss vanLeer",
            "div(phirb,alpha)": "Gauss linear",
            "div(((rho*nuEff)*dev2(T(grad(U)))))": "Gauss linear",
        },
        "laplacianSchemes": {"default": "Gauss linear corrected"},
        "interpolationSchemes": {"default": "linear"},
        "snGradSchemes": {"default": "corrected"},
    }


def solution(num: Numerics) -> dict:
    """``system/fvSolution``: GAMG pressure, PIMPLE correctors from ``num``; the alpha
    controls of MULES (sub-cycles, cAlpha) or of isoAdvector
    (:func:`.isoadvector.alpha_controls`)."""
    gamg = {"solver": "GAMG", "smoother": "GaussSeidel", "tolerance": 1e-8, "relTol": 0.01}
    alpha = (
        alpha_controls(num.iso, num.alpha_subcycles)
        if num.solver == INTER_ISO_FOAM
        else {"nAlphaSubCycles": num.alpha_subcycles, "cAlpha": num.compression}
    )
    return {
        "solvers": {
            '"alpha.*"': alpha,
            '"pcorr.*"': {**gamg, "tolerance": 1e-6, "relTol": 0},
            "p_rgh": {**gamg, "relTol": num.pressure_rel_tol},
            "p_rghFinal": {**gamg, "relTol": 0},
            "U": {
                "solver": "smoothSolver",
                "smoother": "symGaussSeidel",
                "tolerance": 1e-9,
                "relTol": 0.01,
            },
            "UFinal": {
                "solver": "smoothSolver",
                "smoother": "symGaussSeidel",
                "tolerance": 1e-9,
                "relTol": 0,
            },
        },
        "PIMPLE": {
            "momentumPredictor": "yes" if num.momentum_predictor else "no",
            "nOuterCorrectors": num.outer_correctors,
            "nCorrectors": num.correctors,
            "nNonOrthogonalCorrectors": 0,
        },
        "relaxationFactors": {"equations": {'".*"': 1}},
    }
