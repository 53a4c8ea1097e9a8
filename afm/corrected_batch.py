"""A batch of fits corrected for the sample's shape: the options (:class:`ShelledOocyte`, the
FE table of :mod:`afm.corrections`; :class:`BondedLayer`, :mod:`afm.bottom_effect`), each
checked against the tip, nu and fit range, the corrected modulus of every fitted curve and the
group statistics over them.

Each fitted row's E is corrected at the row's largest indentation; a fit the correction
refuses (e.g. deeper than the table) keeps its apparent E in ``fits.csv`` and carries the
reason instead of a corrected value. Statistics follow :meth:`afm.batch.BatchResult.stats`:
the fits rated good (poor ones with ``include_poor``), the rating being the apparent fit's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from afm import bottom_effect
from afm.batch import BatchResult, GroupStats
from afm.bottom_effect import CONE_MODELS, SPHERE_MODELS
from afm.corrections import (
    CELL_TOLERANCE,
    CONE_CURVATURE_GAP,
    TABLE_CELL_OVER_ZONA,
    check_range,
    cone_max_y,
    cone_zona_modulus,
    load_table,
    zona_modulus,
)
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class ShelledOocyte:
    """Option ``shelled_oocyte``: E_ZP from each sphere fit (:func:`zona_modulus`) or cone fit
    (:func:`cone_zona_modulus`), for a ZP of ``zona_um`` over a cytoplasm of ``cytoplasm_kPa``
    on a cell of radius ``cell_um``."""

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
        """Refuse what the tables do not cover: a tip other than a sphere or a cone, nu other
        than 0.5, an unbounded fit range, a depth, probe or cell outside the table, a cone
        so blunt for its depth that the cell's curvature matters."""
        if model not in ("hertz_sphere", "hertz_paraboloid", "sneddon_cone"):
            raise InputError(
                where,
                f"{field}.type",
                "a spherical probe (model hertz_sphere or hertz_paraboloid) or a cone "
                "(sneddon_cone): pyramids are not covered",
                model,
            )
        if nu != 0.5:
            raise InputError(where, "inputs.nu", f"0.5 with {field} (the table's layers)", nu)
        if depth_um is None:
            raise InputError(
                where, "inputs.max_indentation_um", f"a depth (the fit range) with {field}", None
            )
        if model == "sneddon_cone":
            self._check_cone(geometry["half_angle_deg"], depth_um, where)
        else:
            self._check_sphere(geometry["radius_um"], depth_um, where, field)
        check_range(
            self.cell_um / self.zona_um / TABLE_CELL_OVER_ZONA,
            1 - CELL_TOLERANCE,
            1 + CELL_TOLERANCE,
            f"{field}.cell_radius_um / zona_thickness_um over the table's 70/15 (R/h)",
            where,
        )

    def _check_sphere(self, probe_um: float, depth_um: float, where: str, field: str) -> None:
        t = load_table()
        probe_h = probe_um / self.zona_um
        check_range(
            probe_h,
            t.probes[0],
            t.probes[-1],
            f"inputs.geometry.radius_um / {field}.zona_thickness_um (Rp/h)",
            where,
        )
        deepest = t.max_depth_h(probe_h) * self.zona_um
        if depth_um > deepest * (1 + 1e-9):
            raise InputError(
                where,
                "inputs.max_indentation_um",
                f"<= {deepest:.4g} um, the table's deepest for this probe and ZP",
                depth_um,
            )

    def _check_cone(self, half_angle_deg: float, depth_um: float, where: str) -> None:
        tan = math.tan(math.radians(half_angle_deg))
        max_y = cone_max_y(half_angle_deg)
        deepest = min(
            max_y * self.zona_um / tan, CONE_CURVATURE_GAP * math.pi * self.cell_um / tan**2
        )
        if depth_um > deepest * (1 + 1e-9):
            raise InputError(
                where,
                "inputs.max_indentation_um",
                f"<= {deepest:.4g} um for a {half_angle_deg:g} deg cone: the cone table's "
                f"deepest for this angle (y = d tan(alpha) / h <= {max_y:g}) and the "
                f"cell's curvature gap a tan(alpha) / (2 R) <= {CONE_CURVATURE_GAP:g}",
                depth_um,
            )

    def corrected(
        self, e_kPa: float, model: str, geometry: dict[str, float], depth_um: float
    ) -> float:
        """E_ZP [kPa] of a fit that read ``e_kPa`` to ``depth_um``."""
        if model == "sneddon_cone":
            return cone_zona_modulus(
                e_kPa,
                depth_um,
                geometry["half_angle_deg"],
                self.zona_um,
                self.cytoplasm_kPa,
                self.cell_um,
            )
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
            f"shelled_oocyte: E_ZP from the FE tables (afm/data/shell_correction.csv, "
            f"shell_correction_cone.csv for cones) for a "
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


def apply_correction(batch: BatchResult, correction: Correction) -> tuple[float | str, ...]:
    """Per row of ``batch``: the corrected E [kPa], or why not (``""`` for a row not fitted)."""
    out: list[float | str] = []
    for r in batch.rows:
        if r.fit is None or r.error:
            out.append("")
            continue
        f = r.fit
        try:
            out.append(
                correction.corrected(f.E_kPa, f.model, dict(f.geometry), f.max_indentation_um)
            )
        except InputError as exc:
            out.append(f"not corrected: {exc.field}: expected {exc.expected}, got {exc.got}")
    return tuple(out)


def corrected_stats(
    batch: BatchResult, corrected: tuple[float | str, ...], include_poor: bool
) -> list[GroupStats]:
    """Mean +- SD of the corrected E per group (quantity ``E_kPa``); rows whose correction was
    refused are left out of the mean, as poor fits are unless ``include_poor``."""
    out = []
    for group in sorted({r.group for r in batch.rows}):
        fitted = [
            (r.fit, value)
            for r, value in zip(batch.rows, corrected, strict=True)
            if r.group == group and r.fit is not None and not r.error
        ]
        if not fitted:
            continue
        values = np.array(
            [v for f, v in fitted if isinstance(v, float) and (include_poor or f.quality == "good")]
        )
        mean = float(values.mean()) if values.size else float("nan")
        sd = float(np.std(values, ddof=1)) if values.size > 1 else float("nan")
        n_poor = sum(f.quality != "good" for f, _ in fitted)
        out.append(GroupStats(group, "E_kPa", values.size, n_poor, mean, sd))
    return out
