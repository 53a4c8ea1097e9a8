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
table is for the seed's cell, R/h = 70/15 (R/h within 15 % accepted; the effect is measured
in docs/afm.md). Cones are not covered: the FE cone is not verified (docs/fe.md).

A fit with the probe's own radius ``Rp`` (what a user enters) reads ``E_app`` over the
curvature factor of :func:`curvature_factor`; :func:`zona_modulus` undoes both. Units: um, kPa.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline, PchipInterpolator

from afm import bottom_effect
from afm.bottom_effect import CONE_MODELS, SPHERE_MODELS
from afm.models import get_model
from oocyte_fe.errors import InputError

TABLE = Path(__file__).parent / "data" / "shell_correction.csv"
"""The shipped shelled-oocyte table."""
TABLE_CELL_OVER_ZONA = 70.0 / 15.0
"""R/h of the table's cell (the seed's: R = 70 um, h = 15 um)."""
CELL_TOLERANCE = 0.15
"""Relative departure of R/h from the table's accepted (effect measured, docs/afm.md)."""


@dataclass(frozen=True)
class ShellTable:
    """The table on its grid: ``ratio[p][e]`` is the column (d/h nodes ``depth[p]``) of probe
    node ``probes[p]`` and E ratio node ``e_ratios[e]`` (ascending)."""

    probes: tuple[float, ...]
    e_ratios: tuple[float, ...]
    depth: tuple[np.ndarray, ...]
    ratio: tuple[tuple[np.ndarray, ...], ...]

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
    return ShellTable(probes, e_ratios, tuple(depth), tuple(ratio))


def _check(value: float, lo: float, hi: float, quantity: str, where: str) -> None:
    if not (math.isfinite(value) and lo * (1 - 1e-9) <= value <= hi * (1 + 1e-9)):
        raise InputError(where, quantity, f"within the table's range [{lo:g}, {hi:g}]", value)


