"""Pierce-through curves from the user's own files: ``afm_fit_files`` with ``pierce = true``.

The curves are written here from the two-layer closed form (not afm/synthetic.py): Sneddon
cone (half angle 10 deg, nu 0.5) on a cantilever k; at each piezo position z the force solves
F = law(x) with x = z - F/k (brentq). The ZP rises from its contact X0 to the pierce force,
the force drops to a residual level and the cytoplasm is indented from the tip position after
the drop (reading A of afm/pierce.py): F = F_res + E_cyt shape(x - x_after), up to a trigger.
"""

from __future__ import annotations

import csv
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from typer.testing import CliRunner

from afm.curve import ForceCurve
from afm.pierce import fit_pierce
from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases

K = 70.0  # nN/um (0.07 N/m)
X0 = 4.0  # um, ZP contact
F_PIERCE, F_RES, F_TRIGGER = 8.0, 2.4, 12.0  # nN
CONE = 2.0 / math.pi * math.tan(math.radians(10.0)) / (1.0 - 0.5**2)  # F / (E delta^2)
CURVES = {"p1": (7.0, 1.55), "p2": (5.0, 2.0)}  # file -> (E_ZP, E_cyt) [kPa]
TOLERANCE = 0.01  # relative, both layers (measured: within 0.25 %)


def _force_at(z: float, law) -> float:
    return brentq(lambda f: f - law(z - f / K), -1.0, K * abs(z) + 100.0, xtol=1e-12)


