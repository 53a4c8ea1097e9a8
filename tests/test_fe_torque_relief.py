"""The turning part of a free cell's inertia relief in the current configuration
(``fe.loads.TorqueRelief``, applied by the driver to every plane-strain free cell).

A dead traction ``t_r = t_theta = s cos 2 theta`` has no resultant and no moment on the
undeformed disc, but its moment about the deformed one, ``sum u x f``, grows with ``u_r f_theta
~ cos^2 2 theta``: at s = 0.2 E the two pins of the cell carried it as a pair of point forces
of 5 % of the largest nodal load before (measured). With the relief the pins carry nothing
and Newton's tangent includes the relief's rank-one derivative."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oocyte_fe.experiment import Experiment, run_experiment

R = 50.0  # um
E = 1.0  # kPa


def _turning_cell(tmp_path: Path, s_Pa: float) -> Experiment:
    theta = np.radians(np.arange(0.0, 360.0, 1.0))
    t_r = t_t = s_Pa * np.cos(2 * theta)
    tx = t_r * np.cos(theta) - t_t * np.sin(theta)
    ty = t_r * np.sin(theta) + t_t * np.cos(theta)
    x, y = R * np.cos(theta), R * np.sin(theta)
    rows = "\n".join(
        f"{a:.17g},{b:.17g},{c:.17g},{d:.17g}" for a, b, c, d in zip(x, y, tx, ty, strict=True)
    )
    table = tmp_path / "t.csv"
    table.write_text("x_um,y_um,tx_Pa,ty_Pa\n" + rows + "\n")
    return Experiment.model_validate(
        {
            "cell": {
                "outer_diameter_um": 2 * R,
                "mesh_size_um": 10.0,
                "symmetry": "plane_strain",
                "materials": {"cytoplasm": {"E_kPa": E, "nu": 0.5}},
            },
            "loads": {"flow": {"type": "traction", "table": str(table)}},
            "support": "inertia_relief",
            "time": {"duration_s": 1.0, "frames": 4},
        }
    )


def test_the_pins_of_a_free_cell_carry_no_moment(tmp_path: Path) -> None:
    result = run_experiment(_turning_cell(tmp_path, 200.0))
    assert result.success
    problem, last = result.problem, result.frames[-1]
    r, _, _ = problem.assemble(last.x, last.t, 0.25)
    load = np.abs(problem.dead_loads[0][1]).max()  # the largest nodal force, nN
    # the pins' reactions: 1.7e-10 nN measured (0.07 nN, 5 % of the load, without the relief)
    assert np.abs(r[problem.fixed_dofs]).max() < 1e-6 * load


def test_the_tangent_includes_the_relief(tmp_path: Path) -> None:
    """(K + g w^T) v against central differences of the residual, on a deformed state (the
    relief's rank-one part: one column of ``tangent.low_rank``)."""
    result = run_experiment(_turning_cell(tmp_path, 200.0))
    problem, last = result.problem, result.frames[-1]
    x = last.x
    r0, tangent, _ = problem.residual(x, last.t, 0.25)
    G, W = tangent.low_rank
    assert G.shape[1] == 1  # dead loads: the rotation mode only
    g, w = G[:, 0], W[:, 0]
    K = tangent()
    rng = np.random.default_rng(0)
    v = np.zeros_like(x)
    v[: problem.body.n_u] = rng.normal(size=problem.body.n_u)
    eps = 1e-6
    rp = problem.residual(x + eps * v, last.t, 0.25)[0]
    rm = problem.residual(x - eps * v, last.t, 0.25)[0]
    fd = (rp - rm) / (2 * eps)
    exact = K @ v + g * (w @ v)
    without = K @ v
    scale = np.abs(fd).max()
    assert np.abs(exact - fd).max() < 1e-6 * scale
    # the rank-one part matters here: 1.1e-4 without it, 8e-10 with it (measured)
    assert np.abs(without - fd).max() > 3e-5 * scale
