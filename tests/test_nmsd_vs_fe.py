"""NMSD-vs-FE cross-check (issue 9): scenario mapping, AFM material chain, FE probes, agreement
measures, and the quick case end to end."""

from __future__ import annotations

import json
import logging
import tomllib
from pathlib import Path

import numpy as np
import pydantic
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from nmsd.zona import zona_link_factor
from oocyte_fe.crosscheck.agreement import displacement_agreement, spindle_tolerance_um
from oocyte_fe.crosscheck.comparison import zona_ring_ratio
from oocyte_fe.crosscheck.fe_press import FeSettings, output_frames, press_experiment
from oocyte_fe.crosscheck.scenario import PressScenario, interior_grid
from oocyte_fe.crosscheck.zp_material import afm_layer_materials
from oocyte_fe.errors import InputError
from oocyte_fe.experiment.driver import cell_mesh
from oocyte_fe.experiment.layers import LayerMaterials
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.fields import point_probes
from oocyte_fe.fe.material import Material
from oocyte_fe.kinds.crosscheck_inputs import CrosscheckInputs
from oocyte_fe.kinds.fe_nmsd_crosscheck import nmsd_setup
from oocyte_fe.runner.registry import CaseContext
from oocyte_fe.runner.result import read_result
from oocyte_fe.runner.run import plan, run_cases

CASES = Path(__file__).parents[1] / "cases"
CASE = CASES / "nmsd_vs_fe"


def test_table_i_mapping_gives_a_16_um_zona_and_the_spindle_in_it() -> None:
    s = PressScenario()
    assert s.zona_thickness_um == pytest.approx((115.625 - 83.597) / 2)
    assert s.spindle_world_um == pytest.approx([115.625 / 2 - 15.8718, 18.1392])
    r = np.hypot(*s.spindle_world_um)
    assert 83.597 / 2 < r < 115.625 / 2  # in the ZP ring of the FE disc


def test_interior_grid_is_symmetric_and_inside_the_margin() -> None:
    pts = interior_grid(57.8125, 10.0, 8.0)
    assert np.all(np.hypot(pts[:, 0], pts[:, 1]) <= 57.8125 - 8.0)
    assert len(pts) == len({(x, -y) for x, y in pts} & {tuple(p) for p in pts})
    assert [0.0, 0.0] in pts.tolist()


def test_bad_scenario_names_the_field() -> None:
    with pytest.raises(InputError, match="cytoplasm_diameter_um"):
        PressScenario(cytoplasm_diameter_um=120.0)
    with pytest.raises(InputError, match="spindle_paper_um"):
        PressScenario(spindle_paper_um=(-5.0, 0.0))


def test_afm_chain_recovers_the_series_the_creep_record_was_made_from() -> None:
    made = tomllib.loads((CASES / "afm_creep_prony" / "case.toml").read_text())["inputs"]
    mats = afm_layer_materials(CASE / "creep_zp.csv", 1.55)
    assert mats.zona.E_kPa == pytest.approx(made["E0_kPa"], rel=0.01)
    assert mats.zona.prony.g == pytest.approx(made["prony_g"], abs=0.01)
    assert mats.zona.prony.tau_s == pytest.approx(made["prony_tau_s"], rel=0.02)
    assert mats.cytoplasm.E_kPa == 1.55 and not mats.cytoplasm.prony.g


def test_bad_creep_record_is_an_input_error(tmp_path: Path) -> None:
    bad = tmp_path / "creep.csv"
    bad.write_text("time_s,force_nN,height_um\n0,1,2\n")
    with pytest.raises(InputError, match="creep.csv"):
        afm_layer_materials(bad, 1.55)


def test_held_patch_and_probes_reproduce_a_quadratic_field_exactly() -> None:
    scenario = PressScenario()
    layers = {"zona": Material(7.0, 0.5), "cytoplasm": Material(1.55, 0.5)}
    pts = interior_grid(scenario.radius_um, 15.0, 8.0)
    materials = LayerMaterials(layers["zona"], layers["cytoplasm"])
    settings = FeSettings(size_um=14.0, refine_size_um=7.0)
    mesh = cell_mesh(press_experiment(scenario, materials, settings, 10.0, pts))
    held = mesh.boundaries["hold:held"]
    mid = mesh.p[:, mesh.facets[:, held]].mean(axis=1)
    assert np.all(mid[0] < 0) and np.all(np.abs(mid[1]) <= 25.0)
    assert np.hypot(*mid).min() == pytest.approx(scenario.radius_um, rel=5e-3)  # chord midpoints
    body = Body(mesh, layers, "plane_strain")
    straight = skfem.Basis(skfem.MeshTri(mesh.p, mesh.t), body.uelem)
    u = straight.project(lambda x: np.array([x[0] ** 2 - x[1], 0.5 * x[0] * x[1]]))
    got = (point_probes(body, pts) @ u).reshape(2, -1)
    x, y = pts.T
    assert got == pytest.approx(np.array([x**2 - y, 0.5 * x * y]), abs=1e-9)


