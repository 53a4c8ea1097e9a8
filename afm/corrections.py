"""Moduli corrected for the sample's shape: the shelled oocyte (an FE table) and a layer bonded
to a rigid support (:mod:`afm.bottom_effect`), as options of a batch of fits.

Shelled oocyte, spherical probe (radius ``Rp``) on a cell of outer radius ``R`` with a ZP of
thickness ``h`` and modulus ``E_ZP`` over a cytoplasm ``E_c`` (bonded, nu = 0.5). A Hertz fit
(``hertz_sphere``) with the effective radius ``R* = Rp R / (Rp + R)``, from contact to the
depth ``d`` (points uniform in depth), reads

    E_app = E_ZP * ratio(d/h, E_c/E_ZP, Rp/h)                                       (1)

``ratio`` is the table ``afm/data/shell_correction.csv`` made by the project's FE
(``python -m oocyte_fe.afm_corrections.table``; its header names the grid and the
code). ``ratio = 1`` for ``E_c = E_ZP`` and at ``d -> 0``. Interpolation: a cubic spline in
sqrt(d/h) along each FE curve (nodes every 0.025 h; the ratio falls like sqrt(d) from 1),
then monotone cubic (PCHIP) in ln(E_c/E_ZP) and in ln(Rp/h); it passes through the nodes. The
table is for the seed's cell, R/h = 70/15; R/h within 3 % of it is accepted (the ratio moves
by about 1/3 of a relative change of R/h: +2.6 to +4.8 % at R/h = 4.0, docs/afm.md).

Cones (:func:`cone_shell_ratio`, :func:`cone_zona_modulus`): a ``sneddon_cone`` fit to ``d``
reads ``E_app = E_ZP ratio_cone(y, E_c/E_ZP)``, ``y = d tan(alpha) / h``, from the table
``afm/data/shell_correction_cone.csv`` (``python -m oocyte_fe.afm_corrections.cone_table``, a
70 deg cone); in linear elasticity the ratio depends on y and E_c/E_ZP only, whatever the
angle (measured from 45 to 80 deg within 0.75 %).

A fit with the probe's own radius ``Rp`` (what a user enters) reads ``E_app`` over the
curvature factor of :func:`curvature_factor`; :func:`zona_modulus` undoes both. The options of
a batch of fits (this table; a bonded layer, :mod:`afm.bottom_effect`) are in
:mod:`afm.corrected_batch`. Units: um, kPa.
"""

from __future__ import annotations

import csv
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline, PchipInterpolator
from scipy.optimize import brentq

from afm.models import get_model
from oocyte_fe import checks
from oocyte_fe.errors import InputError

TABLE = Path(__file__).parent / "data" / "shell_correction.csv"
"""The shipped shelled-oocyte table."""
TABLE_CELL_OVER_ZONA = 70.0 / 15.0
"""R/h of the table's cell (the seed's: R = 70 um, h = 15 um)."""
CELL_TOLERANCE = 0.03
"""Relative departure of R/h from the table's accepted: the ratio moves by about a third of
it (measured at R = 60 um: +2.6 to +4.8 %), so about 1 % at the edge (docs/afm.md)."""


KINDS = {
    "e_fit_kPa": "modulus_kPa",
    "cytoplasm_kPa": "modulus_kPa",
    "zona_um": "length_um",
    "probe_um": "length_um",
    "cell_um": "length_um",
    "half_angle_deg": "cone_half_angle_deg",
}
"""The physical quantity of each argument of the corrections (``oocyte_fe.checks``)."""


def _checked(where: str, **values: object) -> dict[str, float]:
    """Every argument a real, finite number within its quantity's bounds (a depth >= 0)."""
    out = {}
    for name, value in values.items():
        if name == "depth_um":
            out[name] = checks.number(where, name, value, ge=0.0, le=1e6)
        elif name in KINDS:
            out[name] = checks.quantity(where, name, value, KINDS[name])
        else:
            out[name] = checks.number(where, name, value)
    return out


