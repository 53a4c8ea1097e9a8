"""Small-strain kinematics (``kinematics = "small_strain"``): the linear solid and Sneddon's
contact (a pressure along the tool's axis), against closed forms.

Tolerances: tangents to finite differences (1e-6 relative); the 10 deg cone on a 2 mm cell
(the half-space limit) within 1 % of Sneddon at contact radii of 2.7-5.6 elements (mesh
study in docs/fe.md: 0.9983 / 0.9992 / 0.9995 at h = 0.04 / 0.02 / 0.01 um and d = 2 um);
Hertz's sphere (exact, Sneddon) within 0.6 % at d/R* = 0.01, where the finite-strain FE
reads 0.8 % low.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import closed_form_metrics, push_force_nN
from oocyte_fe.experiment.tools import cone_profile
from oocyte_fe.fe.contact import Contact, ContactLaw, ContactState, evaluate
from oocyte_fe.fe.kinematics import Kinematics
from oocyte_fe.fe.material import Material, Prony, ViscousHistory, response
from oocyte_fe.fe.obstacles import Circle, Linearised, Polyline
from oocyte_fe.runner.casefile import load_case

TAN10 = float(np.tan(np.radians(10.0)))


@pytest.mark.parametrize("with_history", [False, True])
def test_linear_solid_tangent_matches_finite_differences(with_history: bool) -> None:
    rng = np.random.default_rng(1)
    g5 = 0.3 * rng.standard_normal((5, 1, 1))
    p = np.array([[0.4]])
    mat = Material(2.0, 0.45, Prony((0.3, 0.2), (0.1, 1.0)))
    hist = None
    if with_history:
        s = 0.1 * rng.standard_normal((3, 3, 1, 1))
        s[:2, 2] = s[2, :2] = 0.0
        hist = ViscousHistory(S0=s + s.swapaxes(0, 1), h=np.stack([s, 2 * s]))
    res = response(Kinematics.from_grad5(g5, small=True), p, mat, hist, 0.05)
    for q in range(5):
        dg = np.zeros_like(g5)
        dg[q] = 1e-7
        plus = response(Kinematics.from_grad5(g5 + dg, small=True), p, mat, hist, 0.05)
        minus = response(Kinematics.from_grad5(g5 - dg, small=True), p, mat, hist, 0.05)
        np.testing.assert_allclose(
            (plus.P5 - minus.P5)[:, 0, 0] / 2e-7, res.A5[:, q, 0, 0], rtol=1e-6, atol=1e-8
        )
        dJ = (plus.JFinvT5 * 0 + Kinematics.from_grad5(g5 + dg, small=True).J) - (
            Kinematics.from_grad5(g5 - dg, small=True).J
        )
        assert dJ[0, 0] / 2e-7 == pytest.approx(res.JFinvT5[q, 0, 0], abs=1e-8)


def test_linear_solid_is_the_neo_hookean_solid_linearised() -> None:
    """At F = I the two tangents are equal (2 mu dev sym), and for a small gradient the two
    stresses agree to its square."""
    mat = Material(3.0, 0.5)
    zero = np.zeros((5, 1, 1))
    p = np.zeros((1, 1))
    finite = response(Kinematics.from_grad5(zero), p, mat, None, 0.1)
    small = response(Kinematics.from_grad5(zero, small=True), p, mat, None, 0.1)
    np.testing.assert_allclose(small.A5, finite.A5, atol=1e-12)
    g5 = 1e-5 * np.array([1.0, -2.0, 0.5, 0.3, -1.3])[:, None, None]
    finite = response(Kinematics.from_grad5(g5), p, mat, None, 0.1).P5
    small = response(Kinematics.from_grad5(g5, small=True), p, mat, None, 0.1).P5
    np.testing.assert_allclose(small, finite, atol=1e-8)


def test_sneddon_contact_measures_the_gap_along_the_axis() -> None:
    """g = x . a - f(x . e): a 10 deg cone with its apex at y = 5 and a sphere of radius 10
    centred at y = 15 (their fronts 5 + r cot 10 and 15 - sqrt(100 - r^2)), tools above."""
    cone = Linearised(Polyline(tuple(cone_profile(10.0, 0.0, 20.0, 5.0))), (0.0, -1.0))
    x = np.array([[0.0, 0.5, 1.0, 30.0], [4.0, 4.0, 6.0, 0.0]])
    gap = cone.distance(x)[0]
    np.testing.assert_allclose(gap[:3], [1.0, 1.0 + 0.5 / TAN10, 1.0 / TAN10 - 1.0], rtol=1e-12)
    assert gap[3] == np.inf  # beyond the cone's flank: no contact
    sphere = Linearised(Circle((0.0, 15.0), 10.0), (0.0, -1.0))
    r = np.array([0.0, 6.0])
    gap = sphere.distance(np.stack([r, [4.0, 4.0]]))[0]
    np.testing.assert_allclose(gap, 15.0 - np.sqrt(100.0 - r**2) - 4.0, rtol=1e-12)


def test_sneddon_contact_ignores_the_lateral_displacement_and_pushes_along_the_axis() -> None:
    contact = Contact("b", Linearised(Circle((0.0, 15.0), 10.0), (0.0, -1.0)), ContactLaw(50.0))
    X = np.array([[[1.0, 2.0]], [[5.5, 5.5]]])
    state = ContactState(np.zeros_like(X), np.zeros((1, 2)), 0.0)
    u = np.array([[[0.0, 0.0]], [[0.1, 0.2]]])
    ev = evaluate(contact, X, u, state, 0.0)
    moved = evaluate(contact, X, u + np.array([[[0.3, -0.2]], [[0.0, 0.0]]]), state, 0.0)
    np.testing.assert_array_equal(moved.pressure, ev.pressure)
    front = 15.0 - np.sqrt(100.0 - X[0, 0] ** 2)
    np.testing.assert_allclose(ev.pressure[0], 50.0 * (X[1, 0] + u[1, 0] - front), rtol=1e-12)
    np.testing.assert_array_equal(ev.normal[:, 0], [[0.0, 0.0], [-1.0, -1.0]])
    # k_nn = d lambda / d(-u_y): the tangent along the axis
    du = np.array([[[0.0, 0.0]], [[1e-7, 1e-7]]])
    plus = evaluate(contact, X, u + du, state, 0.0).pressure
    np.testing.assert_allclose((plus - ev.pressure) / 1e-7, ev.k_nn, rtol=1e-6)


def _cone_on_half_space(refine_um: float = 0.04) -> dict:
    t = [0.0, 0.25, 0.5, 0.75, 1.0]
    return {
        "kinematics": "small_strain",
        "cell": {
            "outer_diameter_um": 2000.0,
            "mesh_size_um": 125.0,
            "refine_size_um": refine_um,
            "refine_half_angle_deg": 0.02,
            "refine_depth_um": 0.5,
            "curved_edges": False,
            "materials": {"cytoplasm": {"E_kPa": 1.0, "nu": 0.5}},
        },
        "tools": {
            "tip": {
                "type": "cone",
                "half_angle_deg": 10.0,
                "penalty_factor": 100.0,
                "displacement_um": {"time_s": t, "value": [2.0 * x for x in t]},
            },
            "dish": {"type": "holding_pipette", "side": "bottom", "half_width_um": 500.0},
        },
        "time": {"duration_s": 1.0, "frames": 4},
    }


def test_sharp_cone_on_a_half_space_gives_sneddon() -> None:
    """The seed's 10 deg cone to 2 um on a 2 mm cell (a/R = 2e-4): F = 2/pi E/(1 - nu^2)
    tan(alpha) d^2 at every frame within 1 %, and afm's Sneddon fit reads E within 1 %
    (the finite-strain FE cannot go beyond 0.2 um here, docs/fe.md)."""
    result = run_experiment(Experiment.model_validate(_cone_on_half_space()))
    assert result.success
    d = result.advance_um["tip"][1:]
    F = push_force_nN(result, "tip")[1:]
    sneddon = 2.0 / np.pi * 1.0 / 0.75 * TAN10 * d**2
    np.testing.assert_allclose(F / sneddon, 1.0, rtol=0.01)
    assert closed_form_metrics(result)["cone_fit_modulus_kPa"] == pytest.approx(1.0, rel=0.01)


def test_hertz_sphere_in_its_limit_small_strain() -> None:
    """A 10 um sphere 0.1 um into a 2 mm cell (d/R* = 0.01): within 0.6 % of Sneddon's exact
    sphere, closer than the finite-strain FE (0.992, docs/fe.md)."""
    exp = {
        "kinematics": "small_strain",
        "cell": {
            "outer_diameter_um": 2000.0,
            "mesh_size_um": 125.0,
            "refine_size_um": 0.1,
            "refine_half_angle_deg": 0.15,
            "refine_depth_um": 2.6,
            "curved_edges": False,
            "materials": {"cytoplasm": {"E_kPa": 1.0, "nu": 0.5}},
        },
        "tools": {
            "probe": {
                "type": "sphere",
                "radius_um": 10.0,
                "penalty_factor": 100.0,
                "displacement_um": {"time_s": [0.0, 1.0], "value": [0.0, 0.1]},
            },
            "dish": {"type": "holding_pipette", "side": "bottom", "half_width_um": 500.0},
        },
        "time": {"duration_s": 1.0, "frames": 2},
    }
    metrics = closed_form_metrics(run_experiment(Experiment.model_validate(exp)))
    assert metrics["sphere_force_ratio"] == pytest.approx(1.0, abs=0.006)


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"friction": 0.2}, "tools.tip.friction"),
        ({"type": "wedge_pipette", "width_um": 5.0, "tip_angle_deg": 30.0}, "tools.tip"),
    ],
)
def test_small_strain_takes_frictionless_indenters_only(tmp_path: Path, change, named) -> None:
    inputs = copy.deepcopy(_cone_on_half_space())
    tip = inputs["tools"]["tip"]
    if "type" in change:
        tip.pop("half_angle_deg")
    tip.update(change)
    (tmp_path / "case.toml").write_text(
        tomli_w.dumps({"kind": "fe_experiment", "description": "test", "inputs": inputs})
    )
    with pytest.raises(InputError) as err:
        load_case(tmp_path)
    assert "case.toml" in str(err.value) and named in str(err.value)
