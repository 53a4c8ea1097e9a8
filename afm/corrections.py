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
by about 1/3 of a relative change of R/h: +2.6 to +4.8 % at R/h = 4.0, docs/afm.md). Cones
are not covered: the FE cone is not verified (docs/fe.md).

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
from oocyte_fe.errors import InputError

TABLE = Path(__file__).parent / "data" / "shell_correction.csv"
"""The shipped shelled-oocyte table."""
TABLE_CELL_OVER_ZONA = 70.0 / 15.0
"""R/h of the table's cell (the seed's: R = 70 um, h = 15 um)."""
CELL_TOLERANCE = 0.03
"""Relative departure of R/h from the table's accepted: the ratio moves by about a third of
it (measured at R = 60 um: +2.6 to +4.8 %), so about 1 % at the edge (docs/afm.md)."""


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
    if depth_um <= 0:  # the small-depth limit: paraboloids, sqrt(Rp / R*)
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
    check_range(
        cell_um / zona_um / TABLE_CELL_OVER_ZONA,
        1 - CELL_TOLERANCE,
        1 + CELL_TOLERANCE,
        f"cell radius / ZP thickness relative to the table's {TABLE_CELL_OVER_ZONA:.4g}",
        where,
    )
    e_app = e_fit_kPa * curvature_factor(model, probe_um, cell_um, depth_um)
    t, ratio = _checked_profile(depth_um / zona_um, probe_um / zona_um, where)
    lo, hi = cytoplasm_kPa / t.e_ratios[-1], cytoplasm_kPa / t.e_ratios[0]  # E_ZP range

    def residual(e_zp: float) -> float:
        return e_zp * ratio(min(max(cytoplasm_kPa / e_zp, t.e_ratios[0]), t.e_ratios[-1])) - e_app

    if residual(lo) > 0 or residual(hi) < 0:
        raise InputError(
            where,
            "E_cytoplasm / E_ZP",
            f"within the table's range [{t.e_ratios[0]:g}, {t.e_ratios[-1]:g}] for the ZP modulus "
            f"that explains E = {e_app:.4g} kPa",
            f"no E_ZP in [{lo:.4g}, {hi:.4g}] kPa does",
        )
    root = brentq(lambda x: residual(math.exp(x)), math.log(lo), math.log(hi), xtol=1e-13)
    return math.exp(root)