@dataclass(frozen=True)
class ShellTable:
    """The table on its grid: ``ratio[p][e]`` is the column (d/h nodes ``depth[p]``) of probe
    node ``probes[p]`` and E ratio node ``e_ratios[e]`` (ascending)."""

    probes: tuple[float, ...]
    e_ratios: tuple[float, ...]
    depth: tuple[np.ndarray, ...]
    ratio: tuple[tuple[np.ndarray, ...], ...]
    splines: tuple[tuple[CubicSpline, ...], ...]
    """Cubic splines of each column in sqrt(d/h) (the ratio falls like sqrt(d) from 1)."""

    def max_depth_h(self, probe_h: float) -> float:
        """Deepest d/h tabulated for Rp/h = ``probe_h`` (that of the probe node below it)."""
        k = max(0, int(np.searchsorted(self.probes, probe_h * (1 + 1e-9), side="right")) - 1)
        return float(self.depth[k][-1])


@functools.lru_cache(maxsize=2)
def load_table(path: str | Path = TABLE) -> ShellTable:
    """The shelled-oocyte table of ``path`` (CSV: depth_h, e_ratio, probe_h, ratio, hom)."""
    with Path(path).open() as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    data = np.array(
        [[float(r[k]) for k in ("depth_h", "e_ratio", "probe_h", "ratio")] for r in rows]
    )
    probes = tuple(sorted(set(data[:, 2])))
    e_ratios = tuple(sorted(set(data[:, 1])))
    depth, ratio = [], []
    for p in probes:
        at_p = data[data[:, 2] == p]
        depth.append(np.unique(at_p[:, 0]))
        columns = []
        for e in e_ratios:
            col = at_p[at_p[:, 1] == e]
            columns.append(col[np.argsort(col[:, 0]), 3])
        ratio.append(tuple(columns))
    splines = tuple(
        tuple(CubicSpline(np.sqrt(d), c) for c in columns)
        for d, columns in zip(depth, ratio, strict=True)
    )
    return ShellTable(probes, e_ratios, tuple(depth), tuple(ratio), splines)


def check_range(value: float, lo: float, hi: float, quantity: str, where: str) -> None:
    if not (math.isfinite(value) and lo * (1 - 1e-9) <= value <= hi * (1 + 1e-9)):
        raise InputError(where, quantity, f"within the table's range [{lo:g}, {hi:g}]", value)


def check_cell(cell_um: float, zona_um: float, where: str) -> None:
    """The cell's R/h within :data:`CELL_TOLERANCE` of the tables' 70/15."""
    check_range(
        cell_um / zona_um / TABLE_CELL_OVER_ZONA,
        1 - CELL_TOLERANCE,
        1 + CELL_TOLERANCE,
        f"cell radius / ZP thickness relative to the table's {TABLE_CELL_OVER_ZONA:.4g}",
        where,
    )


def _at_depth(t: ShellTable, depth_h: float, probe_h: float) -> Callable[[float], float]:
    """``ratio`` as a function of E_c/E_ZP at fixed d/h and Rp/h (the interpolation of
    :func:`shell_ratio`; the spline in depth is made once)."""
    use = [k for k in range(len(t.probes)) if t.depth[k][-1] >= depth_h * (1 - 1e-9)]
    log_e = np.log(t.e_ratios)
    by_e = []
    for k in use:
        col = [float(spline(math.sqrt(depth_h))) for spline in t.splines[k]]
        by_e.append(PchipInterpolator(log_e, col))
    nodes = np.log([t.probes[k] for k in use])

    def ratio(e_ratio: float) -> float:
        at_probe = [float(f(math.log(e_ratio))) for f in by_e]
        if len(at_probe) == 1:
            return at_probe[0]
        return float(PchipInterpolator(nodes, at_probe)(math.log(probe_h)))

    return ratio