def two_layer_curve(e_zp: float, e_cyt: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(piezo [um], force [nN] as measured: offset 0.3 nN, tilt 0.05 nN/um, noise 0.04 nN)."""

    def zp(x: float) -> float:
        return e_zp * CONE * max(x - X0, 0.0) ** 2

    z_pierce = X0 + math.sqrt(F_PIERCE / (e_zp * CONE)) + F_PIERCE / K
    x_after = z_pierce - F_RES / K

    def cytoplasm(x: float) -> float:
        return F_RES + e_cyt * CONE * max(x - x_after, 0.0) ** 2

    z_end = brentq(lambda z: _force_at(z, cytoplasm) - F_TRIGGER, z_pierce, z_pierce + 50.0)
    piezo = np.linspace(0.0, z_end, 1500)
    force = np.array([_force_at(z, zp if z < z_pierce else cytoplasm) for z in piezo])
    rng = np.random.default_rng(seed)
    return piezo, force + 0.3 + 0.05 * piezo + 0.04 * rng.standard_normal(piezo.size)


def _write(path: Path, piezo: np.ndarray, force: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = ["# spring_constant_N_per_m = 0.07", "piezo_um,force_nN"]
    lines += [f"{z:.7g},{f:.7g}" for z, f in zip(piezo, force, strict=True)]
    path.write_text("\n".join(lines) + "\n")


def _case(folder: Path, extra: str = "pierce = true", model: str = "sneddon_cone") -> Path:
    for seed, (name, (e_zp, e_cyt)) in enumerate(CURVES.items()):
        _write(folder / "curves" / "oocyte" / f"{name}.csv", *two_layer_curve(e_zp, e_cyt, seed))
    # a plain cone curve (no drop): E = 6 kPa up to 8 nN
    piezo = np.linspace(0.0, 7.0, 1500)
    force = np.array([_force_at(z, lambda x: 6.0 * CONE * max(x - X0, 0.0) ** 2) for z in piezo])
    _write(folder / "curves" / "oocyte" / "p3_no_drop.csv", piezo, force + 0.3)
    (folder / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "pierce"\n[inputs]\ncurves = "curves"\n'
        f'model = "{model}"\ngeometry = {{ half_angle_deg = 10.0 }}\nnu = 0.5\n{extra}\n'
    )
    return folder


def test_case_gives_both_moduli_per_curve_and_per_group(tmp_path):
    case = _case(tmp_path / "pierce")
    assert load_case(case).inputs.pierce is True
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    out = tmp_path / "out" / "pierce"
    with (out / "fits.csv").open() as fh:
        rows = {Path(r["file"]).stem: r for r in csv.DictReader(fh)}
    for name, (e_zp, e_cyt) in CURVES.items():
        row = rows[name]
        assert row["quality"] == "good", row["rating"]
        assert row["rating"].startswith("ZP good") and "; cytoplasm good" in row["rating"]
        assert float(row["E_kPa"]) == pytest.approx(e_zp, rel=TOLERANCE)
        assert float(row["E_cytoplasm_kPa"]) == pytest.approx(e_cyt, rel=TOLERANCE)
        assert float(row["contact_from_start_um"]) == pytest.approx(X0, abs=0.05)
        assert (out / "curve_plots" / f"{name}_pierce.png").is_file()
    # the curve without a drop: refused as such on its row, not fitted as one layer
    plain = rows["p3_no_drop"]
    assert (plain["quality"], plain["E_kPa"], plain["E_cytoplasm_kPa"]) == ("error", "", "")
    assert "no pierce detected" in plain["error"]
    metrics = json.loads((out / "metrics.json").read_text())["metrics"]
    assert (metrics["n_fitted"], metrics["n_failed"], metrics["n_no_pierce"]) == (2, 1, 1)
    # one material per layer: the mean of the two curves' moduli
    zp = tomllib.loads((out / "material_oocyte_zp.toml").read_text())["material"]
    cyt = tomllib.loads((out / "material_oocyte_cytoplasm.toml").read_text())["material"]
    assert zp["E_kPa"] == pytest.approx(6.0, rel=TOLERANCE)
    assert cyt["E_kPa"] == pytest.approx(1.775, rel=TOLERANCE)
    assert (zp["name"], cyt["name"], cyt["nu"]) == ("oocyte_zp", "oocyte_cytoplasm", 0.5)
    assert not (out / "material_oocyte.toml").exists()
    report = (out / "report.md").read_text()
    assert "| oocyte | cytoplasm | 2 | 0 |" in report
    assert "1 without a detectable pierce" in report


def test_without_pierce_the_same_curves_are_one_poor_layer(tmp_path):
    """What the tester saw before the option: one layer, rated poor, no cytoplasm."""
    case = _case(tmp_path / "one_layer", extra="")
    run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    with (tmp_path / "out" / "one_layer" / "fits.csv").open() as fh:
        row = next(r for r in csv.DictReader(fh) if "p1" in r["file"])
    assert row["quality"] == "poor" and row["E_cytoplasm_kPa"] == ""
    assert float(row["E_kPa"]) < 0.5 * CURVES["p1"][1]


@pytest.mark.parametrize(
    ("model", "extra", "line"),
    [
        (
            "flat_punch",
            "pierce = true",
            "inputs.model: expected a tip for pierce-through curves, one of hertz_paraboloid, "
            "hertz_sphere, pyramid, pyramid_3s, sneddon_cone (under a force linear in depth the "
            "cytoplasm's contact reference and force level are one parameter), with pierce = "
            "true, got 'flat_punch'",
        ),
        (
            "sneddon_cone",
            'pierce = true\nanalysis = "nanite"',
            'inputs.analysis: expected analysis = "default" with pierce = true (both layers are '
            "fitted by afm.fit), got 'nanite'",
        ),
        (
            "sneddon_cone",
            'pierce = true\nviscoelastic = { relaxation = "sls" }',
            "inputs.viscoelastic: expected no viscoelastic table with pierce = true (a ramp fit "
            "in time takes the whole curve as one layer)",
        ),
        (
            "sneddon_cone",
            'pierce = true\nmax_indentation_um = 1.0\ncorrection = { type = "garcia_bonded", '
            "layer_thickness_um = 20.0 }",
            "inputs.correction: expected no correction table with pierce = true (a correction "
            "takes one layer's modulus, the other's given)",
        ),
    ],
)
def test_validate_refuses_what_pierce_cannot_take_in_one_line(tmp_path, model, extra, line):
    case = _case(tmp_path / "bad", extra=extra, model=model)
    if model == "flat_punch":
        text = (case / "case.toml").read_text().replace("half_angle_deg", "radius_um")
        (case / "case.toml").write_text(text)
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [f"invalid {case}/case.toml: {line}"]


def test_fit_pierce_refuses_a_linear_tip():
    piezo, force = two_layer_curve(*CURVES["p1"])
    with pytest.raises(InputError, match="model: expected a tip for pierce-through curves"):
        fit_pierce(ForceCurve(piezo, force, K, "p1.csv"), "flat_punch", {"radius_um": 2.0})


def test_the_least_drop_taken_as_the_pierce_is_an_input(tmp_path):
    """The drop of these curves (8.0 -> 2.4 nN) is 0.47 of their force range (0-12 nN):
    pierce_min_drop_fraction = 0.6 finds no pierce in any curve and says so with the value;
    0.3 finds both, their moduli within 1 % of the truth (as with the default 0.1)."""
    rows = {}
    for fraction in (0.6, 0.3):
        case = _case(
            tmp_path / f"f{fraction}", f"pierce = true\npierce_min_drop_fraction = {fraction}"
        )
        run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
        with (tmp_path / "out" / case.name / "fits.csv").open() as fh:
            rows[fraction] = {Path(r["file"]).stem: r for r in csv.DictReader(fh)}
    for name in CURVES:
        assert rows[0.6][name]["quality"] == "error"
        assert "a force drop of more than 0.6 of the force range" in rows[0.6][name]["error"]
        e_zp, e_cyt = CURVES[name]
        assert float(rows[0.3][name]["E_kPa"]) == pytest.approx(e_zp, rel=TOLERANCE)
        assert float(rows[0.3][name]["E_cytoplasm_kPa"]) == pytest.approx(e_cyt, rel=TOLERANCE)
