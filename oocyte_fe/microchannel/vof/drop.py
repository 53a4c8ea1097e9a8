"""A two-phase Newtonian drop in simple shear on the VOF solver, for verification (2-D).

A circular drop of radius a and viscosity ``lambda mu`` sits at the centre of a planar box
``[-L, L] x [-H, H]`` (um) filled with fluid of viscosity ``mu``; the walls y = +-H slide at
``+-G H`` (simple shear of rate G), x = +-L are periodic (cyclic), the interface has tension
sigma. Once steady, the Taylor deformation ``D = (L_d - B_d)/(L_d + B_d)`` is read from the
second moments of alpha (``D = (1 - r)/(1 + r)`` with r = minor/major, :func:`.post.shape_moments`).

**Small-deformation result in 2-D.** For a circular drop (a cylinder in 3-D) in creeping simple
shear, to first order in ``Ca = mu G a / sigma``::

    D = Ca          for every viscosity ratio lambda

(re-derived here: with the planar strain ``E = G/2`` and stream functions ``f(r) sin 2 theta``,
outside ``E r^2/2 + C + D/r^2``, inside ``A r^2 + B r^4``, the kinematic, velocity and shear-stress
conditions on r = a give ``B a^2 = E/(2 (1 + lambda))`` and a normal-stress jump ``6 mu E cos 2
theta``, independent of lambda, which the curvature change ``3 eps sigma/a cos 2 theta`` of
``r = a (1 + eps cos 2 theta)`` balances: ``D = eps = 2 mu E a/sigma = Ca``; the same result,
``D = g(lambda) Ca`` with ``g = 1``, is derived and checked numerically in arXiv:2508.13022).
Taylor's 3-D ``D = Ca (19 lambda + 16)/(16 lambda + 16)`` (Taylor 1932, 1934) is for a sphere and
does not apply to a planar drop. The walls confine the drop (``a/H``) and raise D above Ca; the
box here keeps that below a few per cent (docs/microchannel.md).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.casewriter import (
    UM,
    Disk,
    Numerics,
    Phase,
    VofSetup,
    control_dict,
    phases_text,
    schemes,
    solution,
)
from oocyte_fe.microchannel.vof.foamfile import read_internal_field, write_dictionary, write_field
from oocyte_fe.microchannel.vof.geometry import Block, Layout
from oocyte_fe.microchannel.vof.monitor import SolverMonitor
from oocyte_fe.microchannel.vof.post import shape_moments, time_directories
from oocyte_fe.microchannel.vof.runner import OpenFoam, run_solver, run_utility

SURFACE_TENSION_SI = 1e-3  # nN/um -> N/m


@dataclass(frozen=True)
class ShearDrop:
    """The drop in shear: radius (um), box half-sizes (um), grid dx (um), shear rate G (1/s),
    outer viscosity (Newtonian, kPa s), viscosity ratio, density (nN s^2/um^4), tension (nN/um)."""

    radius: float
    half_length: float
    half_height: float
    dx: float
    shear_rate: float
    viscosity: float
    viscosity_ratio: float
    density: float
    surface_tension: float

    @property
    def capillary_number(self) -> float:
        """``Ca = mu G a / sigma`` (kPa s x 1/s x um / (nN/um): dimensionless)."""
        return self.viscosity * self.shear_rate * self.radius / self.surface_tension

    @property
    def reynolds_number(self) -> float:
        """``Re = rho G a^2 / mu``."""
        return self.density * self.shear_rate * self.radius**2 / self.viscosity

    def layout(self) -> Layout:
        """One block of square cells; no inlets (the box is closed by walls and cyclics)."""
        nx = round(2 * self.half_length / self.dx)
        ny = round(2 * self.half_height / self.dx)
        block = Block(
            -self.half_length, self.half_length, -self.half_height, self.half_height, nx, ny
        )
        return Layout(self.dx, [block], {}, (0, "xmax"))

    def setup(self, numerics: Numerics) -> VofSetup:
        """Phases ``matrix`` (background) and ``drop`` with the drop's disk at the centre."""
        mu = self.viscosity
        phases = (
            Phase("matrix", Rheology.of("newtonian", mu=mu), self.density),
            Phase("drop", Rheology.of("newtonian", mu=self.viscosity_ratio * mu), self.density),
        )
        tension = replace(numerics, surface_tension=self.surface_tension * SURFACE_TENSION_SI)
        return VofSetup(self.layout(), phases, (Disk("drop", (0.0, 0.0), self.radius),), tension)