def test_spindle_goal_is_the_larger_of_2_um_and_10_percent() -> None:
    assert spindle_tolerance_um(np.array([[3.0, 4.0], [30.0, 40.0]])) == pytest.approx([2, 5])
    u_fe = np.zeros((2, 3, 2))
    u_fe[:, 0] = [[10.0, 0.0], [40.0, 0.0]]
    u_nm = u_fe.copy()
    u_nm[:, 0, 1] += [1.5, 3.0]
    u_nm[1, 2] = [0.0, 7.0]
    agree = displacement_agreement(np.array([10.0, 40.0]), u_fe, u_nm)
    assert agree.spindle_error_um == pytest.approx([1.5, 3.0])
    assert agree.spindle_ratio == pytest.approx([0.75, 0.75])
    assert agree.max_error_um == pytest.approx(7.0)


@pytest.mark.slow
def test_quick_case_fits_the_fe_force_and_reports_the_missed_spindle_goal(quick_run) -> None:
    folder = quick_run("nmsd_vs_fe")  # shared with the round-off test (tests/conftest.py)
    result = read_result(folder)
    data = json.loads((folder / "metrics.json").read_text())
    checks = {c["name"]: c for c in data["checks"]}
    m = data["metrics"]
    # held: the NMSD reproduces the FE force curve it is calibrated to (R^2 0.981, similarity
    # 0.998 measured); contact is resolved (0.38 um largest penetration of the 62.5 um press)
    assert m["nmsd_fe_r2"] >= 0.95
    assert m["nmsd_fe_similarity"] >= 0.99
    assert m["penetration_max_um"] <= 1.0
    # both spindles move towards the holder by more than half the advance; with link dampers
    # (the case's reading) the NMSD spindle travel is within 25 % of the FE's (12 % measured)
    assert 0.5 * 62.5 < m["spindle_fe_end_um"] < 62.5
    assert abs(m["spindle_nmsd_end_um"] - m["spindle_fe_end_um"]) < 0.25 * m["spindle_fe_end_um"]
    # fitted at 30 and 3 um/s together: the 3 um/s curve is followed too (0.973 measured)
    assert m["rate_check_force_r2"] >= 0.93
    # issue 9 goal (max(2 um, 10 %)) held as stated: missed (2.8 x), a documented known miss
    # (MISS, within its regression bound), the only check not passed
    assert 2.5 < m["spindle_goal_ratio_max"] < 3.0
    assert checks["spindle_goal_ratio_max"]["status"] == "MISS"
    assert result.status == "MISS" and result.ok
    # the fits eq 7 cannot tell apart (within 10 % of the best RMSE) predict nearly the same
    # spindle path (round-off of the inputs no longer moves the fit:
    # tests/test_nmsd_reproducible.py). Since the creep fit takes the measured force history
    # (the ZP's Prony series moved by about 0.1 %, the FE force by 0.03 %) the best fit is
    # closer (RMSE 0.74 against 0.93 uN) and alone within 10 %: 1 of 6 starts, 2.74 x; before,
    # 2 of 6 at 2.76-2.81 x. The spread is checked where there are several.
    lo, hi = m["near_best_spindle_goal_ratio_min"], m["near_best_spindle_goal_ratio_max"]
    assert m["near_best_fits"] >= 1 and lo <= m["spindle_goal_ratio_max"] <= hi
    assert hi - lo < 0.3
    assert [n for n, c in checks.items() if not c["passed"]] == ["spindle_goal_ratio_max"]
    assert {p.name for p in folder.glob("*.png")} >= {
        "force_curves.png",
        "displacement_arrows.png",
        "fe_section_end.png",
    }


@pytest.mark.slow
def test_quick_matched_lattice_case_meets_the_spindle_goal_at_both_speeds(tmp_path: Path) -> None:
    # area term (nu 0.49), eq 8 lifted, ZP ring at the relaxed AFM ratio; fitted at 30 and
    # 3 um/s: the issue 9 goal max(2 um, 10 %) holds at both (0.54 / 0.56 x measured, quick)
    case = CASES / "nmsd_vs_fe_matched_lattice"
    [result] = run_cases(plan([case], quick=True), tmp_path, quick=True)
    data = json.loads((tmp_path / case.name / "metrics.json").read_text())
    checks = {c["name"]: c for c in data["checks"]}
    m = data["metrics"]
    assert result.status == "PASS", [n for n, c in checks.items() if not c["passed"]]
    assert m["spindle_goal_ratio_max"] < 1.0 and m["rate_check_spindle_goal_ratio_max"] < 1.0
    assert m["nmsd_fe_r2"] >= 0.99 and m["rate_check_force_r2"] >= 0.98
    assert (
        "relaxed (NMSD ring input: `afm_relaxed`)"
        in (tmp_path / case.name / "report.md").read_text()
    )


