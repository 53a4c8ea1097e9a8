"""Moduli corrected for the sample's shape (afm.corrections, afm.bottom_effect): the shelled-
oocyte FE table, Dimitriadis' and Garcia's bonded-layer corrections, the afm_fit_files option."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from afm import bottom_effect as be
from afm.corrections import (
    CONE_CURVATURE_GAP,
    cone_curvature_gap,
    cone_shell_ratio,
    cone_zona_modulus,
    curvature_factor,
    effective_radius_um,
    load_cone_table,
    load_table,
    shell_ratio,
    zona_modulus,
)
from afm.curve_io import write_curve
from afm.material_file import read_material
from afm.synthetic import indentation_curve
from oocyte_fe.errors import InputError
from oocyte_fe.runner.run import plan, run_cases


def test_interpolation_returns_the_table_nodes_exactly():
    t = load_table()
    for p, probe in enumerate(t.probes):
        for e, ratio in enumerate(t.e_ratios):
            for k in (1, len(t.depth[p]) // 2, len(t.depth[p]) - 1):
                expected = t.ratio[p][e][k]
                got = shell_ratio(float(t.depth[p][k]), ratio, probe)
                assert got == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_ratio_is_one_at_the_homogeneous_limit_and_at_zero_depth():
    t = load_table()
    for probe in (t.probes[0], 0.5, t.probes[-1]):
        deepest = t.max_depth_h(probe)
        for depth in np.linspace(0.0, deepest, 7):
            assert shell_ratio(float(depth), 1.0, probe) == pytest.approx(1.0, abs=1e-12)
        for e in (0.05, 0.3, 0.7):
            assert shell_ratio(0.0, e, probe) == pytest.approx(1.0, abs=1e-12)
    # and a stiff ZP over a soft cytoplasm reads low, the more the deeper
    deep = [shell_ratio(d, 0.22, 2 / 3) for d in (0.05, 0.2, 0.4)]
    assert 1 > deep[0] > deep[1] > deep[2] > 0


@pytest.mark.parametrize(
    ("args", "quantity"),
    [
        ((0.1, 0.01, 0.5), "E_cytoplasm / E_ZP"),
        ((0.1, 2.0, 0.5), "E_cytoplasm / E_ZP"),
        ((0.1, 0.2, 0.1), "Rp/h"),
        ((0.45, 0.2, 1 / 3), "depth / ZP thickness"),
    ],
)
def test_outside_the_table_names_the_quantity_and_range(args, quantity):
    with pytest.raises(InputError, match=r"within the table's range \[") as err:
        shell_ratio(*args)
    assert quantity in str(err.value)


def test_zona_modulus_undoes_the_table_and_the_curvature():
    # a fit with the probe's own radius reads E_ZP ratio / c; zona_modulus returns E_ZP
    e_zp, e_c, h, rp, r, d = 6.0, 1.32, 15.0, 8.0, 70.0, 2.4
    ratio = shell_ratio(d / h, e_c / e_zp, rp / h)
    for model in ("hertz_sphere", "hertz_paraboloid"):
        read = e_zp * ratio / curvature_factor(model, rp, r, d)
        assert zona_modulus(read, d, h, e_c, rp, r, model) == pytest.approx(e_zp, rel=1e-9)
    # the curvature factor of a paraboloid at small depth: sqrt(Rp / R*)
    c = curvature_factor("hertz_paraboloid", rp, r, 1e-3)
    assert c == pytest.approx(math.sqrt(rp / effective_radius_um(rp, r)), rel=1e-4)


def test_cone_table_returns_its_nodes_and_is_one_in_its_limits():
    t = load_cone_table()
    for e, column in zip(t.e_ratios, t.ratio, strict=True):
        for y, r in zip(t.y, column, strict=True):
            assert cone_shell_ratio(float(y), e) == pytest.approx(r, abs=1e-12)
        assert cone_shell_ratio(0.0, e) == pytest.approx(1.0, abs=1e-12)
    for y in (0.01, 0.1, 0.3):
        assert cone_shell_ratio(y, 1.0) == pytest.approx(1.0, abs=1e-12)
    # a softer cytoplasm and a deeper fit read lower
    assert cone_shell_ratio(0.2, 0.05) < cone_shell_ratio(0.2, 0.22) < cone_shell_ratio(0.1, 0.22)


def test_cone_zona_modulus_undoes_the_table_and_refuses_a_blunt_cone():
    e_zp, e_c, d, angle = 7.0, 1.55, 2.0, 10.0  # the seed's cone and moduli
    y = d * np.tan(np.radians(angle)) / 15.0
    e_fit = e_zp * cone_shell_ratio(y, e_c / e_zp)
    assert cone_zona_modulus(e_fit, d, angle, 15.0, e_c, 70.0) == pytest.approx(e_zp, rel=1e-10)
    # gap = a tan(alpha) / (2 R), a = 2 d tan(alpha) / pi
    tan = np.tan(np.radians(70.0))
    assert cone_curvature_gap(1.0, 70.0, 70.0) == pytest.approx(2 / np.pi * tan**2 / 140.0)
    deepest = CONE_CURVATURE_GAP * np.pi * 70.0 / tan**2  # 0.29 um for 70 deg
    cone_zona_modulus(5.0, 0.99 * deepest, 70.0, 15.0, 1.55, 70.0)
    with pytest.raises(InputError, match="curvature gap"):
        cone_zona_modulus(5.0, 1.01 * deepest, 70.0, 15.0, 1.55, 70.0)
    with pytest.raises(InputError, match=r"\(y\)"):
        cone_shell_ratio(0.31, 0.22)
    # sharper than 45 deg: the table is accepted to y = 0.1 only
    d_sharp = 0.101 * 15.0 / np.tan(np.radians(10.0))
    with pytest.raises(InputError, match="10 deg cone"):
        cone_zona_modulus(7.0, d_sharp, 10.0, 15.0, 1.55, 70.0)
    cone_zona_modulus(7.0, 0.099 * 15.0 / np.tan(np.radians(10.0)), 10.0, 15.0, 1.55, 70.0)


def test_dimitriadis_coefficients_and_closed_form():
    # eq. 12's first two numbers from Dimitriadis' alpha0 = -1.7795 (bonded, nu = 0.5)
    alpha0 = -1.7795
    first = (-2 * alpha0 / math.pi, 4 * alpha0**2 / math.pi**2)
    assert first == pytest.approx(be.DIMITRIADIS_BONDED[:2], abs=5e-4)
    # F/F_Hertz at x = sqrt(R d)/h = 0, 0.5, 1 (R = 4, h = 2: d = 0, 0.25, 1)
    f = be.dimitriadis_factor(np.array([0.0, 0.25, 1.0]), 4.0, 2.0)
    assert f == pytest.approx([1.0, 1 + 0.5665 + 0.32075 + 0.096125 + 0.00609375, 4.2825])
    # a fit of the paraboloid to d reads E (1 + sum c_k x_d^k 8/(8 + k)) (s^2 ~ d^3, x ~ d^1/2)
    x = math.sqrt(4.0 * 0.81) / 2.0
    closed = 1 + sum(c * x ** (k + 1) * 8 / (9 + k) for k, c in enumerate(be.DIMITRIADIS_BONDED))
    got = be.fit_factor("hertz_paraboloid", {"radius_um": 4.0}, 0.81, 2.0)
    assert got == pytest.approx(closed, rel=1e-4)
    # Garcia's cone: y = d tan(alpha)/h = 1 -> 1 + 0.721 + 0.650 + 0.491 + 0.225
    cone = be.garcia_cone_factor(np.array([2.0]), 45.0, 2.0)
    assert cone == pytest.approx([3.087])


def _case(
    tmp_path: Path,
    correction: str,
    model: str = "hertz_sphere",
    extra: str = "",
    angle: float = 35.0,
) -> Path:
    case = tmp_path / "case"
    (case / "curves").mkdir(parents=True, exist_ok=True)
    cone = {"half_angle_deg": angle}
    geometry = (
        "{ radius_um = 5.0 }" if model != "sneddon_cone" else f"{{ half_angle_deg = {angle} }}"
    )
    for i, e in enumerate((5.0, 7.0)):
        curve = indentation_curve(
            e,
            3.0,
            max_piezo_um=6.0,
            n_points=300,
            k_nN_per_um=1e3,
            model=model,
            geometry={"radius_um": 5.0} if model != "sneddon_cone" else cone,
        )
        write_curve(curve, case / "curves" / f"c{i}.csv")
    (case / "case.toml").write_text(
        f'kind = "afm_fit_files"\ndescription = "correction"\n[inputs]\ncurves = "curves"\n'
        f'model = "{model}"\ngeometry = {geometry}\ncurve_plots = "none"\n'
        f"max_indentation_um = 2.0\n{extra}[inputs.correction]\n{correction}\n"
    )
    return case


SHELL = 'type = "shelled_oocyte"\nzona_thickness_um = 15.0\ncytoplasm_modulus_kPa = 1.2\n'
SHELL += "cell_radius_um = 70.0"


def test_shelled_oocyte_option_through_the_case(tmp_path):
    case = _case(tmp_path, SHELL)
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    out = tmp_path / "out" / "case"
    with (out / "fits.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2
    header = list(rows[0])
    assert header[header.index("E_kPa") + 1] == "E_corrected_kPa"
    corrected = []
    for row in rows:
        e, d = float(row["E_kPa"]), float(row["max_indentation_um"])
        expected = zona_modulus(e, d, 15.0, 1.2, 5.0, 70.0, "hertz_sphere")
        assert float(row["E_corrected_kPa"]) == pytest.approx(expected, rel=1e-5)
        assert row["correction"] == "shelled_oocyte" and expected > e  # the shell reads low
        corrected.append(expected)
    material = read_material(out / "material_curves.toml")
    assert material.E_kPa == pytest.approx(np.mean(corrected), rel=1e-5)
    report = (out / "report.md").read_text()
    assert "shelled_oocyte: E_ZP from the FE table" in report


def test_shelled_oocyte_option_corrects_a_cone_fit_through_the_case(tmp_path):
    case = _case(tmp_path, SHELL, "sneddon_cone")
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    with (tmp_path / "out" / "case" / "fits.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2
    for row in rows:
        e, d = float(row["E_kPa"]), float(row["max_indentation_um"])
        expected = cone_zona_modulus(e, d, 35.0, 15.0, 1.2, 70.0)
        y = d * np.tan(np.radians(35.0)) / 15.0
        assert expected == pytest.approx(e / cone_shell_ratio(y, 1.2 / expected), rel=1e-9)
        assert float(row["E_corrected_kPa"]) == pytest.approx(expected, rel=1e-5)
        assert 1.0 < expected / e < 1.15  # y = 0.093: the shell reads a few percent low


def test_dimitriadis_option_through_the_case(tmp_path):
    case = _case(tmp_path, 'type = "dimitriadis_bonded"\nlayer_thickness_um = 8.0')
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    with (tmp_path / "out" / "case" / "fits.csv").open() as fh:
        for row in csv.DictReader(fh):
            e, d = float(row["E_kPa"]), float(row["max_indentation_um"])
            factor = be.fit_factor("hertz_sphere", {"radius_um": 5.0}, d, 8.0)
            assert float(row["E_corrected_kPa"]) == pytest.approx(e / factor, rel=1e-5)
            assert factor > 1.2  # x = sqrt(5 * 2)/8 = 0.4: a 20 % + bottom effect


@pytest.mark.parametrize(
    ("correction", "model", "extra", "field"),
    [
        (SHELL, "sneddon_cone:75", "", "inputs.max_indentation_um"),  # curvature gap 0.13
        (SHELL, "hertz_sphere", "nu = 0.45\n", "inputs.nu"),
        (SHELL.replace("15.0", "30.0"), "hertz_sphere", "", "Rp/h"),
        (SHELL.replace("15.0", "9.0"), "hertz_sphere", "", "inputs.max_indentation_um"),
        (SHELL.replace("70.0", "40.0"), "hertz_sphere", "", "correction.cell_radius_um"),
        ('type = "dimitriadis_bonded"\nlayer_thickness_um = 2.0', "hertz_sphere", "", "max_ind"),
        ('type = "garcia_bonded"\nlayer_thickness_um = 8.0', "hertz_sphere", "", "correction.type"),
    ],
)
def test_option_refuses_what_it_does_not_cover(tmp_path, correction, model, extra, field):
    model, _, angle = model.partition(":")
    case = _case(tmp_path, correction, model, extra, float(angle or 35.0))
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "ERROR" and field in result.reason, result.reason


@pytest.mark.slow
def test_the_tables_reproduce_fresh_fe_runs_off_their_nodes(tmp_path, monkeypatch):
    """Issue 28 C: fresh FE runs (their own mesh, fewer frames than the tables' 24, no cache)
    at a point on no node agree with the shipped sphere table within 1 %: Rp/h = 0.5,
    E_c/E_ZP = 0.3, d/h = 0.1, run to d/h = 0.1 in 5 frames, where the table's column runs to
    0.3 (measured 0.08 % off, 0.04 % off with 8 frames to 0.3 at 8 times the cost; 7 CPU s).
    The cone table's check off its nodes (a 60 deg cone at E_c/E_ZP = 0.3, y = 0.04: 0.037 %
    off) costs 84 CPU s, its steps cut back where the tip meets the zona: it runs in the heavy
    case afm_shell_correction (70 deg at E_c/E_ZP = 0.3, 60 deg at 0.22, five y; and more
    sphere points), with 24 frames."""
    from oocyte_fe.afm_corrections.table import column

    monkeypatch.setenv("OOCYTE_FE_CACHE", str(tmp_path))
    depth = np.array([0.1])
    layered, homogeneous = (column(e, 0.5, depth, run_to_h=0.1, frames=5) for e in (0.3, 1.0))
    sphere = layered.e_fit / homogeneous.e_fit
    assert shell_ratio(0.1, 0.3, 0.5) == pytest.approx(sphere[0], rel=0.01)
