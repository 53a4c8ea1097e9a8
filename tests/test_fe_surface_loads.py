"""Surface loads of an FE experiment (pressure, traction table) against linear closed forms.

A free cell (``support = "inertia_relief"``) under small loads (p/E = 1e-3, strains 1e-3):
finite strain moves the linear answers by about the strain, so the stated tolerance is 0.5 %
(measured: 0.003-0.04 % for the pressures, see each test).

* Uniform external pressure ``p`` on a disc (plane strain) and on a sphere::

      u_r(R) = -p R (1 + nu)(1 - 2 nu) / E,       u_r(R) = -p R (1 - 2 nu) / E

* A normal traction ``t_r = s cos 2 theta`` on a disc (plane strain), from the Airy function
  ``phi = (A r^2 + B r^4) cos 2 theta`` with ``A = -s/2``, ``B = s / (6 R^2)``::

      u_r(R, theta) = (1 + nu) s R (1 - 2 nu / 3) cos 2 theta / E      (= s R / E at nu = 1/2)
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from oocyte_fe.errors import InputError
from oocyte_fe.experiment import Experiment, run_experiment
from oocyte_fe.experiment.analysis import closed_form_metrics
from oocyte_fe.runner.casefile import load_case

R = 50.0  # um
E = 1.0  # kPa


def _free_cell(symmetry: str, nu: float, loads: dict, mesh: float = 5.0) -> dict:
    return {
        "cell": {
            "outer_diameter_um": 2 * R,
            "mesh_size_um": mesh,
            "symmetry": symmetry,
            "materials": {"cytoplasm": {"E_kPa": E, "nu": nu}},
            "points": {"east": [R, 0.0], "north": [0.0, R]},
        },
        "loads": loads,
        "support": "inertia_relief",
        "time": {"duration_s": 1.0, "frames": 1},
    }


def _pressure(p_Pa: float) -> dict:
    return {"p": {"type": "pressure", "pressure_Pa": {"time_s": [0, 1], "value": [0, p_Pa]}}}


def _write_table(path: Path, theta: np.ndarray, tx: np.ndarray, ty: np.ndarray) -> Path:
    x, y = R * np.cos(theta), R * np.sin(theta)
    rows = "\n".join(
        f"{a:.17g},{b:.17g},{c:.17g},{d:.17g}" for a, b, c, d in zip(x, y, tx, ty, strict=True)
    )
    path.write_text("# a test table\nx_um,y_um,tx_Pa,ty_Pa\n" + rows + "\n")
    return path


@pytest.mark.parametrize(
    ("symmetry", "factor"),
    [("plane_strain", lambda nu: (1 + nu) * (1 - 2 * nu)), ("axisymmetric", lambda nu: 1 - 2 * nu)],
)
def test_uniform_pressure_gives_the_linear_radial_displacement(symmetry, factor):
    nu, p = 0.3, 1.0  # Pa
    result = run_experiment(Experiment.model_validate(_free_cell(symmetry, nu, _pressure(p))))
    exact = -1e-3 * p * R * factor(nu) / E
    assert result.success
    assert result.tracks_um["east"][-1, 0] == pytest.approx(exact, rel=5e-3)  # 0.003 / 0.04 %
    assert result.tracks_um["north"][-1, 1] == pytest.approx(exact, rel=5e-3)
    # balanced: no resultant, no reaction on the pins (nN; the load is 31 nN around)
    assert np.abs(result.hold_reaction_nN[-1]).max() < 1e-9


@pytest.mark.parametrize("nu", [0.5, 0.3])
def test_cosine_traction_table_gives_the_airy_displacement(tmp_path: Path, nu: float):
    theta = np.radians(np.arange(0.0, 360.0, 1.0))
    s = 1.0  # Pa
    tr = s * np.cos(2 * theta)
    table = _write_table(tmp_path / "t.csv", theta, tr * np.cos(theta), tr * np.sin(theta))
    loads = {"flow": {"type": "traction", "table": str(table)}}
    result = run_experiment(Experiment.model_validate(_free_cell("plane_strain", nu, loads)))
    amplitude = (1 + nu) * 1e-3 * s * R * (1 - 2 * nu / 3) / E
    assert result.success
    assert result.tracks_um["east"][-1, 0] == pytest.approx(amplitude, rel=5e-3)
    assert result.tracks_um["north"][-1, 1] == pytest.approx(-amplitude, rel=5e-3)  # cos(180)
    # the section becomes an ellipse of semi-axes R +- amplitude (to first order)
    deformation = closed_form_metrics(result)["deformation"]
    assert deformation == pytest.approx(2 * amplitude / (R + amplitude), rel=1e-2)


def test_traction_resultant_and_inertia_relief(tmp_path: Path):
    """A uniform drag t_x = 1 Pa: resultant 2 pi R t_x per um of thickness (nN), balanced by
    the cell's acceleration (the pins carry nothing)."""
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    table = _write_table(tmp_path / "t.csv", theta, np.ones_like(theta), np.zeros_like(theta))
    loads = {"drag": {"type": "traction", "table": str(table)}}
    result = run_experiment(Experiment.model_validate(_free_cell("plane_strain", 0.5, loads)))
    force = result.load_force_nN["drag"][-1]
    assert force[0] == pytest.approx(2 * np.pi * R * 1e-3, rel=1e-3)  # curved edges: exact arc
    assert abs(force[1]) < 1e-9
    assert np.abs(result.hold_reaction_nN[-1]).max() < 1e-6 * force[0]


