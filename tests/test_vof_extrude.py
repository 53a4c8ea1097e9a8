"""The 3-D extrusion of the junction (timing runs): mesh dictionary, sphere sampling, cell order
against blockMesh (the last one skipped, with the install line, without OpenFOAM)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.microchannel.vof.casewriter import Numerics
from oocyte_fe.microchannel.vof.extrude import (
    extruded_centres,
    extruded_mesh_dict,
    set_inlet_profiles,
    sphere_fraction,
    write_extruded_case,
)
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import junction_setup, mean_velocity, seed_phases
from oocyte_fe.microchannel.vof.runner import (
    INSTALL_HINT,
    find_openfoam,
    openfoam_available,
    run_utility,
)


def test_sphere_fraction_gives_the_sphere_volume() -> None:
    """r = 70 um on dx = 10 um cubes: volume within 0.5 % of 4/3 pi r^3."""
    g = (np.arange(-10, 10) + 0.5) * 10.0
    centres = np.stack(np.meshgrid(g, g, g), axis=-1).reshape(-1, 3)
    volume = sphere_fraction(centres, 10.0, (0.0, 0.0, 0.0), 70.0).sum() * 1e3
    assert volume == pytest.approx(4 / 3 * math.pi * 70.0**3, rel=5e-3)


def test_extruded_mesh_has_walls_front_and_back() -> None:
    layout = JunctionGeometry().layout(25.0, 1e5, 1e5)
    entries = extruded_mesh_dict(layout, 250.0)
    assert entries["blocks"].count("(30 10 10)") == 1  # upstream arm: 750 x 250 x 250 um
    assert "empty" not in entries["boundary"] and "frontAndBack" not in entries["boundary"]
    assert len(extruded_centres(layout, 250.0)) == 10 * layout.n_cells


def test_seed_phases_cap_the_zero_shear_viscosity() -> None:
    medium, zp, cyto = seed_phases(46.0)
    assert float(zp.rheology.viscosity(0.0)) == pytest.approx(46e-3, rel=1e-9)
    assert float(cyto.rheology.viscosity(0.0)) == pytest.approx(46e-3, rel=1e-9)
    assert mean_velocity(600.0) == pytest.approx(2 * mean_velocity(300.0))


@pytest.mark.skipif(not openfoam_available(), reason=f"OpenFOAM not installed: {INSTALL_HINT}")
def test_extruded_cells_in_blockmesh_order_and_duct_inlet(tmp_path: Path) -> None:
    """Python's 3-D cell centres are blockMesh's to 1e-9 um; the inlet profile written on the
    reported face centres has the inlet's mean velocity within 2 % (10 x 10 faces)."""
    from oocyte_fe.microchannel.vof.foamfile import read_internal_field

    u = mean_velocity(300.0)
    numerics = Numerics(time_step=1e-6, end_time=1e-6, write_interval=1e-6)
    setup = junction_setup(JunctionGeometry(), 25.0, *seed_phases(), u, u, numerics)
    case = write_extruded_case(setup, tmp_path / "c", 250.0)
    foam = find_openfoam()
    run_utility(foam, case, ["blockMesh"])
    centres = set_inlet_profiles(foam, case, setup.layout, 250.0)
    assert np.max(np.abs(centres - extruded_centres(setup.layout, 250.0))) < 1e-9
    text = (case / "0" / "U").read_text()
    start = text.index("inletA", text.index("boundaryField"))
    block = text[text.index("List<vector>", start) :]
    n = int(block.split()[1])
    values = np.array(
        block[block.index("(") + 1 : block.index("\n)")]
        .replace("(", " ")
        .replace(")", " ")
        .split(),
        float,
    )
    ux = values.reshape(n, 3)[:, 0] * 1e6
    assert n == 100
    assert ux.mean() == pytest.approx(u, rel=0.02)
    assert read_internal_field(case / "0" / "alpha.zp").shape == (len(centres),)