def test_nmsd_area_stiffness_reaches_the_lattice_and_is_checked(tmp_path: Path) -> None:
    files = {"creep_data": CASE / "creep_zp.csv", "table2_data": CASE / "creep_zp.csv"}
    with pytest.raises(pydantic.ValidationError, match="nmsd_area_stiffness"):
        CrosscheckInputs(**files, nmsd_area_stiffness=-1.0)
    assert CrosscheckInputs(**files).nmsd_area_stiffness == 0.0  # default: the paper's model
    inputs = CrosscheckInputs(**files, nmsd_area_stiffness=3.79, nmsd_n_steps=4)
    ctx = CaseContext("x", CASE, tmp_path, inputs, True, logging.getLogger("test"))
    setup, base = nmsd_setup(ctx, 1.0)
    assert base.area_stiffness == 3.79 and setup.lattice.cells is not None


def test_nmsd_zona_ring_reaches_the_lattice_at_the_cytoplasm_radius(tmp_path: Path) -> None:
    files = {"creep_data": CASE / "creep_zp.csv", "table2_data": CASE / "creep_zp.csv"}
    with pytest.raises(pydantic.ValidationError, match="nmsd_zona_stiffness_ratio"):
        CrosscheckInputs(**files, nmsd_zona_stiffness_ratio=0.0)
    assert CrosscheckInputs(**files).nmsd_zona_stiffness_ratio == 1.0  # the paper's lattice
    inputs = CrosscheckInputs(**files, nmsd_zona_stiffness_ratio=4.52, nmsd_n_steps=4)
    ctx = CaseContext("x", CASE, tmp_path, inputs, True, logging.getLogger("test"))
    setup, base = nmsd_setup(
        ctx,
        zona_ring_ratio(
            inputs.nmsd_zona_stiffness_ratio, afm_layer_materials(files["creep_data"], 1.55)
        ),
    )
    assert base.zona_stiffness_ratio == 4.52
    assert base.zona_inner_radius_um == pytest.approx(83.597 / 2)
    factor = zona_link_factor(setup.lattice, base)
    assert 0 < np.sum(factor == 4.52) < len(factor)
    # a cytoplasm wider than the cell is refused where it enters (the inputs' rule), before
    # the NMSD ring could be built
    with pytest.raises(pydantic.ValidationError, match="cytoplasm_diameter_um < cell_diameter"):
        CrosscheckInputs(
            **files, nmsd_zona_stiffness_ratio=4.52, cytoplasm_diameter_um=200.0, nmsd_n_steps=4
        )


def test_nmsd_zona_ratio_from_the_afm_layers_is_relaxed_or_instantaneous() -> None:
    # the creep record was made (cases/afm_creep_prony) from E0 and Prony g; the cytoplasm is
    # elastic at 1.55 kPa: relaxed E0 (1 - sum g) / 1.55, instantaneous E0 / 1.55
    made = tomllib.loads((CASES / "afm_creep_prony" / "case.toml").read_text())["inputs"]
    files = {"creep_data": CASE / "creep_zp.csv", "table2_data": CASE / "creep_zp.csv"}
    materials = afm_layer_materials(files["creep_data"], 1.55)
    e0, g_inf = materials.zona.E_kPa, 1.0 - sum(materials.zona.prony.g)
    relaxed = CrosscheckInputs(**files, nmsd_zona_stiffness_ratio="afm_relaxed")
    instant = CrosscheckInputs(**files, nmsd_zona_stiffness_ratio="afm_instantaneous")
    assert zona_ring_ratio(relaxed.nmsd_zona_stiffness_ratio, materials) == pytest.approx(
        e0 * g_inf / 1.55, rel=1e-12
    )
    assert zona_ring_ratio(instant.nmsd_zona_stiffness_ratio, materials) == pytest.approx(
        e0 / 1.55, rel=1e-12
    )
    made_relaxed = made["E0_kPa"] * (1.0 - sum(made["prony_g"])) / 1.55
    assert zona_ring_ratio(relaxed.nmsd_zona_stiffness_ratio, materials) == pytest.approx(
        made_relaxed, rel=0.02
    )
    with pytest.raises(pydantic.ValidationError, match="nmsd_zona_stiffness_ratio"):
        CrosscheckInputs(**files, nmsd_zona_stiffness_ratio="afm")


@settings(max_examples=60, deadline=None)
@given(
    frames=st.integers(1, 400),
    step=st.floats(0.01, 50.0),
    e_travel=st.sampled_from([-1e-9, 0.0, 1e-9]),
    e_step=st.sampled_from([-1e-9, 0.0, 1e-9]),
)
def test_output_frames_of_a_step_that_fits_the_travel_ignore_round_off(
    frames: int, step: float, e_travel: float, e_step: float
) -> None:
    """A step written to fit the travel (travel = frames x step) keeps its frames when either
    is off by a relative 1e-9 (an absolute slack of 1e-9 on the ratio gave one frame more, so
    that the shipped matched-lattice case's arrows at 20 / 40 / 60 um fell between frames); a
    step 1e-4 short of fitting gives the next frame."""
    travel = frames * step
    assert output_frames(travel * (1 + e_travel), step * (1 + e_step)) == frames
    assert output_frames(travel * (1 + 1e-4), step) == frames + 1