def _checked_profile(
    depth_h: float, probe_h: float, where: str
) -> tuple[ShellTable, Callable[[float], float]]:
    t = load_table()
    check_range(probe_h, t.probes[0], t.probes[-1], "probe radius / ZP thickness (Rp/h)", where)
    check_range(
        depth_h, 0.0, t.max_depth_h(probe_h), f"depth / ZP thickness at Rp/h = {probe_h:.3g}", where
    )
    return t, _at_depth(t, depth_h, probe_h)


def shell_ratio(
    depth_h: float, e_ratio: float, probe_h: float, where: str = "shell_correction"
) -> float:
    """``ratio`` of eq. (1): E_app / E_ZP at d/h, E_c/E_ZP and Rp/h (interpolated).

    Outside the table: :class:`InputError` naming the quantity and the range.
    """
    depth_h, e_ratio, probe_h = (
        checks.number(where, n, x)
        for n, x in (("depth_h", depth_h), ("e_ratio", e_ratio), ("probe_h", probe_h))
    )
    t, ratio = _checked_profile(depth_h, probe_h, where)
    check_range(e_ratio, t.e_ratios[0], t.e_ratios[-1], "E_cytoplasm / E_ZP", where)
    return ratio(e_ratio)


def effective_radius_um(probe_um: float, cell_um: float) -> float:
    """R* = Rp R / (Rp + R) [um]: a sphere of radius Rp on a sphere of radius R."""
    return probe_um * cell_um / (probe_um + cell_um)


def _shape(model: str, radius_um: float, depth_um: np.ndarray) -> np.ndarray:
    return get_model(model).shape(depth_um, {"radius_um": radius_um}, 0.5)


def curvature_factor(model: str, probe_um: float, cell_um: float, depth_um: float) -> float:
    """E_app(R*) / E_fit(Rp): a fit of ``model`` (hertz_sphere or hertz_paraboloid) with the
    probe's radius to a curve that follows ``hertz_sphere`` with R*, from contact to
    ``depth_um`` (points uniform in depth): ``int s_Rp^2 / int s_R* s_Rp`` [1]."""
    v = _checked("curvature_factor", probe_um=probe_um, cell_um=cell_um, depth_um=depth_um)
    probe_um, cell_um, depth_um = v["probe_um"], v["cell_um"], v["depth_um"]
    if depth_um <= 1e-6 * probe_um:  # the small-depth limit (to O(d/Rp)): sqrt(Rp / R*)
        return math.sqrt(probe_um / effective_radius_um(probe_um, cell_um))
    x = np.linspace(0.0, depth_um, 2001)
    s_user = _shape(model, probe_um, x)
    s_cell = _shape("hertz_sphere", effective_radius_um(probe_um, cell_um), x)
    return float(np.trapezoid(s_user**2, x) / np.trapezoid(s_cell * s_user, x))


def zona_modulus(
    e_fit_kPa: float,
    depth_um: float,
    zona_um: float,
    cytoplasm_kPa: float,
    probe_um: float,
    cell_um: float,
    model: str = "hertz_sphere",
    where: str = "shell_correction",
) -> float:
    """E_ZP [kPa] from the modulus ``e_fit_kPa`` a Hertz ``model`` fit with the probe's radius
    read to ``depth_um``: solves ``E_fit c = E_ZP ratio(d/h, E_c/E_ZP, Rp/h)`` (eq. 1, ``c``
    the :func:`curvature_factor`) for E_ZP by Brent's method in ln E_ZP (the cytoplasm's
    modulus given in kPa)."""
    v = _checked(
        where,
        e_fit_kPa=e_fit_kPa,
        depth_um=depth_um,
        zona_um=zona_um,
        cytoplasm_kPa=cytoplasm_kPa,
        probe_um=probe_um,
        cell_um=cell_um,
    )
    e_fit_kPa, depth_um, zona_um = v["e_fit_kPa"], v["depth_um"], v["zona_um"]
    cytoplasm_kPa, probe_um, cell_um = v["cytoplasm_kPa"], v["probe_um"], v["cell_um"]
    check_cell(cell_um, zona_um, where)
    e_app = e_fit_kPa * curvature_factor(model, probe_um, cell_um, depth_um)
    t, ratio = _checked_profile(depth_um / zona_um, probe_um / zona_um, where)
    return _solve_zona(e_app, cytoplasm_kPa, t.e_ratios, ratio, where)


