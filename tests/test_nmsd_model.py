"""NMSD model: lattice, spring law (eqs 3-5), stability of the implicit step, press, errors."""

from __future__ import annotations

import numpy as np
import pytest

from nmsd.calibration import fit_metrics
from nmsd.cytoplasm_loss import aspirated_length_for, loss_fraction
from nmsd.errors import NmsdDivergence, NmsdInputError
from nmsd.integrator import BackwardEulerStepper, explicit_time_step_limit
from nmsd.lattice import Lattice, circular_lattice
from nmsd.material_point import locate
from nmsd.parameters import NmsdParameters
from nmsd.pipette import Pipette
from nmsd.press import press_setup, simulate_press
from nmsd.spring import link_force
from nmsd.tableII import read_force_displacement

TABLE = "cases/nmsd_calibration_tableII/nmsd_force_displacement_tableII.csv"


def test_default_lattice_has_231_nodes_with_8_links_inside():
    lat = circular_lattice()
    assert lat.n_nodes == 231
    assert lat.degree.max() == 8
    # mirror symmetric about the pipette axis
    mirrored = lat.nodes * [1, -1]
    assert np.allclose(
        np.sort(mirrored.view(complex).ravel()), np.sort(lat.nodes.view(complex).ravel())
    )


def test_spring_force_and_slope_continuous_at_critical_strain():
    k1, k2, c = 3.0, 400.0, 0.3
    eps = 1e-9
    f, df = link_force(np.array([c - eps, c + eps, -c - eps]), k1, k2, c)
    assert f[0] == pytest.approx(k1 * c + k2 * c**3, rel=1e-6)  # A, eq 4
    assert f[1] == pytest.approx(f[0], rel=1e-6)
    assert df[1] == pytest.approx(k1 + 3 * k2 * c**2)  # B, eq 5
    assert df[0] == pytest.approx(df[1], rel=1e-6)
    assert f[2] == pytest.approx(-f[1], rel=1e-6)  # odd


def test_link_tangent_matches_finite_difference():
    lat = circular_lattice(40.0, 5)
    setup = press_setup(lat, n_steps=2)
    stepper = BackwardEulerStepper(lat, NmsdParameters(), setup.pipette, setup.held)
    rng = np.random.default_rng(1)
    x = lat.nodes + rng.normal(scale=0.5, size=lat.nodes.shape)
    f0, k = stepper.internal_force(x)
    e = 0
    a, b = lat.edges[e]
    h = 1e-6
    xp = x.copy()
    xp[a, 0] += h
    fp, _ = stepper.internal_force(xp)
    # d(force on a)/d(x_a) from the link e alone cannot be isolated; compare the full column
    col = (fp - f0).ravel() / h
    dense = np.zeros(2 * lat.n_nodes)
    for j, (p, q) in enumerate(lat.edges):
        for node, sign in ((p, 1), (q, -1)):
            if node == a:
                dense[2 * p : 2 * p + 2] += sign * k[j][:, 0]
                dense[2 * q : 2 * q + 2] -= sign * k[j][:, 0]
    assert np.allclose(col, dense, rtol=1e-4, atol=1e-4 * np.abs(dense).max())


def test_backward_euler_goes_far_beyond_explicit_limit_and_stays_bounded():
    setup = press_setup(n_steps=10)
    params = NmsdParameters(k1=50.0, k2=5000.0, d0=1.0, d1=0.0)
    stepper = BackwardEulerStepper(setup.lattice, params, setup.pipette, setup.held)
    dt_explicit = explicit_time_step_limit(stepper)
    dt = 65.0 / 30.0 / 10
    assert dt > 1e4 * dt_explicit
    result = setup.run(params)
    assert np.isfinite(result.force_nN).all()
    assert np.abs(result.positions - setup.lattice.nodes).max() < 2 * setup.travel_um


