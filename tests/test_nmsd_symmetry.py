"""The press's mirror symmetry: sideways buckling off the symmetric branch, and the branch."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from nmsd.integrator import BackwardEulerStepper
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import press_setup
from nmsd.symmetry import mirror_of
from oocyte_fe.errors import InputError
from tests.band_storage import band_to_dense

# a soft constant set that buckles (docs/nmsd.md, "Sideways buckling")
SOFT = NmsdParameters(
    k1=7.49, k2=4342.0, dl_c=0.8, d0=7.2, d1=0.0046, node_mass=node_mass_for(115.625, 231)
)
# the Table II displacements, um (the calibration's points)
ADVANCES = [
    3.5,
    6.25,
    12.5,
    14.375,
    16.25,
    19.375,
    23.75,
    28.125,
    33.125,
    41.25,
    53.25,
    57.75,
    62.375,
]


def _asymmetry(setup, positions: np.ndarray) -> float:
    mirror = mirror_of(setup.lattice, setup.pipette, setup.held)
    image = mirror.point + mirror.reflect(positions[mirror.pairs] - mirror.point)
    return float(np.abs(image - positions).max())


def _folded(
    stepper: BackwardEulerStepper,
    x_new: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    advance: float,
    dt: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Residual and dense tangent of the half-lattice system, through the public
    ``residual`` and ``fold`` of the stepper."""
    red = stepper.reduction
    res, ab, _, _ = stepper.residual(x_new, x, v, advance, dt, with_tangent=True)
    ab_h = np.zeros((3 * red.band + 1, red.n_dof), order="F")
    res_h = np.zeros(red.n_dof)
    stepper.fold(ab, res, ab_h, res_h, True)
    return res_h, band_to_dense(ab_h, red.band)


@pytest.mark.parametrize(("damping", "area"), [("nodal", 0.0), ("link", 3.0)])
def test_mirror_pairs_the_lattice_and_the_half_lattice_tangent_is_exact(damping, area):
    setup = press_setup()
    mirror = setup.mirror
    assert mirror is not None
    pairs = mirror.pairs
    assert np.array_equal(pairs[pairs], np.arange(len(pairs)))  # an involution
    x0 = setup.lattice.nodes
    assert np.allclose(x0[pairs], x0 * [1.0, -1.0], atol=1e-9)  # axis y = 0
    params = NmsdParameters(
        k1=30.0, k2=2000.0, dl_c=0.1, d0=2.0, d1=0.7, damping=damping, area_stiffness=area
    )
    stepper = BackwardEulerStepper(setup.lattice, params, setup.pipette, setup.held, mirror=mirror)
    red = stepper.reduction
    # about half the DOFs; numbered by across-axis columns, the band is narrower too
    assert red.n_dof < 0.56 * stepper.n_dof and red.band == 21 and stepper.band == 37
    # a symmetric state: a random kept displacement, mirrored; a few nodes in contact
    rng = np.random.default_rng(3)
    x = x0.copy()
    red.expand(x, np.where(red.fixed, 0.0, rng.normal(scale=0.5, size=red.n_dof)))
    assert _asymmetry(setup, x) < 1e-12
    x_new = x.copy()
    red.expand(x_new, np.where(red.fixed, 0.0, rng.normal(scale=0.3, size=red.n_dof)))
    v = (x_new - x) / 0.05
    advance, dt = 3.0, 0.05
    res, dense = _folded(stepper, x_new, x, v, advance, dt)
    full_res, _, contact, _ = stepper.residual(x_new, x, v, advance, dt, with_tangent=False)
    assert (contact != 0).any()
    # kept rows of the full residual; the mirrored rows are their reflections
    full = full_res.reshape(-1, 2)
    kept = red.kept_row >= 0
    expected = np.zeros((red.n_dof // 2, 2))
    expected[red.kept_row[kept]] = full[kept]
    expected = expected.ravel()
    expected[red.fixed] = 0.0
    assert res == pytest.approx(expected, rel=1e-12, abs=1e-9)
    image = full[pairs] * [1.0, -1.0]
    assert np.allclose(image, full, atol=1e-8 * np.abs(full).max())
    # the folded tangent against central differences of the kept residual
    h = 1e-6
    for q in np.flatnonzero(~red.fixed)[::5]:
        dq = np.zeros(red.n_dof)
        dq[q] = h
        xp, xm = x_new.copy(), x_new.copy()
        red.expand(xp, dq)
        red.expand(xm, -dq)
        rp = _folded(stepper, xp, x, v, advance, dt)[0]
        rm = _folded(stepper, xm, x, v, advance, dt)[0]
        fd = (rp - rm) / (2 * h)
        assert dense[:, q] == pytest.approx(fd, rel=1e-5, abs=1e-5 * np.abs(fd).max())


def test_half_lattice_press_equals_the_full_press_before_it_buckles():
    record = [5.0, 10.0, 15.0]
    half = press_setup(n_steps=30, travel_um=15.0).run(SOFT, record_um=record)
    full = press_setup(n_steps=30, travel_um=15.0, symmetric=False).run(SOFT, record_um=record)
    assert np.abs(half.positions - full.positions).max() < 1e-7
    assert half.force_at(record) == pytest.approx(full.force_at(record), rel=1e-8)


def test_free_press_buckles_sideways_and_the_symmetric_branch_converges_in_dt():
    free = press_setup(n_steps=160, symmetric=False)
    r = free.run(SOFT, record_um=[15.0, 65.0])
    # round-off grows into a sideways buckle of several um
    assert _asymmetry(free, r.snapshots[15.0]) < 1e-6
    assert _asymmetry(free, r.snapshots[65.0]) > 1.0
    # the symmetric branch stays symmetric and 40 steps are within 3 % of 640 steps at the
    # Table II points (measured 1.4 %, 1.5 % against 2600 steps; the buckled branch is 9 %
    # off at 640 steps)
    sym = press_setup(n_steps=40)
    coarse = sym.run(SOFT, record_um=ADVANCES)
    fine = sym.run(SOFT, record_um=ADVANCES, n_steps=640)
    assert _asymmetry(sym, coarse.positions) < 1e-9
    f_coarse, f_fine = coarse.force_at(ADVANCES), fine.force_at(ADVANCES)
    assert np.abs(f_coarse - f_fine).max() < 0.03 * np.abs(f_fine).max()


def test_symmetric_press_needs_a_symmetric_setup():
    setup = press_setup(n_steps=2)
    off_axis = replace(setup.pipette, start=(setup.pipette.start[0], 0.5))
    with pytest.raises(InputError, match="symmetric"):
        mirror_of(setup.lattice, off_axis, setup.held)
    held = setup.held.copy()
    held[np.flatnonzero(held)[0]] = False
    with pytest.raises(InputError, match="held nodes not symmetric"):
        mirror_of(setup.lattice, setup.pipette, held)