def shell_ratio(
    depth_h: float, e_ratio: float, probe_h: float, where: str = "shell_correction"
) -> float:
    """``ratio`` of eq. (1): E_app / E_ZP at d/h, E_c/E_ZP and Rp/h (interpolated).

    Outside the table: :class:`InputError` naming the quantity and the range.
    """
    t = load_table()
    _check(probe_h, t.probes[0], t.probes[-1], "probe radius / ZP thickness (Rp/h)", where)
    _check(e_ratio, t.e_ratios[0], t.e_ratios[-1], "E_cytoplasm / E_ZP", where)
    _check(
        depth_h, 0.0, t.max_depth_h(probe_h), f"depth / ZP thickness at Rp/h = {probe_h:.3g}", where
    )
    use = [k for k, p in enumerate(t.probes) if t.depth[k][-1] >= depth_h * (1 - 1e-9)]
    log_e = np.log(t.e_ratios)
    at_probe = []
    for k in use:
        root = np.sqrt(t.depth[k])  # the ratio falls like sqrt(d) from 1 at d = 0
        col = [float(CubicSpline(root, c)(math.sqrt(depth_h))) for c in t.ratio[k]]
        at_probe.append(float(PchipInterpolator(log_e, col)(math.log(e_ratio))))
    if len(use) == 1:
        return at_probe[0]
    nodes = np.log([t.probes[k] for k in use])
    return float(PchipInterpolator(nodes, at_probe)(math.log(probe_h)))


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
    the :func:`curvature_factor`) for E_ZP by bisection in ln E_ZP (the cytoplasm's modulus
    given in kPa)."""
    _check(
        cell_um / zona_um / TABLE_CELL_OVER_ZONA,
        1 - CELL_TOLERANCE,
        1 + CELL_TOLERANCE,
        f"cell radius / ZP thickness relative to the table's {TABLE_CELL_OVER_ZONA:.4g}",
        where,
    )
    e_app = e_fit_kPa * curvature_factor(model, probe_um, cell_um, depth_um)
    d_h, p_h = depth_um / zona_um, probe_um / zona_um
    t = load_table()
    lo, hi = cytoplasm_kPa / t.e_ratios[-1], cytoplasm_kPa / t.e_ratios[0]  # E_ZP range

    def residual(e_zp: float) -> float:
        return e_zp * shell_ratio(d_h, cytoplasm_kPa / e_zp, p_h, where) - e_app

    if residual(lo) > 0 or residual(hi) < 0:
        raise InputError(
            where,
            "E_cytoplasm / E_ZP",
            f"within the table's range [{t.e_ratios[0]:g}, {t.e_ratios[-1]:g}] for the ZP modulus "
            f"that explains E = {e_app:.4g} kPa",
            f"no E_ZP in [{lo:.4g}, {hi:.4g}] kPa does",
        )
    a, b = math.log(lo), math.log(hi)
    for _ in range(60):
        m = 0.5 * (a + b)
        a, b = (m, b) if residual(math.exp(m)) < 0 else (a, m)
    return math.exp(0.5 * (a + b))


@dataclass(frozen=True)
class ShelledOocyte:
    """Option ``shelled_oocyte``: E_ZP from each sphere fit (:func:`zona_modulus`), for a ZP
    of ``zona_um`` over a cytoplasm of ``cytoplasm_kPa`` on a cell of radius ``cell_um``."""

    zona_um: float
    cytoplasm_kPa: float
    cell_um: float
    name: str = "shelled_oocyte"

    def check(
        self,
        model: str,
        geometry: dict[str, float],
        nu: float,
        depth_um: float | None,
        where: str,
        field: str,
    ) -> None:
        """Refuse what the table does not cover: a tip other than a sphere, nu other than
        0.5, an unbounded fit range, a depth, probe or cell outside the table."""
        if model not in ("hertz_sphere", "hertz_paraboloid"):
            raise InputError(
                where,
                f"{field}.type",
                "a spherical probe (model hertz_sphere or hertz_paraboloid): cones are not covered",
                model,
            )
        if nu != 0.5:
            raise InputError(where, "inputs.nu", f"0.5 with {field} (the table's layers)", nu)
        if depth_um is None:
            raise InputError(
                where, "inputs.max_indentation_um", f"a depth (the fit range) with {field}", None
            )
        t = load_table()
        probe_h = geometry["radius_um"] / self.zona_um
        _check(probe_h, t.probes[0], t.probes[-1], "probe radius / ZP thickness (Rp/h)", where)
        deepest = t.max_depth_h(probe_h) * self.zona_um
        if depth_um > deepest * (1 + 1e-9):
            raise InputError(
                where,
                "inputs.max_indentation_um",
                f"<= {deepest:.4g} um, the table's deepest for this probe and ZP",
                depth_um,
            )
        _check(
            self.cell_um / self.zona_um / TABLE_CELL_OVER_ZONA,
            1 - CELL_TOLERANCE,
            1 + CELL_TOLERANCE,
            "cell radius / ZP thickness over the table's 70/15",
            where,
        )

    def corrected(
        self, e_kPa: float, model: str, geometry: dict[str, float], depth_um: float
    ) -> float:
        """E_ZP [kPa] of a fit that read ``e_kPa`` to ``depth_um``."""
        return zona_modulus(
            e_kPa,
            depth_um,
            self.zona_um,
            self.cytoplasm_kPa,
            geometry["radius_um"],
            self.cell_um,
            model,
        )

    @property
    def text(self) -> str:
        return (
            f"shelled_oocyte: E_ZP from the FE table (afm/data/shell_correction.csv) for a "
            f"{self.zona_um:g} um ZP over a {self.cytoplasm_kPa:g} kPa cytoplasm, cell "
            f"radius {self.cell_um:g} um (curvature and shell)"
        )


@dataclass(frozen=True)
class BondedLayer:
    """Option ``dimitriadis_bonded`` (sphere) / ``garcia_bonded`` (cone): a layer of
    ``layer_um`` bonded to a rigid support (:mod:`afm.bottom_effect`)."""

    layer_um: float
    name: str = "dimitriadis_bonded"

    def check(
        self,
        model: str,
        geometry: dict[str, float],
        nu: float,
        depth_um: float | None,
        where: str,
        field: str,
    ) -> None:
        """Refuse a tip the formula is not for, nu other than 0.5, an unbounded or too deep
        fit range (d < h; Dimitriadis: sqrt(R d)/h <= 1, their stated range)."""
        models = CONE_MODELS if self.name == "garcia_bonded" else SPHERE_MODELS
        if model not in models:
            raise InputError(
                where, f"{field}.type", f"a tip model {' or '.join(models)} for {self.name}", model
            )
        if nu != 0.5:
            raise InputError(where, "inputs.nu", f"0.5 with {field} (nu = 0.5 coefficients)", nu)
        if depth_um is None:
            raise InputError(
                where, "inputs.max_indentation_um", f"a depth (the fit range) with {field}", None
            )
        limit = self.layer_um
        if model in SPHERE_MODELS:
            limit = min(limit, self.layer_um**2 / geometry["radius_um"])
        if depth_um > limit:
            raise InputError(
                where,
                "inputs.max_indentation_um",
                f"<= {limit:.4g} um (d < h and sqrt(R d)/h <= 1 for {self.name})",
                depth_um,
            )

    def corrected(
        self, e_kPa: float, model: str, geometry: dict[str, float], depth_um: float
    ) -> float:
        """E [kPa] of the layer from a half-space fit that read ``e_kPa`` to ``depth_um``."""
        return e_kPa / bottom_effect.fit_factor(model, geometry, depth_um, self.layer_um)

    @property
    def text(self) -> str:
        who = (
            "Garcia and Garcia 2018 (cone; not FE-checked)"
            if self.name == "garcia_bonded"
            else "Dimitriadis et al. 2002 (sphere)"
        )
        return f"{self.name}: a {self.layer_um:g} um layer bonded to a rigid support, {who}"


Correction = ShelledOocyte | BondedLayer
"""A correction option of :func:`afm.fit_files.fit_files`."""