def _solve_zona(
    e_app: float,
    cytoplasm_kPa: float,
    e_ratios: tuple[float, ...],
    ratio: Callable[[float], float],
    where: str,
) -> float:
    """E_ZP [kPa] with ``E_ZP ratio(E_c / E_ZP) = e_app`` (Brent in ln E_ZP, over the E_ZP
    the table's E ratios allow)."""
    lo, hi = cytoplasm_kPa / e_ratios[-1], cytoplasm_kPa / e_ratios[0]  # E_ZP range

    def residual(e_zp: float) -> float:
        return e_zp * ratio(min(max(cytoplasm_kPa / e_zp, e_ratios[0]), e_ratios[-1])) - e_app

    if residual(lo) > 0 or residual(hi) < 0:
        raise InputError(
            where,
            "E_cytoplasm / E_ZP",
            f"within the table's range [{e_ratios[0]:g}, {e_ratios[-1]:g}] for the ZP modulus "
            f"that explains E = {e_app:.4g} kPa",
            f"no E_ZP in [{lo:.4g}, {hi:.4g}] kPa does",
        )
    root = brentq(lambda x: residual(math.exp(x)), math.log(lo), math.log(hi), xtol=1e-13)
    return math.exp(root)


CONE_TABLE = Path(__file__).parent / "data" / "shell_correction_cone.csv"
"""The shipped shelled-oocyte table for cones (``oocyte_fe.afm_corrections.cone_table``)."""
CONE_CURVATURE_GAP = 0.01
"""Largest ``a tan(alpha) / (2 R)`` accepted for a cone: the cell's extra gap at the contact
edge over the cone's. The table's ratio divides the curvature out to first order; what is
left, the homogeneous curved cell reading low, is about 0.8 of this gap (measured at 70 deg,
docs/afm.md), so about 0.8 % at the bound."""


SHARP_CONE_DEG = 45.0
"""Cones sharper than this are outside what the FE verifies (docs/fe.md); for them the table
rests on the linear-elastic angle invariance and is accepted to y = :data:`SHARP_CONE_MAX_Y`
only (a 30 deg FE run, itself not verified, departs from the table by at most 0.75 % there
and by 2 % at y = 0.2; docs/afm.md)."""
SHARP_CONE_MAX_Y = 0.1


def cone_max_y(half_angle_deg: float) -> float:
    """Deepest y = d tan(alpha)/h accepted for a cone of ``half_angle_deg``."""
    deepest = float(load_cone_table().y[-1])
    return deepest if half_angle_deg >= SHARP_CONE_DEG else min(deepest, SHARP_CONE_MAX_Y)


@dataclass(frozen=True)
class ConeTable:
    """The cone table: ``ratio[e]`` at the y nodes ``y`` for E ratio node ``e_ratios[e]``."""

    y: np.ndarray
    e_ratios: tuple[float, ...]
    ratio: tuple[np.ndarray, ...]
    splines: tuple[CubicSpline, ...]
    """Cubic splines of each column in y (the ratio falls like y = pi a / (2 h) from 1)."""


@functools.lru_cache(maxsize=2)
def load_cone_table(path: str | Path = CONE_TABLE) -> ConeTable:
    """The cone table of ``path`` (CSV: y, e_ratio, ratio, hom)."""
    with Path(path).open() as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    data = np.array([[float(r[k]) for k in ("y", "e_ratio", "ratio")] for r in rows])
    e_ratios = tuple(sorted(set(data[:, 1])))
    y = np.unique(data[:, 0])
    columns = []
    for e in e_ratios:
        col = data[data[:, 1] == e]
        columns.append(col[np.argsort(col[:, 0]), 2])
    splines = tuple(CubicSpline(y, c) for c in columns)
    return ConeTable(y, e_ratios, tuple(columns), splines)


