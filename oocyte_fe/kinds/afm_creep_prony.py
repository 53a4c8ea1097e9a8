"""Case kind ``afm_creep_prony``: ZP creep (force clamp) -> Prony series -> material file."""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from afm.creep import fit_creep
from afm.creep_data import FORCE_CLAMP_TOLERANCE
from afm.curve import spring_constant_nN_per_um
from afm.curve_io import read_creep, write_creep
from afm.fe_export import ansys_prony_block, febio_material
from afm.material_file import MaterialFile, read_material, write_material
from afm.plotting import plot_creep
from afm.prony_series import RelaxationProny
from afm.synthetic import creep_indentation
from oocyte_fe.errors import InputError
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, Figure, case_kind
from oocyte_fe.runner.schema import CaseInputs, Relation

RelaxationTime = Annotated[float, Field(ge=1e-4, le=1e4)]
Fraction = Annotated[float, Field(ge=1e-6, lt=1)]
MIN_SAMPLES = 10
"""Fewest samples of a creep record (:class:`afm.creep_data.CreepData`)."""
MAX_SAMPLES = 2e5
"""Most samples of the synthetic record (200 s at 1 kHz, 33 x the paper's 6 s hold): each 1e5
samples cost about a CPU second (CSV, fit, plot); 1e6 took 10 s, beyond a cheap kind."""


def _force_to_depth(m: CreepInputs, depth_um: float) -> float:
    """Clamp force [nN] whose noise-free indentation reaches ``depth_um`` at the end of the hold
    (Lee-Radok: the indentation grows as sqrt(force)); inf if the series is not yet valid."""
    if len(m.prony_g) != len(m.prony_tau_s) or sum(m.prony_g) >= 1:
        return math.inf  # refused by _series with its own message
    truth = RelaxationProny(m.E0_kPa / (2 * (1 + m.nu)), m.prony_g, m.prony_tau_s)
    unit = float(creep_indentation(truth, np.array([m.hold_s]), 1.0, m.half_angle_deg, m.nu)[0])
    return (depth_um / unit) ** 2