TABLE = {"flow": {"type": "traction", "table": "t.csv"}}
PLATE = {"type": "plate", "displacement_um": {"time_s": [0, 1], "value": [0, 1]}}


def _case(tmp_path: Path, inputs: dict) -> None:
    (tmp_path / "case.toml").write_text(
        tomli_w.dumps({"kind": "fe_experiment", "description": "test", "inputs": inputs})
    )


@pytest.mark.parametrize(
    ("change", "says"),
    [
        (lambda th: (R * 1.1 * np.cos(th), R * np.sin(th)), "on the cell's outline"),
        (lambda th: (R * np.cos(th / 2), R * np.sin(th / 2)), "gaps <= 45 deg"),
    ],
)
def test_a_traction_table_off_the_cell_is_refused(tmp_path: Path, change, says):
    theta = np.radians(np.arange(0.0, 360.0, 10.0))
    x, y = change(theta)
    rows = "\n".join(f"{a},{b},1,0" for a, b in zip(x, y, strict=True))
    (tmp_path / "t.csv").write_text("x_um,y_um,tx_Pa,ty_Pa\n" + rows + "\n")
    _case(
        tmp_path, _free_cell("plane_strain", 0.5, {"flow": {"type": "traction", "table": "t.csv"}})
    )
    with pytest.raises(InputError, match=says) as err:
        load_case(tmp_path)
    assert "t.csv" in str(err.value) and "loads.flow" in str(err.value)


def test_a_traction_table_needs_its_columns(tmp_path: Path):
    (tmp_path / "t.csv").write_text("x,y,tx,ty\n" + "1,2,3,4\n" * 10)
    _case(
        tmp_path, _free_cell("plane_strain", 0.5, {"flow": {"type": "traction", "table": "t.csv"}})
    )
    with pytest.raises(InputError, match="x_um, y_um, tx_Pa, ty_Pa"):
        load_case(tmp_path)


@pytest.mark.parametrize(
    ("edit", "says"),
    [
        (lambda i: i.update(loads={}), "at least one tool or load"),
        (
            lambda i: i.update(
                tools={
                    "plate": {
                        "type": "plate",
                        "displacement_um": {"time_s": [0, 1], "value": [0, 1]},
                    }
                }
            ),
            "a free cell with loads, no tools",
        ),
        (lambda i: i.update(support="tools"), "the cell needs support"),
        (lambda i: i["loads"]["p"].update(window_deg=[30, 10]), "lo < hi"),
    ],
)
def test_load_relations_are_checked(tmp_path: Path, edit, says):
    inputs = copy.deepcopy(_free_cell("plane_strain", 0.5, _pressure(1.0)))
    edit(inputs)
    _case(tmp_path, inputs)
    with pytest.raises(InputError, match=says):
        load_case(tmp_path)
