"""Case kind ``afm_zp_cytoplasm``: pierce-through curves -> ZP and cytoplasm moduli."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from pydantic import Field, model_validator

from afm.batch import curve_files, fit_batch, write_batch_table
from afm.curve import spring_constant_nN_per_um
from afm.curve_io import write_curve
from afm.plotting import plot_batch, plot_fit, plot_histogram
from afm.synthetic import check_pierce_visible, pierce_curve
from oocyte_fe.errors import InputError
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Relation, Setup


def _pierce_visible(m: ZpCytoplasmInputs) -> None:
    """The pierce of the noise-free curve at the mean moduli is detected (else no curve fits)."""
    check_pierce_visible(
        m.E_zp_mean_kPa,
        m.E_cytoplasm_mean_kPa,
        m.contact_point_um,
        pierce_force_nN=m.pierce_force_nN,
        residual_fraction=m.residual_fraction,
        trigger_force_nN=m.trigger_force_nN,
        k_nN_per_um=spring_constant_nN_per_um(m.spring_constant_N_per_m),
        geometry={"half_angle_deg": m.half_angle_deg},
        nu=m.nu,
        tilt_nN_per_um=m.tilt_nN_per_um,
    )


class ZpCytoplasmInputs(CaseInputs):
    rules = (
        Relation("trigger_force_nN", ">", lambda m: m.pierce_force_nN, "pierce_force_nN"),
        Setup(_pierce_visible),
    )

    n_oocytes: int = Field(
        ge=1,
        le=1000,
        description="oocytes in the synthetic population",
        json_schema_extra={"unit": "1"},
    )
    points_per_oocyte: int = Field(
        ge=1,
        le=1000,
        description="pierce-through curves per oocyte",
        json_schema_extra={"unit": "1"},
    )
    E_zp_mean_kPa: float = Field(
        gt=0, description="mean of the ZP moduli drawn", json_schema_extra={"unit": "kPa"}
    )
    E_zp_sd_kPa: float = Field(
        ge=0, description="SD of the ZP moduli drawn", json_schema_extra={"unit": "kPa"}
    )
    E_cytoplasm_mean_kPa: float = Field(
        gt=0, description="mean of the cytoplasm moduli drawn", json_schema_extra={"unit": "kPa"}
    )
    E_cytoplasm_sd_kPa: float = Field(
        ge=0, description="SD of the cytoplasm moduli drawn", json_schema_extra={"unit": "kPa"}
    )
    min_E_kPa: float = Field(
        gt=0,
        description="draws below this are redrawn (non-physical); below both means",
        json_schema_extra={"unit": "kPa"},
    )
    half_angle_deg: float = Field(
        description="cone half angle, in [0.1, 89] deg",
        json_schema_extra={"unit": "deg", "quantity": "cone_half_angle_deg"},
    )
    nu: float = Field(gt=-1, le=0.5, description="Poisson ratio", json_schema_extra={"unit": "1"})
    spring_constant_N_per_m: float = Field(
        gt=0, description="cantilever spring constant", json_schema_extra={"unit": "N/m"}
    )
    pierce_force_nN: float = Field(
        gt=0,
        description="force at which the probe pierces the ZP",
        json_schema_extra={"unit": "nN"},
    )
    residual_fraction: float = Field(
        ge=0, lt=1, description="force left after the drop / peak", json_schema_extra={"unit": "1"}
    )
    contact_point_um: float = Field(
        gt=0, description="scanner height at contact", json_schema_extra={"unit": "um"}
    )
    trigger_force_nN: float = Field(
        gt=0, description="force that ends the approach", json_schema_extra={"unit": "nN"}
    )
    n_points: int = Field(
        ge=100, le=1_000_000, description="samples per curve", json_schema_extra={"unit": "1"}
    )
    noise_fraction: float = Field(
        ge=0, le=1, description="force noise SD / pierce force", json_schema_extra={"unit": "1"}
    )
    tilt_nN_per_um: float = Field(description="baseline tilt", json_schema_extra={"unit": "nN/um"})
    seed: int = Field(
        0,
        ge=0,
        description="random seed of the population and noise",
        json_schema_extra={"unit": "1"},
    )

    @model_validator(mode="after")
    def _draws_possible(self) -> ZpCytoplasmInputs:
        for what in ("zp", "cytoplasm"):
            mean = getattr(self, f"E_{what}_mean_kPa")
            sd = getattr(self, f"E_{what}_sd_kPa")
            if mean - self.min_E_kPa < -3 * sd or (sd == 0 and mean < self.min_E_kPa):
                raise ValueError(
                    f"min_E_kPa below E_{what}_mean_kPa + 3 E_{what}_sd_kPa (almost every draw "
                    f"would be redrawn: mean {mean:g}, SD {sd:g}, floor {self.min_E_kPa:g} kPa)"
                )
        if self.n_oocytes * self.points_per_oocyte > 10_000:
            raise ValueError("n_oocytes x points_per_oocyte at most 10 000 curves")
        return self


METRICS = {
    "E_zp_mean_kPa": "mean fitted ZP modulus over the population, kPa",
    "E_zp_sd_kPa": "SD of the fitted ZP moduli, kPa",
    "E_cytoplasm_mean_kPa": "mean fitted cytoplasm modulus, kPa",
    "E_cytoplasm_sd_kPa": "SD of the fitted cytoplasm moduli, kPa",
    "zp_mean_vs_drawn_pct": "fitted ZP mean against the drawn sample's mean, %",
    "cytoplasm_mean_vs_drawn_pct": "fitted cytoplasm mean against the drawn sample's mean, %",
    "n_fitted": "curves fitted",
    "n_failed": "curves that could not be fitted",
}


MAX_REDRAW_ROUNDS = 1000


def _draw(
    rng: np.random.Generator, mean: float, sd: float, n: int, floor: float, where: Path
) -> np.ndarray:
    """n draws of N(mean, sd), each below ``floor`` redrawn (at most ``MAX_REDRAW_ROUNDS``)."""
    values = rng.normal(mean, sd, n)
    for _ in range(MAX_REDRAW_ROUNDS):
        bad = values < floor
        if not np.any(bad):
            return values
        values[bad] = rng.normal(mean, sd, int(bad.sum()))
    raise InputError(
        where,
        "inputs.min_E_kPa",
        f"a floor most draws of N({mean:g}, {sd:g}) kPa pass; {MAX_REDRAW_ROUNDS} redraw rounds "
        f"left {int(np.sum(values < floor))} of {n} below {floor:g} kPa",
    )


def _gallery(out_dir: Path, rows: list, drawn: dict[str, tuple[float, float]]) -> str:
    """A table linking each curve's own figure (``curve_plots/``) with its drawn and fitted
    moduli (kPa), so none of the per-curve PNGs is left unlinked."""
    lines = [
        f"Each fitted curve has its own figure in `curve_plots/` ({len(rows)} files); "
        "drawn: the modulus the synthetic curve was generated with.",
        "",
        "| curve | ZP drawn [kPa] | ZP fitted [kPa] | cytoplasm drawn [kPa] "
        "| cytoplasm fitted [kPa] | figure |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        name = Path(r.file).name
        png = Path("curve_plots") / f"{Path(name).stem}.png"
        link = f"[{png.name}]({png.as_posix()})" if (out_dir / png).exists() else "(none)"
        zp, cyt = drawn[name]
        lines.append(
            f"| {name} | {zp:.3f} | {r.fit.E_kPa:.3f} | {cyt:.3f} | {r.cytoplasm.E_kPa:.3f} "
            f"| {link} |"
        )
    return "\n".join(lines)


@case_kind("afm_zp_cytoplasm", inputs=ZpCytoplasmInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Synthetic pierce-through curves (paper's mean/SD) -> batch fit -> both moduli."""
    inp: ZpCytoplasmInputs = ctx.inputs  # type: ignore[assignment]
    rng = np.random.default_rng(inp.seed)
    n = inp.n_oocytes * inp.points_per_oocyte
    e_zp = _draw(
        rng, inp.E_zp_mean_kPa, inp.E_zp_sd_kPa, n, inp.min_E_kPa, ctx.case_dir / "case.toml"
    )
    e_cyt = _draw(
        rng,
        inp.E_cytoplasm_mean_kPa,
        inp.E_cytoplasm_sd_kPa,
        n,
        inp.min_E_kPa,
        ctx.case_dir / "case.toml",
    )
    k = spring_constant_nN_per_um(inp.spring_constant_N_per_m)
    geometry = {"half_angle_deg": inp.half_angle_deg}

    ctx.step(f"writing {n} synthetic pierce-through curves")
    folder = ctx.output("curves/oocytes/.keep").parent
    drawn: dict[str, tuple[float, float]] = {}
    for i in range(n):
        curve = pierce_curve(
            e_zp[i],
            e_cyt[i],
            inp.contact_point_um,
            pierce_force_nN=inp.pierce_force_nN,
            residual_fraction=inp.residual_fraction,
            trigger_force_nN=inp.trigger_force_nN,
            n_points=inp.n_points,
            k_nN_per_um=k,
            geometry=geometry,
            nu=inp.nu,
            tilt_nN_per_um=inp.tilt_nN_per_um,
            noise_fraction=inp.noise_fraction,
            seed=int(rng.integers(2**31)),
            group="oocytes",
        )
        oocyte, point = divmod(i, inp.points_per_oocyte)
        name = f"oocyte{oocyte + 1:03d}_point{point + 1:02d}.csv"
        write_curve(curve, folder / name)
        drawn[name] = (e_zp[i], e_cyt[i])

    ctx.step("fitting the batch (pierce detection, ZP and cytoplasm fits)")
    batch = fit_batch(curve_files(folder), pierce=True, geometry=geometry, nu=inp.nu)
    write_batch_table(batch, ctx.output("fits.csv"), relative_to=ctx.out_dir)
    good = [r for r in batch.rows if not r.error]
    if not good:
        raise InputError(
            ctx.case_dir / "case.toml",
            "inputs (pierce_force_nN, tilt_nN_per_um, noise_fraction)",
            f"curves whose pierce is detected; all {n} failed, first: {batch.failures[0].error}",
        )
    zp = np.array([r.fit.E_kPa for r in good])
    cyt = np.array([r.cytoplasm.E_kPa for r in good])
    truth = np.array([drawn[Path(r.file).name] for r in good])

    ctx.step("plots")
    plot_batch(batch, ctx.output("curve_plots/.keep").parent)
    first = good[int(np.argsort(zp)[len(zp) // 2])]  # the curve with the median ZP modulus
    plot_fit(
        [("ZP", first.fit), ("cytoplasm", first.cytoplasm)],
        ctx.output("curve_fit.png"),
        title=first.file.rsplit("/", 1)[-1],
    )
    plot_histogram(
        {"ZP": zp, "cytoplasm": cyt},
        ctx.output("histogram.png"),
        references={
            "ZP": (inp.E_zp_mean_kPa, inp.E_zp_sd_kPa),
            "cytoplasm": (inp.E_cytoplasm_mean_kPa, inp.E_cytoplasm_sd_kPa),
        },
    )
    zp_vs = 100 * (zp.mean() / truth[:, 0].mean() - 1)
    cyt_vs = 100 * (cyt.mean() / truth[:, 1].mean() - 1)
    per_curve = np.abs(zp / truth[:, 0] - 1), np.abs(cyt / truth[:, 1] - 1)
    metrics = {
        "E_zp_mean_kPa": float(zp.mean()),
        "E_zp_sd_kPa": float(zp.std(ddof=1)),
        "E_cytoplasm_mean_kPa": float(cyt.mean()),
        "E_cytoplasm_sd_kPa": float(cyt.std(ddof=1)),
        "zp_mean_vs_drawn_pct": float(zp_vs),
        "cytoplasm_mean_vs_drawn_pct": float(cyt_vs),
        "n_fitted": float(len(good)),
        "n_failed": float(len(batch.failures)),
    }
    checks = [
        Check(
            "ZP: every curve within 5 % of its drawn modulus",
            float(100 * per_curve[0].max()),
            bool(per_curve[0].max() < 0.05),
            "< 5 %",
            unit="%",
        ),
        Check(
            "cytoplasm: every curve within 5 % of its drawn modulus",
            float(100 * per_curve[1].max()),
            bool(per_curve[1].max() < 0.05),
            "< 5 %",
            unit="%",
        ),
    ]
    table = "\n".join(
        f"| {s.quantity} | {s.n} | {s.mean_kPa:.3f} | {s.sd_kPa:.3f} |" for s in batch.stats()
    )
    sections = [
        (
            "Population",
            f"{n} synthetic curves ({inp.n_oocytes} oocytes x {inp.points_per_oocyte} points); "
            f"drawn ZP {e_zp.mean():.3f} +- {e_zp.std(ddof=1):.3f} kPa, cytoplasm "
            f"{e_cyt.mean():.3f} +- {e_cyt.std(ddof=1):.3f} kPa. Fitted (mean +- SD):\n\n"
            "| modulus | n | mean [kPa] | SD [kPa] |\n|---|---|---|---|\n" + table,
        )
    ]
    sections.append(("Every curve", _gallery(ctx.out_dir, good, drawn)))
    figures = [
        Figure("curve_fit.png", "Median-ZP curve: data, Sneddon fits of both segments, E(delta)"),
        Figure("histogram.png", "Fitted moduli; dashed: the paper's mean, band: +- SD"),
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)