def shear_box_mesh_dict(layout: Layout) -> dict:
    """``blockMeshDict`` of the one-block box: ``top``/``bottom`` walls, ``left``/``right`` a
    cyclic pair, ``frontAndBack`` empty."""
    entries = layout.block_mesh_dict()
    _, [lab] = layout.vertices()

    def face(*k: int) -> str:
        return "(" + " ".join(str(lab[i]) for i in k) + ")"

    patches = {
        "bottom": ("wall", face(0, 1, 5, 4), ""),
        "top": ("wall", face(3, 7, 6, 2), ""),
        "left": ("cyclic", face(0, 4, 7, 3), "neighbourPatch right;"),
        "right": ("cyclic", face(1, 2, 6, 5), "neighbourPatch left;"),
        "frontAndBack": ("empty", f"{face(0, 3, 2, 1)} {face(4, 5, 6, 7)}", ""),
    }
    text = [
        f"    {name} {{ type {kind}; {extra} faces ({faces}); }}"
        for name, (kind, faces, extra) in patches.items()
    ]
    return {**entries, "boundary": "(\n" + "\n".join(text) + "\n)"}


def write_shear_case(drop: ShearDrop, numerics: Numerics, directory: Path) -> VofSetup:
    """Write the drop-in-shear case into ``directory``; return its setup."""
    d = Path(directory)
    setup = drop.setup(numerics)
    layout, num = setup.layout, setup.numerics
    write_dictionary(d / "system" / "blockMeshDict", shear_box_mesh_dict(layout))
    write_dictionary(d / "system" / "controlDict", control_dict(num))
    write_dictionary(d / "system" / "fvSchemes", schemes())
    pimple = solution(num)
    pimple["PIMPLE"] |= {"pRefCell": 0, "pRefValue": 0}  # no outlet: fix the pressure level
    write_dictionary(d / "system" / "fvSolution", pimple)
    write_dictionary(
        d / "constant" / "g",
        {"dimensions": "[0 1 -2 0 0 0 0]", "value": "(0 0 0)"},
        "uniformDimensionedVectorField",
    )
    write_dictionary(d / "constant" / "turbulenceProperties", {"simulationType": "laminar"})
    write_dictionary(
        d / "constant" / "transportProperties",
        {
            "phases": phases_text(setup.phases),
            "sigmas": f"(\n(matrix drop) {num.surface_tension:.10g}\n)",
        },
    )
    cyclic = {"left": {"type": "cyclic"}, "right": {"type": "cyclic"}}
    empty = {"frontAndBack": {"type": "empty"}}
    wall_speed = drop.shear_rate * drop.half_height * UM  # m/s
    u0 = np.zeros((layout.n_cells, 3))
    u0[:, 0] = drop.shear_rate * layout.cell_centres()[:, 1] * UM
    write_field(
        d / "0" / "U",
        "[0 1 -1 0 0 0 0]",
        u0,
        {
            "top": {"type": "fixedValue", "value": f"uniform ({wall_speed:.10g} 0 0)"},
            "bottom": {"type": "fixedValue", "value": f"uniform ({-wall_speed:.10g} 0 0)"},
            **cyclic,
            **empty,
        },
    )
    walls = {n: {"type": "fixedFluxPressure", "value": "uniform 0"} for n in ("top", "bottom")}
    write_field(d / "0" / "p_rgh", "[1 -1 -2 0 0 0 0]", "uniform 0", {**walls, **cyclic, **empty})
    zero_gradient = {n: {"type": "zeroGradient"} for n in ("top", "bottom")}
    for name, values in [*setup.alpha().items(), ("alphas", None)]:
        write_field(
            d / "0" / (name if values is None else f"alpha.{name}"),
            "[0 0 0 0 0 0 0]",
            "uniform 0" if values is None else values,
            {**zero_gradient, **cyclic, **empty},
        )
    (d / "case.foam").write_text("")
    return setup


@dataclass(frozen=True)
class DropResult:
    """Taylor deformation D(t) of the drop and the drop area error at the end."""

    time: np.ndarray  # s
    deformation: np.ndarray
    area_error: float
    steps: int

    @property
    def steady_deformation(self) -> float:
        return float(self.deformation[-1])

    @property
    def last_change(self) -> float:
        """|D(t_end) - D(t_prev)| / D(t_end): how steady the last write is."""
        return float(abs(self.deformation[-1] - self.deformation[-2]) / self.deformation[-1])


def run_shear_drop(
    foam: OpenFoam, drop: ShearDrop, numerics: Numerics, directory: Path, nice: int = 0
) -> DropResult:
    """Write, mesh and run the drop in shear; D from each written time."""
    setup = write_shear_case(drop, numerics, directory)
    layout = setup.layout
    run_utility(foam, Path(directory), ["blockMesh"], nice)
    wall_speed = drop.shear_rate * drop.half_height * UM
    monitor = SolverMonitor(numerics.end_time, numerics.time_step, drop.dx * UM, wall_speed)
    run_solver(foam, Path(directory), monitor, nice=nice)
    times, deformation, areas = [], [], []
    for t, folder in time_directories(Path(directory)):
        alpha = read_internal_field(folder / "alpha.drop", layout.n_cells)
        _, ratio = shape_moments(layout.cell_centres(), alpha)
        times.append(t)
        deformation.append((1.0 - ratio) / (1.0 + ratio))
        areas.append(float(alpha.sum()))
    return DropResult(
        np.array(times), np.array(deformation), areas[-1] / areas[0] - 1.0, monitor.steps
    )