def test_press_force_zero_before_contact_and_symmetric_field():
    setup = press_setup(n_steps=20, gap_um=5.0, travel_um=20.0)
    params = NmsdParameters(k1=20.0, k2=2000.0, d0=1.0, d1=0.05)
    r = setup.run(params, record_um=[4.0, 20.0])
    assert r.force_at([4.0])[0] == 0.0
    assert r.force_nN[-1] > 0
    x = r.snapshots[20.0]
    lat = setup.lattice
    # mirror image of the deformed lattice about the axis is the deformed lattice
    ref = lat.nodes[:, 0] + 1j * lat.nodes[:, 1]
    order = np.argsort(ref)
    mirror = np.argsort(np.conj(ref))
    assert np.allclose(x[order] * [1, -1], x[mirror], atol=1e-4)


def test_faster_press_needs_more_force():
    setup = press_setup(n_steps=15, travel_um=30.0)
    params = NmsdParameters(k1=20.0, k2=2000.0, d0=5.0, d1=0.1)
    slow = setup.run(params, speed_um_s=10.0).force_nN[-1]
    fast = setup.run(params, speed_um_s=90.0).force_nN[-1]
    assert fast > slow > 0


def test_material_point_follows_rigid_translation():
    lat = circular_lattice()
    points = np.array([[10.0, 5.0], [-20.0, 30.0]])
    carried = locate(lat, points)
    assert np.allclose(carried.positions(lat.nodes + [3.0, -2.0]), points + [3.0, -2.0])


def test_paper_model_column_rmse_is_0p51_uN():
    data = read_force_displacement(TABLE)
    m = fit_metrics(data.paper_model_nN, data.force_nN)
    assert m.rmse_nN == pytest.approx(513.1, abs=0.5)
    assert m.similarity > 0.999


def test_cytoplasm_loss_inverts():
    frac = loss_fraction(30.0, 20.0, 115.625)
    assert aspirated_length_for(frac, 20.0, 115.625) == pytest.approx(30.0)
    assert frac == pytest.approx(0.25 * 400 * 30 / (115.625**3 / 6))


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (
            lambda: Lattice(np.zeros((5, 2)) + np.arange(5)[:, None], np.array([[0, 1]]), 1.0),
            "nodes",
        ),
        (
            lambda: Lattice(
                np.column_stack([np.arange(8.0), np.zeros(8)]),
                np.array([[i, i + 1] for i in range(6)]),
                5.0,
            ),
            "edges",
        ),
        (lambda: NmsdParameters(dl_c=0.0), "dl_c"),
        (lambda: NmsdParameters(node_mass=-1.0), "node_mass"),
        (lambda: press_setup(gap_um=-3.0), "gap_um"),
    ],
)
def test_bad_input_names_the_field(make, field):
    with pytest.raises(NmsdInputError, match=field):
        make()


def test_pipette_starting_inside_is_refused():
    setup = press_setup(n_steps=2)
    inside = Pipette(start=(40.0, 0.0))
    with pytest.raises(NmsdInputError, match="outside the cell"):
        simulate_press(setup.lattice, NmsdParameters(), inside, setup.held, n_steps=2)


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("displacement_um,force_experiment_uN\n0,0\n2,1\n1,2\n", "displacement_um"),
        ("displacement_um,force_uN\n0,0\n1,1\n", "force_experiment_uN"),
    ],
)
def test_bad_csv(tmp_path, text, field):
    f = tmp_path / "t.csv"
    f.write_text(text)
    with pytest.raises(NmsdInputError, match=field):
        read_force_displacement(f)


def test_blow_up_names_step_and_time_step():
    setup = press_setup(n_steps=1, travel_um=60.0, contact_stiffness=1e12)
    params = NmsdParameters(k1=1e6, k2=1e9, d0=0.0, d1=0.0, node_mass=0.0, dl_c=5.0)
    with pytest.raises(NmsdDivergence, match=r"step 1 .*time step of"):
        setup.run(params)