class CreepInputs(CaseInputs):
    rules = (
        # the record is t = 0, 1/rate, ... up to the hold: hold x rate + 1 samples
        Relation(
            "hold_s",
            ">=",
            lambda m: (MIN_SAMPLES - 1) / m.sample_rate_Hz,
            f"{MIN_SAMPLES - 1} / sample_rate_Hz (a creep record of at least {MIN_SAMPLES} "
            "samples)",
        ),
        Relation(
            "hold_s",
            "<=",
            lambda m: MAX_SAMPLES / m.sample_rate_Hz,
            f"{MAX_SAMPLES:g} / sample_rate_Hz (at most {MAX_SAMPLES:g} samples)",
        ),
        Relation(
            "prony_tau_s",
            "<",
            lambda m: m.hold_s,
            "hold_s (each relaxation time within the record it is identified from)",
            measure="max",
        ),
        Relation(
            "clamp_force_nN",
            ">=",
            lambda m: m.force_noise_nN / (0.5 * FORCE_CLAMP_TOLERANCE),
            f"force_noise_nN / {0.5 * FORCE_CLAMP_TOLERANCE:g} (force SD/mean within half the "
            f"{FORCE_CLAMP_TOLERANCE:g} a clamped record allows)",
        ),
        Relation(
            "clamp_force_nN",
            "<",
            lambda m: _force_to_depth(m, m.cell_diameter_um),
            "the force [nN] indenting cell_diameter_um deep by the end of the hold",
        ),
    )

    E0_kPa: float = Field(
        7.01,
        gt=0,
        description="instantaneous Young's modulus of the synthetic ZP",
        json_schema_extra={"unit": "kPa"},
    )
    nu: float = Field(
        0.5, gt=-1, le=0.5, description="Poisson ratio", json_schema_extra={"unit": "1"}
    )
    prony_g: list[Fraction] = Field(
        default_factory=lambda: [0.3, 0.2],
        min_length=1,
        description="normalised relaxation terms g_i, each in [1e-6, 1), summing below 1",
        json_schema_extra={"unit": "1"},
    )
    prony_tau_s: list[RelaxationTime] = Field(
        default_factory=lambda: [0.2, 1.5],
        min_length=1,
        description="relaxation times tau_i, each in [1e-4, 1e4] s",
        json_schema_extra={"unit": "s"},
    )
    half_angle_deg: float = Field(
        10.0,
        description="cone half angle, in [0.1, 89] deg",
        json_schema_extra={"unit": "deg", "quantity": "cone_half_angle_deg"},
    )
    clamp_force_nN: float = Field(
        5.0, gt=0, description="force held during the creep", json_schema_extra={"unit": "nN"}
    )
    hold_s: float = Field(
        6.0, gt=0, le=1e4, description="duration of the hold", json_schema_extra={"unit": "s"}
    )
    sample_rate_Hz: float = Field(
        1000.0,
        gt=0,
        le=1e5,
        description="samples per second of the record",
        json_schema_extra={"unit": "Hz"},
    )
    noise_fraction: float = Field(
        0.002,
        ge=0,
        le=1,
        description="indentation noise SD / indentation",
        json_schema_extra={"unit": "1"},
    )
    force_noise_nN: float = Field(
        0.02, ge=0, description="force noise SD during the clamp", json_schema_extra={"unit": "nN"}
    )
    plateau_height_um: float = Field(
        8.0, description="scanner height at the end of the hold", json_schema_extra={"unit": "um"}
    )
    spring_constant_N_per_m: float = Field(
        0.07, gt=0, description="cantilever spring constant", json_schema_extra={"unit": "N/m"}
    )
    per_decade: int = Field(
        4,
        ge=1,
        le=20,
        description="NNLS grid: retardation times per decade",
        json_schema_extra={"unit": "1"},
    )
    cytoplasm_E_kPa: float = Field(
        1.55,
        gt=0,
        description="elastic cytoplasm modulus (seed Table 1)",
        json_schema_extra={"unit": "kPa"},
    )
    seed: int = Field(
        0, ge=0, description="random seed of the noise", json_schema_extra={"unit": "1"}
    )
    cell_diameter_um: float = Field(
        115.625,
        gt=0,
        description="diameter of the oocyte (with ZP); the final indentation stays below it",
        json_schema_extra={"unit": "um"},
    )

    @model_validator(mode="after")
    def _series(self) -> CreepInputs:
        if len(self.prony_g) != len(self.prony_tau_s):
            raise ValueError("prony_g and prony_tau_s of equal length")
        if sum(self.prony_g) >= 1:
            raise ValueError(f"prony_g summing below 1 (a solid; the sum is {sum(self.prony_g):g})")
        return self


METRICS = {
    "E0_kPa": "instantaneous Young's modulus 2 (1 + nu) G0 of the fitted series, kPa",
    "E_inf_kPa": "long-time Young's modulus 2 (1 + nu) G_inf, kPa",
    "G_max_error_pct": "largest |G_fit(t) / G_true(t) - 1| over 0.01 s .. hold, %",
    "inverse_J_max_error_pct": "largest |1/J(t) / G_true(t) - 1| (the paper's pointwise route), %",
    "n_prony_terms": "terms of the fitted series",
    "relative_rms_J": "relative RMS residual of the J(t) fit, 1",
    "final_height_um": "scanner height at the end of the hold, um",
    "final_indentation_um": "indentation at the end of the hold, um",
}


