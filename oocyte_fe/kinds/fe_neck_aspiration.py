"""Case kind ``fe_neck_aspiration``: the AFM-derived layered oocyte through a 200 -> 150 um neck
(seed 001, Section 3.2, Fig. 5)."""

from __future__ import annotations

import numpy as np

from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.fe.fields import contact_pressure_at_vertices, stress_fields
from oocyte_fe.fe.material import read_material_file
from oocyte_fe.io import FieldSeriesWriter, write_history_csv
from oocyte_fe.kinds.neck_inputs import METRICS, UNITS, NeckInputs
from oocyte_fe.neck import report
from oocyte_fe.neck.materials import materials_from_afm_case
from oocyte_fe.neck.passage import PassageResult, PassageSettings, run_passage
from oocyte_fe.neck.pipette import NeckedPipette
from oocyte_fe.runner.registry import CaseContext, CaseOutcome, Check, case_kind


def _settings(inp: NeckInputs, size: float | None = None, friction: float | None = None):
    return PassageSettings(
        size_um=size or inp.size_um,
        refine_factor=inp.refine_factor,
        duration_s=inp.duration_s,
        steps=inp.steps,
        advance_um=inp.advance_um,
        friction=inp.friction if friction is None else friction,
        penalty_factor=inp.penalty_factor,
    )


def _end(result: PassageResult, key: str) -> np.ndarray:
    return np.asarray(result.history[key][-1], dtype=float)


def _stall(result: PassageResult, dp_kPa: float) -> float:
    need = result.series("suction_kPa")
    over = np.nonzero(need > dp_kPa)[0]
    return float(result.series("centroid_advance_um")[over[0]]) if over.size else float("nan")


def _require(result: PassageResult, label: str) -> None:
    if not result.complete:
        raise RuntimeError(f"{label}: {result.failure}")