def cone_shell_ratio(y: float, e_ratio: float, where: str = "shell_correction") -> float:
    """E_app / E_ZP of a ``sneddon_cone`` fit from contact to ``y = d tan(alpha) / h`` on the
    shelled oocyte with E_c / E_ZP = ``e_ratio`` (any half angle: in linear elasticity the
    ratio depends on y and E_c/E_ZP only; measured within 0.75 % from 45 to 80 deg)."""
    y, e_ratio = checks.number(where, "y", y), checks.number(where, "e_ratio", e_ratio)
    t = load_cone_table()
    check_range(y, 0.0, float(t.y[-1]), "depth tan(half angle) / ZP thickness (y)", where)
    check_range(e_ratio, t.e_ratios[0], t.e_ratios[-1], "E_cytoplasm / E_ZP", where)
    return _cone_at(t, y)(e_ratio)


def _cone_at(t: ConeTable, y: float) -> Callable[[float], float]:
    by_e = PchipInterpolator(np.log(t.e_ratios), [float(s(y)) for s in t.splines])
    return lambda e_ratio: float(by_e(math.log(e_ratio)))


def cone_curvature_gap(depth_um: float, half_angle_deg: float, cell_um: float) -> float:
    """``a tan(alpha) / (2 R)`` with Sneddon's contact radius ``a = 2 d tan(alpha) / pi``: the
    cell's extra gap at the contact edge over the cone's own [1]."""
    v = _checked("cone_curvature_gap", depth_um=depth_um, half_angle_deg=half_angle_deg)
    depth_um, half_angle_deg = v["depth_um"], v["half_angle_deg"]
    cell_um = checks.quantity("cone_curvature_gap", "cell_um", cell_um, "length_um")
    tan = math.tan(math.radians(half_angle_deg))
    return 2.0 / math.pi * depth_um * tan * tan / (2.0 * cell_um)


def cone_zona_modulus(
    e_fit_kPa: float,
    depth_um: float,
    half_angle_deg: float,
    zona_um: float,
    cytoplasm_kPa: float,
    cell_um: float,
    where: str = "shell_correction",
) -> float:
    """E_ZP [kPa] from the modulus ``e_fit_kPa`` a ``sneddon_cone`` fit read to ``depth_um``:
    solves ``E_fit = E_ZP ratio(y, E_c/E_ZP)`` (:func:`cone_shell_ratio`) by Brent's method
    in ln E_ZP. Refused: R/h off the table's by more than 3 %, or a cone so blunt for its
    depth that the cell's curvature matters (:data:`CONE_CURVATURE_GAP`)."""
    v = _checked(
        where,
        e_fit_kPa=e_fit_kPa,
        depth_um=depth_um,
        half_angle_deg=half_angle_deg,
        zona_um=zona_um,
        cytoplasm_kPa=cytoplasm_kPa,
        cell_um=cell_um,
    )
    e_fit_kPa, depth_um, half_angle_deg = v["e_fit_kPa"], v["depth_um"], v["half_angle_deg"]
    zona_um, cytoplasm_kPa, cell_um = v["zona_um"], v["cytoplasm_kPa"], v["cell_um"]
    check_cell(cell_um, zona_um, where)
    check_range(
        cone_curvature_gap(depth_um, half_angle_deg, cell_um),
        0.0,
        CONE_CURVATURE_GAP,
        "the cell's curvature gap at the contact edge, a tan(half angle) / (2 R)",
        where,
    )
    t = load_cone_table()
    y = depth_um * math.tan(math.radians(half_angle_deg)) / zona_um
    check_range(
        y,
        0.0,
        cone_max_y(half_angle_deg),
        f"depth tan(half angle) / ZP thickness (y) for a {half_angle_deg:g} deg cone",
        where,
    )
    ratio = _cone_at(t, y)
    return _solve_zona(e_fit_kPa, cytoplasm_kPa, t.e_ratios, ratio, where)