@case_kind("afm_creep_prony", inputs=CreepInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Synthetic ZP creep (5 nN, 6 s) -> Lee-Radok J(t) -> Prony -> exact G(t) -> material files."""
    inp: CreepInputs = ctx.inputs  # type: ignore[assignment]
    truth = RelaxationProny(inp.E0_kPa / (2 * (1 + inp.nu)), inp.prony_g, inp.prony_tau_s)

    ctx.step("synthetic force-clamp hold")
    rng = np.random.default_rng(inp.seed)
    t = np.arange(0.0, inp.hold_s + 0.5 / inp.sample_rate_Hz, 1.0 / inp.sample_rate_Hz)
    delta = creep_indentation(truth, t, inp.clamp_force_nN, inp.half_angle_deg, inp.nu)
    delta = delta * (1.0 + inp.noise_fraction * rng.standard_normal(t.size))
    force = inp.clamp_force_nN + inp.force_noise_nN * rng.standard_normal(t.size)
    k = spring_constant_nN_per_um(inp.spring_constant_N_per_m)
    contact = inp.plateau_height_um - delta[-1] - inp.clamp_force_nN / k
    height = contact + delta + force / k
    csv = write_creep(
        ctx.output("creep_zp.csv"),
        t,
        force,
        height,
        contact,
        inp.spring_constant_N_per_m,
        note="SYNTHETIC creep record (afm_creep_prony case), not measured data",
    )

    ctx.step("Lee-Radok compliance, Prony fit, exact relaxation series")
    try:
        fit = fit_creep(read_creep(csv), inp.half_angle_deg, inp.nu, inp.per_decade)
    except InputError as exc:  # name the inputs, not the record written from them
        raise InputError(
            ctx.case_dir / "case.toml",
            "inputs (clamp_force_nN, force_noise_nN, noise_fraction, prony_tau_s)",
            f"a synthetic record the creep fit accepts ({exc.field}: {exc.expected})",
            exc.got,
        ) from None
    material = fit.material(
        "zona_pellucida",
        "afm_creep_prony case: SYNTHETIC ZP creep (5 nN clamp, 6 s), Lee-Radok cone, "
        "creep Prony fit, exact conversion to relaxation",
    )
    zp_file = write_material(material, ctx.output("material_zp.toml"))
    cytoplasm = MaterialFile(
        "cytoplasm",
        "seed 001 Table 1 / Section 3.1: E = 1.55 kPa, nu = 0.5; elastic (no prominent creep)",
        inp.cytoplasm_E_kPa,
        inp.nu,
    )
    write_material(cytoplasm, ctx.output("material_cytoplasm.toml"))
    ctx.output("material_zp_ansys.inp").write_text(ansys_prony_block(material))
    ctx.output("material_zp_febio.xml").write_text(febio_material(material))
    again = read_material(zp_file)

    ctx.step("plots")
    tt = np.logspace(-2, np.log10(inp.hold_s), 300)
    plot_creep(fit, ctx.output("creep_prony.png"), truth=truth)
    g_err = float(np.max(np.abs(fit.relaxation(tt) / truth(tt) - 1)))
    inv_err = float(np.max(np.abs(1 / fit.creep(tt) / truth(tt) - 1)))
    metrics = {
        "E0_kPa": fit.E0_kPa,
        "E_inf_kPa": fit.E_inf_kPa,
        "G_max_error_pct": 100 * g_err,
        "inverse_J_max_error_pct": 100 * inv_err,
        "n_prony_terms": float(len(fit.relaxation.g)),
        "relative_rms_J": fit.relative_rms,
        "final_height_um": float(height[-1]),
        "final_indentation_um": float(delta[-1]),
    }
    checks = [
        Check(
            "material_zp.toml reads back with the same series",
            float(max(abs(a - b) for a, b in zip(again.g, material.g, strict=True))),
            again.g == material.g and again.tau_s == material.tau_s,
            "exact",
        )
    ]
    series = "\n".join(
        f"| {i + 1} | {g:.4f} | {tau:.4g} |"
        for i, (g, tau) in enumerate(zip(fit.relaxation.g, fit.relaxation.tau_s, strict=True))
    )
    sections = [
        (
            "Fitted relaxation series (written to material_zp.toml)",
            f"E0 = {fit.E0_kPa:.4g} kPa, E_inf = {fit.E_inf_kPa:.4g} kPa, nu = {inp.nu}. "
            f"G(t) within {100 * g_err:.3g} % of the series used to make the data over "
            f"0.01-{inp.hold_s:g} s; 1/J(t) (the paper's pointwise route) is off by up to "
            f"{100 * inv_err:.3g} %. Fit quality: {fit.quality} (relative RMS "
            f"{fit.relative_rms:.2g}).\n\n"
            "| i | g_i | tau_i [s] |\n|---|---|---|\n" + series + "\n\nAlso written: "
            "`material_cytoplasm.toml` (elastic), `material_zp_ansys.inp` (TB,PRONY), "
            "`material_zp_febio.xml` (FEBio viscoelastic), `creep_zp.csv` (the synthetic record).",
        )
    ]
    figures = [
        Figure(
            "creep_prony.png",
            "Left: J(t) from the creep record (Lee-Radok) and its Prony fit. Right: G(t) by the "
            "exact conversion, the series used to make the data, and 1/J(t).",
        )
    ]
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)