@case_kind("fe_neck_aspiration", inputs=NeckInputs, metrics=METRICS)
def run(ctx: CaseContext) -> CaseOutcome:
    """Layered viscoelastic oocyte through a narrowed pipette neck; peripheral deformation."""
    inp: NeckInputs = ctx.inputs  # type: ignore[assignment]
    if inp.material_case is None:
        zp, cy = inp.zona_material_file, inp.cytoplasm_material_file
        ctx.step(f"materials: {zp.name}, {cy.name}")
        mats = LayerMaterials(read_material_file(zp), read_material_file(cy))
        origin = f"read from the case's files `{zp.name}` and `{cy.name}`"
    else:
        afm_dir = (ctx.case_dir / inp.material_case).resolve()
        ctx.step(f"materials: re-running {afm_dir.name} into material/")
        mats = materials_from_afm_case(afm_dir, ctx.output("material"), ctx.log, ctx.quick)
        origin = (
            f"regenerated through afm by re-running `{inp.material_case}`: files "
            "`material/material_zp.toml`, `material/material_cytoplasm.toml`"
        )
    mats = mats.with_moduli(inp.zona_E_kPa, inp.cytoplasm_E_kPa)
    pipette = NeckedPipette(inp.bore_diameter_um / 2, inp.neck_diameter_um / 2, inp.taper_length_um)
    geometry = {"cytoplasm_radius_um": inp.cytoplasm_radius_um, "zona_um": inp.zona_thickness_um}
    dp0 = inp.suction_Pa * 1e-3

    failures: list[str] = []

    def passage(label: str, settings: PassageSettings, **kw) -> PassageResult | None:
        """A comparison run; one that stops early is reported, not fatal."""
        ctx.step(f"passage: {label}")
        result = run_passage(mats.regions(**kw), settings, pipette, log=ctx.log, **geometry)
        if not result.complete:
            failures.append(f"{label}: {result.failure}")
            return None
        return result

    # main run, with the VTU series written frame by frame
    ctx.step(f"passage: viscoelastic (main), element size {inp.size_um:g} um")
    series: list = []

    def keep(result: PassageResult, frame) -> None:
        if inp.vtu:
            body = result.problem.body
            fields = stress_fields(result.problem, frame.x)
            series.append(
                (
                    frame.t,
                    body.vertex_displacement(frame.x),
                    -fields["mean_stress"],
                    fields["von_mises"],
                    contact_pressure_at_vertices(result.problem, frame),
                )
            )

    main = run_passage(
        mats.regions(), _settings(inp), pipette, log=ctx.log, on_frame=keep, **geometry
    )
    _require(main, "viscoelastic passage")
    body = main.problem.body
    if inp.vtu:
        wall = np.asarray(main.pipette.profile(), dtype=float)  # fixed in the lab frame
        with FieldSeriesWriter(ctx.output("fields"), body.mesh, "neck", axisymmetric=True) as vtu:
            for t, u, p, vm, cp in series:
                vtu.write(
                    t, u, pressure=p, von_mises=vm, contact_pressure=cp, obstacles={"pipette": wall}
                )

    ctx.step("outputs")
    h = main.history
    columns = {k: np.asarray(v, dtype=float) for k, v in h.items() if np.ndim(v[0]) == 0}
    for j, angle in enumerate(main.points.polar_deg):
        columns[f"radial_inward_{angle:.0f}deg_um"] = np.asarray(h["radial_inward_um"])[:, j]
        columns[f"deformation_{angle:.0f}deg_um"] = np.asarray(h["deformation_um"])[:, j]
    units = {k: (k.rsplit("_", 1)[-1] if k.rsplit("_", 1)[-1] in UNITS else "") for k in columns}
    write_history_csv(ctx.output("history.csv"), columns, units)

    figures = report.passage_figures(
        main, ctx.output, inp.cytoplasm_radius_um, inp.zona_thickness_um, dp0
    )

    deform = _end(main, "deformation_um")
    radial = _end(main, "radial_inward_um")
    runs = {"viscoelastic (main)": deform}
    metrics = {
        "deformation_min_um": float(deform.min()),
        "deformation_max_um": float(deform.max()),
        "radial_inward_max_um": float(radial.max()),
        "volume_change_pct": float(100 * np.abs(main.series("volume_change")).max()),
        "suction_needed_max_Pa": float(1e3 * main.series("suction_kPa").max()),
        "stall_advance_um": _stall(main, dp0),
        "centroid_advance_um": float(main.series("centroid_advance_um")[-1]),
    }
    wall = main.series("wall_force_nN")
    touching = wall > 0.05 * wall.max()
    metrics["push_fraction_max"] = float(
        np.max(np.abs(main.series("push_force_nN")[touching]) / wall[touching])
    )
    sections = []

    elastic = passage("elastic (Prony terms dropped)", _settings(inp), viscoelastic=False)
    if elastic is not None:
        runs["elastic"] = _end(elastic, "deformation_um")
        change = runs["elastic"] / deform - 1
        metrics["elastic_vs_visco_pct"] = float(100 * np.max(np.abs(change)))
        sections.append(
            report.elastic_section(
                main.points.polar_deg,
                deform,
                runs["elastic"],
                metrics["suction_needed_max_Pa"],
                1e3 * elastic.series("suction_kPa").max(),
            )
        )

    sens_rows = []
    base = None
    if inp.sensitivity:
        base = passage("sensitivity base", _settings(inp, inp.sensitivity_size_um))
        cases = [
            (f"friction {mu:g}", _settings(inp, inp.sensitivity_size_um, mu), {})
            for mu in inp.friction_values
        ]
        e0 = mats.zona.E_kPa
        cases += [
            (f"E_ZP {e:.2f} kPa", _settings(inp, inp.sensitivity_size_um), {"zona_E_kPa": e})
            for e in (e0 - inp.zona_E_sd_kPa, e0 + inp.zona_E_sd_kPa)
        ]
        for label, st, kw in [("base (coarse)", None, None), *cases]:
            r = base if st is None else passage(label, st, **kw)
            if r is None:
                continue
            d = _end(r, "deformation_um")
            runs[label] = d
            sens_rows.append((label, d, 1e3 * r.series("suction_kPa").max(), _stall(r, dp0)))
        sections.append(report.sensitivity_section(inp.sensitivity_size_um, sens_rows))

    if inp.mesh_study_sizes_um:
        study = []
        for size in sorted(inp.mesh_study_sizes_um, reverse=True):
            done = {inp.size_um: main}
            if base is not None:
                done[inp.sensitivity_size_um] = base
            r = done.get(size) or passage(f"mesh {size:g} um", _settings(inp, size))
            if r is None:
                continue
            study.append(
                (
                    size,
                    r.problem.body.mesh.nelements,
                    r.problem.body.n_dofs,
                    _end(r, "deformation_um"),
                )
            )
        if len(study) >= 2:
            a, b = study[-2][3], study[-1][3]
            metrics["mesh_change_pct"] = float(100 * np.max(np.abs(a / b - 1)))
        sections.append(report.mesh_section(study))

    figures.append(report.periphery_figure(ctx.output, main.points.polar_deg, runs))
    sections = report.neck_sections(main, radial, deform, mats, sections, failures, origin)
    checks = [
        Check(
            "volume conserved (nu = 0.5) within 0.5 %",
            metrics["volume_change_pct"],
            metrics["volume_change_pct"] <= 0.5,
            "<= 0.5 %",
            unit="%",
        )
    ]
    if "mesh_change_pct" in metrics:
        checks.append(
            Check(
                f"deformation changes < {inp.mesh_change_max_pct:g} % between the two finest "
                "meshes",
                metrics["mesh_change_pct"],
                metrics["mesh_change_pct"] < inp.mesh_change_max_pct,
                f"< {inp.mesh_change_max_pct:g} %",
                unit="%",
            )
        )
    return CaseOutcome(metrics=metrics, figures=figures, sections=sections, checks=checks)
