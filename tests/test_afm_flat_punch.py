"""Sneddon's flat cylindrical punch (``flat_punch``): F = 2 a E/(1 - nu^2) delta.

Curves are written here from the closed form, not by afm/synthetic.py: for a punch of face
radius a on a spring k the force at piezo position z past contact x0 solves F = S (z - F/k -
x0) with S = 2 a E/(1 - nu^2), so F = S (z - x0) / (1 + S/k) exactly.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from afm.creep import fit_creep_tip
from afm.creep_data import CreepData
from afm.curve import ForceCurve
from afm.fit import fit_indentation
from afm.models import MODELS, get_model
from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.run import plan, run_cases

K = 70.0  # nN/um (0.07 N/m)
X0 = 5.0  # um, contact (piezo)
RADIUS = 2.0  # um
E_TRUE = 2.0  # kPa


def punch_curve(e_kPa: float = E_TRUE, nu: float = 0.5, noise: float = 0.01, seed: int = 3):
    """Approach of 8 um, contact at X0, offset 0.3 nN, tilt 0.05 nN/um, noise as a fraction
    of the peak force: (piezo [um], force [nN] as measured)."""
    stiffness = 2.0 * RADIUS * e_kPa / (1.0 - nu**2)  # nN/um
    piezo = np.linspace(0.0, 8.0, 1500)
    force = stiffness * np.clip(piezo - X0, 0.0, None) / (1.0 + stiffness / K)
    rng = np.random.default_rng(seed)
    measured = force + 0.3 + 0.05 * piezo + noise * force.max() * rng.standard_normal(piezo.size)
    return piezo, measured


def test_force_is_the_closed_form_in_nanonewtons():
    # 2 a E/(1 - nu^2) delta, a = 2 um, E = 3 kPa, nu = 0.3, delta = 0.5 um: 6.593... nN
    got = get_model("flat_punch").force(np.array([0.5, -1.0]), 3.0, {"radius_um": 2.0}, 0.3)
    assert got[0] == pytest.approx(2 * 2.0 * 3.0 / (1 - 0.09) * 0.5, rel=1e-14)
    assert got[1] == 0.0
    # SI: 2 * 2e-6 m * 3000 Pa / 0.91 * 0.5e-6 m = N; x 1e9 -> nN
    assert got[0] == pytest.approx(2 * 2e-6 * 3000 / 0.91 * 0.5e-6 * 1e9, rel=1e-12)
    assert MODELS["flat_punch"].exponent == 1.0


@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_noisy_curve_gives_the_modulus_within_2_percent(nu):
    piezo, force = punch_curve(nu=nu)
    fit = fit_indentation(
        ForceCurve(piezo, force, K, "punch.csv"), "flat_punch", {"radius_um": RADIUS}, nu
    )
    assert fit.E_kPa == pytest.approx(E_TRUE, rel=0.02)
    assert fit.contact_point_um == pytest.approx(X0, abs=0.05)  # the tip is at the piezo at F = 0
    assert fit.quality == "good"


def test_creep_of_a_punch_follows_lee_radok_exactly():
    # J(t) = J0 + J1 (1 - exp(-t/0.5 s)) [1/kPa]; the contact radius is constant, so
    # delta(t) = (1 - nu) F0 J(t) / (4 a): E0 = 2 (1 + nu) / J0, E_inf = 2 (1 + nu) / (J0 + J1)
    j0, j1, nu, f0 = 3.0 / 7.0, 0.2, 0.5, 5.0
    t = np.linspace(0.0, 10.0, 2001)
    compliance = j0 + j1 * (1.0 - np.exp(-t / 0.5))
    delta = (1.0 - nu) * f0 * compliance / (4.0 * RADIUS)
    noisy = delta * (1.0 + 0.002 * np.random.default_rng(1).standard_normal(t.size))
    fit = fit_creep_tip(
        CreepData(t, np.full(t.size, f0), noisy, "hold.csv"),
        "flat_punch",
        {"radius_um": RADIUS},
        nu,
    )
    assert fit.E0_kPa == pytest.approx(2 * (1 + nu) / j0, rel=0.01)
    assert fit.E_inf_kPa == pytest.approx(2 * (1 + nu) / (j0 + j1), rel=0.01)


@pytest.mark.parametrize(
    ("geometry", "field"),
    [({"radius_um": 0.0}, "radius_um"), ({"radius_um": -2.0}, "radius_um"), ({}, "radius_um")],
)
def test_radius_must_be_positive_and_given(geometry, field):
    with pytest.raises(InputError, match=field) as err:
        MODELS["flat_punch"].check_geometry(geometry, "case")
    assert "\n" not in str(err.value)


def _case(folder: Path, geometry: str) -> Path:
    piezo, force = punch_curve()
    (folder / "curves" / "cell").mkdir(parents=True)
    lines = ["# spring_constant_N_per_m = 0.07", "piezo_um,force_nN"]
    lines += [f"{z:.6g},{f:.6g}" for z, f in zip(piezo, force, strict=True)]
    (folder / "curves" / "cell" / "f1.csv").write_text("\n".join(lines) + "\n")
    (folder / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "punch"\n[inputs]\ncurves = "curves"\n'
        f'model = "flat_punch"\ngeometry = {geometry}\nnu = 0.5\n'
    )
    return folder


def test_user_route_fits_the_punch(tmp_path):
    case = _case(tmp_path / "punch", "{ radius_um = 2.0 }")
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    with (tmp_path / "out" / "punch" / "fits.csv").open() as fh:
        [row] = list(csv.DictReader(fh))
    assert (row["model"], row["tip"], row["quality"]) == ("flat_punch", "radius_um=2", "good")
    assert float(row["E_kPa"]) == pytest.approx(E_TRUE, rel=0.02)
    assert math.isclose(float(row["contact_from_start_um"]), X0, abs_tol=0.05)


@pytest.mark.parametrize(
    ("geometry", "line"),
    [
        (
            "{ radius_um = 0.0 }",
            "inputs.geometry.radius_um: expected a value in (0, inf) um, got 0.0",
        ),
        ("{}", "inputs.geometry.radius_um: expected this geometry key for model flat_punch"),
    ],
)
def test_validate_refuses_a_bad_radius_in_one_line(tmp_path, geometry, line):
    case = _case(tmp_path / "punch", geometry)
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [f"invalid {case}/case.toml: {line}"]
