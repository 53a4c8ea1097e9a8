"""FE core bad input: each error names what is wrong; a failing step stops loudly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError, SolverError
from oocyte_fe.fe.body import Body
from oocyte_fe.fe.contact import Contact, ContactLaw
from oocyte_fe.fe.loads import FollowerPressure, Prescribed
from oocyte_fe.fe.material import Material, Prony, read_material_file
from oocyte_fe.fe.obstacles import Circle, flat_plate, necked_pipette_wall
from oocyte_fe.fe.solver import NewtonSettings, Problem
from tests.fe_geometry import rectangle


@pytest.mark.parametrize(
    ("g", "tau", "fragment"),
    [
        ((0.6, 0.5), (0.1, 1.0), "sum of g_i < 1"),
        ((0.2,), (0.0,), "relaxation times > 0"),
        ((-0.1,), (1.0,), "non-negative"),
        ((0.1, 0.2), (1.0,), "as many terms"),
    ],
)
def test_bad_prony(g: tuple, tau: tuple, fragment: str) -> None:
    with pytest.raises(InputError, match=fragment):
        Prony(g, tau, source="zp.toml")


@pytest.mark.parametrize(("E", "nu", "field"), [(-1.0, 0.3, "E_kPa"), (1.0, 0.6, "nu")])
def test_bad_material(E: float, nu: float, field: str) -> None:
    with pytest.raises(InputError, match=f"material.{field}"):
        Material(E, nu, source="zp.toml")


def test_bad_material_file_names_file_and_field(tmp_path: Path) -> None:
    f = tmp_path / "zp.toml"
    f.write_text("[material]\nname = 'zp'\nsource = 'x'\nE_kPa = -7.0\nnu = 0.5\n")
    with pytest.raises(InputError) as info:
        read_material_file(f)
    assert str(f) in str(info.value) and "E_kPa" in str(info.value)


def test_missing_physical_group_is_named() -> None:
    with pytest.raises(InputError, match="subdomain 'zona'.*present: solid"):
        Body(rectangle(1, 1, 2, 2), {"zona": Material(1.0, 0.3)}, source="oocyte.msh")
    body = Body(rectangle(1, 1, 2, 2), {"solid": Material(1.0, 0.3)})
    with pytest.raises(InputError, match="boundary 'outer_surface'"):
        Problem(body, [Prescribed("outer_surface", 0)])


def test_inverted_element_is_refused() -> None:
    mesh = rectangle(1, 1, 2, 2)
    p = mesh.p.copy()
    centre = np.flatnonzero(np.all(np.isclose(p, 0.5), axis=0))
    p[:, centre] = [[1.4], [1.4]]  # drags the centre node across the far corner
    folded = type(mesh)(p, mesh.t).with_subdomains({"solid": lambda x: x[0] > -1})
    with pytest.raises(InputError, match="oocyte.msh"):
        Body(folded, {"solid": Material(1.0, 0.3)}, "plane_strain", source="oocyte.msh")


def test_obstacle_starting_inside_the_body() -> None:
    body = Body(rectangle(1, 1, 2, 2), {"solid": Material(1.0, 0.3)}, "plane_strain")
    sphere = Circle((0.5, 1.1), 0.3, name="sphere")
    with pytest.raises(InputError, match="sphere: obstacle: .*penetration 0.1"):
        Problem(body, contacts=[Contact("top", sphere, ContactLaw(10.0), name="sphere")])


def test_pipette_profile_must_increase() -> None:
    with pytest.raises(InputError, match="increasing Z"):
        necked_pipette_wall([(100.0, 0.0), (75.0, -10.0)])


def test_step_that_never_converges_stops_loudly() -> None:
    body = Body(rectangle(1, 1, 2, 2), {"solid": Material(1.0, 0.3)}, "plane_strain")
    push = FollowerPressure("left", lambda t: 0.1 * t)  # nothing holds the block along x
    prob = Problem(body, [Prescribed("bottom", 1)], [push])
    with pytest.raises(SolverError) as info:
        prob.solve([1.0], NewtonSettings(max_cutbacks=2))
    msg = str(info.value)
    assert "no convergence at t = " in msg and "after 2 cutbacks" in msg and "residual" in msg
    assert info.value.result is not None and info.value.result.frames == []


def test_rigid_translation_converges() -> None:
    """Forces vanish in a rigid motion: the residual floor still lets the step converge."""
    body = Body(rectangle(1, 1, 2, 2), {"solid": Material(1.0, 0.3)}, "plane_strain")
    prob = Problem(body, [Prescribed("left", 0, lambda t: 2.0 * t), Prescribed("left", 1)])
    result = prob.solve([1.0])
    u = body.vertex_displacement(result.frames[-1].x)
    assert np.allclose(u[0], 2.0) and np.allclose(u[1], 0.0, atol=1e-12)
    assert result.steps[-1].iterations <= 2


def test_predictor_that_would_invert_an_element_falls_back_to_the_last_state() -> None:
    """A wild extrapolation (an increment 100x too large) costs no cutback: the step restarts
    from the last converged state."""
    body = Body(rectangle(1, 1, 4, 4), {"solid": Material(1.0, 0.3)}, "plane_strain")
    prob = Problem(
        body,
        [Prescribed("left", 0), Prescribed("left", 1), Prescribed("right", 0, lambda t: -0.1 * t)],
    )
    prob.solve([1.0])
    prob._increment = (100.0 * prob._increment[0], prob._increment[1])  # folds the mesh
    result = prob.solve([2.0])
    assert result.cutbacks == 0
    u = body.vertex_displacement(result.frames[-1].x)
    right = np.isclose(body.mesh.p[0], 1.0)
    assert np.allclose(u[0, right], -0.2)


def test_frictionless_plate_contact_force_balances_pressure() -> None:
    """A plate pressed by a uniform pressure: the contact force equals p times the area."""
    body = Body(rectangle(2.0, 1.0, 4, 2), {"solid": Material(1.0, 0.3)}, "plane_strain")
    plate = flat_plate(0.0, -1.0, 3.0)
    p = 1e-3
    prob = Problem(
        body,
        [Prescribed("left", 0)],
        [FollowerPressure("top", lambda t: p * t)],
        [Contact("bottom", plate, ContactLaw(1e3))],
    )
    frame = prob.solve([1.0]).frames[-1]
    # the follower pressure acts on the deformed (laterally stretched) top: force p * length
    u = body.vertex_displacement(frame.x)
    top = np.isclose(body.mesh.p[1], 1.0)
    length = np.ptp(body.mesh.p[0, top] + u[0, top])
    assert length > 2.0
    assert frame.obstacle_forces["contact"][1] == pytest.approx(-p * length, rel=1e-6)
    assert np.all(frame.contact_pressure["contact"] == pytest.approx(p, rel=0.02))


@pytest.mark.parametrize("smoothing", [0.0, 2e-6])
def test_plate_penetration_follows_the_penalty_law(smoothing: float) -> None:
    """Uniform pressure p on a block on a plate: penetration p / eps (+ delta / 2 when the
    C1-smoothed law is in its linear branch)."""
    body = Body(rectangle(2.0, 1.0, 4, 2), {"solid": Material(1.0, 0.3)}, "plane_strain")
    p, eps = 1e-2, 1e3
    contact = Contact("bottom", flat_plate(0.0, -1.0, 3.0), ContactLaw(eps, smoothing_um=smoothing))
    prob = Problem(
        body, [Prescribed("left", 0)], [FollowerPressure("top", lambda t: p * t)], [contact]
    )
    x = prob.solve([0.5, 1.0]).frames[-1].x
    u = body.vertex_displacement(x)
    bottom = np.isclose(body.mesh.p[1], 0.0)
    assert -u[1, bottom].mean() == pytest.approx(p / eps + smoothing / 2, rel=0.02)
