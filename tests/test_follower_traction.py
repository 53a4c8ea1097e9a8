"""A flow's traction with its normal part as a follower pressure (``follower = true``).

Closed form at finite strain: the homogeneous pure shear ``F = diag(lambda, 1 / lambda)`` of an
incompressible neo-Hookean disc (``mu = E / 3``) carries the nominal traction ``P N`` of
``P = diag(s, -s)``, ``s = mu (lambda - 1 / lambda)``. Split it into a follower pressure ``p``
on the current surface (Nanson, J = 1: force ``-p cof(F) N dS``) read at the current polar
angle, and a dead tangential part: ``p = -(P N . N) / (F^-T N . N)`` at each reference point,
the table's row at angle ``a`` carrying the pressure of the point whose CURRENT angle is ``a``
and the tangential part of the point whose REFERENCE angle is ``a``. Loaded so, the cell must
take the pure shear: b/a = ``lambda^-2``, smallest stretch ``1 / lambda`` (tolerance 0.1 %).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.microchannel.elastic_junction import elastic_cell_at_junction

R = 70.0


def _table(path: Path, t: np.ndarray, a: np.ndarray) -> Path:
    rows = [
        f"{np.degrees(ai):.6f},{R * np.cos(ai):.9f},{R * np.sin(ai):.9f},{ti[0]:.12g},{ti[1]:.12g}"
        for ai, ti in zip(a, t, strict=True)
    ]
    path.write_text("arc_angle_deg,x_um,y_um,t_x_kPa,t_y_kPa\n" + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("s_over_mu", [0.3, 0.9])
def test_follower_pressure_gives_the_pure_shear_at_finite_strain(tmp_path: Path, s_over_mu):
    """The module's closed form at s/mu = 0.3 and 0.9 (b/a 0.742 and 0.418, stretch 0.65):
    measured within 4e-5 / 2.5e-5 (b/a) and 1.4e-5 / 1.7e-4 (stretch); the same table as a
    dead load gives b/a 0.44 % off at 0.3."""
    E = 1.0
    s = s_over_mu * E / 3.0
    lam = (s_over_mu + np.sqrt(s_over_mu**2 + 4.0)) / 2.0
    a = np.radians(np.arange(0.0, 360.0, 1.0))
    N = np.column_stack([np.cos(a), np.sin(a)])
    PN, FiTN = N * [s, -s], N * [1.0 / lam, lam]
    p_ref = -np.einsum("ij,ij->i", PN, N) / np.einsum("ij,ij->i", FiTN, N)  # at reference a
    current = np.arctan2(np.sin(a) / lam, lam * np.cos(a)) % (2 * np.pi)
    p_row = np.interp(a, current, p_ref, period=2 * np.pi)  # at current angle a
    need = PN + p_ref[:, None] * FiTN  # what the dead part must carry at reference a
    tangential = need - np.einsum("ij,ij->i", need, N)[:, None] * N
    csv = _table(tmp_path / "t.csv", -p_row[:, None] * N + tangential, a)
    cell = elastic_cell_at_junction(csv, tmp_path, zona_kPa=E, cytoplasm_kPa=E, follower=True)
    assert cell.experiment.success
    assert cell.b_over_a == pytest.approx(lam**-2, rel=1e-3)
    assert cell.smallest_stretch == pytest.approx(1.0 / lam, rel=1e-3)
    dead = elastic_cell_at_junction(csv, tmp_path / "dead", zona_kPa=E, cytoplasm_kPa=E)
    assert abs(dead.b_over_a - lam**-2) > 0.002  # the same table read as a dead load differs


def _pushed_cell(folder: Path):
    """The free cell (E = 1 kPa) under the follower pressure p = 0.05 cos theta + 0.08 cos 2
    theta (kPa)."""
    a = np.radians(np.arange(0.0, 360.0, 5.0))
    N = np.column_stack([np.cos(a), np.sin(a)])
    p = 0.05 * np.cos(a) + 0.08 * np.cos(2 * a)
    csv = _table(folder / "t.csv", -p[:, None] * N, a)
    return elastic_cell_at_junction(csv, folder, zona_kPa=1.0, cytoplasm_kPa=1.0, follower=True)


def test_a_pushed_cell_under_a_follower_load_leaves_nothing_to_its_pins(tmp_path: Path):
    """A normal traction with a net push, ``p = P1 cos theta + s cos 2 theta``, on the free
    cell as a follower: its resultant changes as the cell deforms (by more than 1 % here); the
    translation relief takes the change, so the pins' reaction (the residual at the pinned
    degrees of freedom) stays at the solver's tolerance: measured 1.1e-5 of the push, asserted
    below 1e-3 (the change the relief takes is above 1e-2)."""
    result = _pushed_cell(tmp_path).experiment
    assert result.success
    push = np.linalg.norm(result.load_force_nN["flow"][-1])
    relief = np.linalg.norm(result.load_force_nN["translation relief"][-1])
    assert push == pytest.approx(np.pi * R * 0.05, rel=0.05)  # pi R P1 on the round cell
    assert relief > 0.01 * push
    problem, frame = result.problem, result.frames[-1]
    r, _, _ = problem.residual(frame.x, frame.t, 1.0)
    assert np.abs(r[problem.fixed_dofs]).max() < 1e-3 * push


def test_a_follower_traction_needs_a_plane_strain_cell(tmp_path: Path):
    from oocyte_fe.experiment import Experiment

    a = np.radians(np.arange(0.0, 180.1, 10.0))
    csv = tmp_path / "t.csv"
    rows = [f"{R * np.sin(x):.6f},{R * np.cos(x):.6f},0,1" for x in a]
    csv.write_text("x_um,y_um,tx_Pa,ty_Pa\n" + "\n".join(rows) + "\n")
    description = {
        "cell": {
            "outer_diameter_um": 2 * R,
            "zona_thickness_um": 15.0,
            "symmetry": "axisymmetric",
            "mesh_size_um": 5.0,
            "materials": {"zona": {"E_kPa": 7.0}, "cytoplasm": {"E_kPa": 1.5}},
        },
        "loads": {"flow": {"type": "traction", "table": str(csv), "follower": True}},
        "support": "inertia_relief",
        "time": {"duration_s": 1.0, "frames": 2},
    }
    with pytest.raises(ValueError, match="loads.flow.follower: a plane-strain cell"):
        Experiment.model_validate(description)


def test_the_tangent_of_a_position_dependent_pressure_is_its_derivative():
    """``FacetOperators.pressure`` with ``grad_pn``: ``-d f / d u`` of the force of a pressure
    read at the current position (:class:`.experiment.surface_loads.PolarPressure`) matches
    central differences of the force to 1e-6 relative."""
    import skfem

    from oocyte_fe.experiment.surface_loads import PolarPressure
    from oocyte_fe.fe.vectorized import FacetOperators

    mesh = skfem.MeshTri.init_circle(2).scaled([R, R])
    fb = skfem.FacetBasis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    ops = FacetOperators.of(fb)
    theta = np.arange(-180.0, 180.0, 7.5)
    load = PolarPressure(theta, np.cos(np.radians(theta)) + 0.5 * np.sin(np.radians(3 * theta)))
    u = 2.0 * np.random.default_rng(3).normal(size=ops.n_u)

    def force(u: np.ndarray) -> np.ndarray:
        x = ops.X + ops.interpolate(u)[0]
        return ops.pressure_force(u, load(x), False)

    x = ops.X + ops.interpolate(u)[0]
    _, K = ops.pressure(u, load(x), False, load.gradient(x))
    K = K.toarray()
    h = 1e-6
    for j in np.random.default_rng(4).choice(ops.n_u, 12, replace=False):
        e = np.zeros(ops.n_u)
        e[j] = h
        column = -(force(u + e) - force(u - e)) / (2 * h)
        assert np.allclose(K[:, j], column, rtol=0.0, atol=1e-6 * np.abs(K).max())


def test_the_tangent_of_a_follower_traction_with_its_reliefs_is_the_derivative(tmp_path: Path):
    """On the deformed state of the pushed cell (previous test's load): ``(K + G W^T) v``
    against central differences of the residual: measured 2.7e-10 of its size, asserted 1e-8;
    without the reliefs' low-rank part (the translation's two columns and the rotation's)
    4.0e-6, asserted above 1e-6."""
    result = _pushed_cell(tmp_path).experiment
    problem, last = result.problem, result.frames[-1]
    x = last.x
    _, tangent, _ = problem.residual(x, last.t, 0.1)
    G, W = tangent.low_rank
    assert G.shape[1] == 3
    K = tangent()
    v = np.zeros_like(x)
    v[: problem.body.n_u] = np.random.default_rng(0).normal(size=problem.body.n_u)
    eps = 1e-6
    fd = (
        problem.residual(x + eps * v, last.t, 0.1)[0]
        - problem.residual(x - eps * v, last.t, 0.1)[0]
    ) / (2 * eps)
    scale = np.abs(fd).max()
    assert np.abs(K @ v + G @ (W.T @ v) - fd).max() < 1e-8 * scale
    assert np.abs(K @ v - fd).max() > 1e-6 * scale
