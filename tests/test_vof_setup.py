"""The VOF case writer's pieces that need no OpenFOAM: viscosity conversion, the cap, the
geometry, initial fractions, shape moments and the log monitor."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel import units
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry, disk_fraction
from oocyte_fe.microchannel.vof.monitor import Limits, SolverMonitor
from oocyte_fe.microchannel.vof.post import shape_moments
from oocyte_fe.microchannel.vof.rheology import cap_zero_shear, foam_viscosity
from oocyte_fe.microchannel.vof.runner import INSTALL_HINT, OpenFoamMissing
from oocyte_fe.runner.run import plan, run_cases

CASES = Path(__file__).resolve().parents[1] / "cases"

PA_S = units.VISCOSITY["Pa_s"]
RHO = 1047.0 * units.DENSITY["kg_m3"]
RATES = np.logspace(-4, 5, 60)


@pytest.mark.parametrize(
    ("key", "params"),
    [
        ("carreau", {"eta0": 4.6179, "eta_inf": 3.371e-3, "time_constant": 661.0, "n": 0.047}),
        (
            "carreau_yasuda",
            {"eta0": 3.4, "eta_inf": 1e-3, "time_constant": 50.0, "n": 0.2, "a": 0.87},
        ),
        ("cross", {"eta0": 2.591, "eta_inf": 1.368e-3, "time_constant": 979.0, "m": 1.004}),
        ("newtonian", {"mu": 1.66e-6}),
    ],
)
def test_openfoam_coefficients_give_the_registry_curve(key: str, params: dict) -> None:
    """nu_OpenFOAM(gamma) rho = eta_registry(gamma) to 1e-12 over nine decades of rate."""
    rheology = Rheology.of(key, **params)
    foam = foam_viscosity(rheology, RHO)
    eta_si = rheology.viscosity(RATES) / PA_S
    assert foam.nu(RATES) * 1047.0 == pytest.approx(eta_si, rel=1e-12)
    assert (
        foam.model
        == {
            "carreau": "BirdCarreau",
            "carreau_yasuda": "BirdCarreau",
            "cross": "CrossPowerLaw",
            "newtonian": "Newtonian",
        }[key]
    )


def test_bird_carreau_and_cross_power_law_agree_on_a_cross_equivalent_curve() -> None:
    """A Carreau-Yasuda curve with a = 1 - n equals the Cross curve with m = 1 - n: the two
    OpenFOAM models, written by the converter, give the same viscosity curve."""
    n = 0.4
    cy = Rheology.of("carreau_yasuda", eta0=1.0, eta_inf=1e-3, time_constant=2.0, n=n, a=1 - n)
    cr = Rheology.of("cross", eta0=1.0, eta_inf=1e-3, time_constant=2.0, m=1 - n)
    bc, cpl = foam_viscosity(cy, RHO), foam_viscosity(cr, RHO)
    assert (bc.model, cpl.model) == ("BirdCarreau", "CrossPowerLaw")
    assert bc.nu(RATES) == pytest.approx(cpl.nu(RATES), rel=1e-12)


def test_cap_keeps_the_high_rate_branch() -> None:
    """Capping eta0 = 4618 Pa s at 46 Pa s: the plateau is the cap; above 10 1/s the capped
    curve is within 1 % of the original (and exactly equal asymptotically)."""
    zp = Rheology.of("carreau", eta0=4.6179, eta_inf=3.371e-3, time_constant=661.0, n=0.047)
    capped = cap_zero_shear(zp, 46e-3)
    assert float(capped.viscosity(1e-9)) == pytest.approx(46e-3, rel=1e-6)
    high = np.logspace(1, 5, 20)
    assert capped.viscosity(high) == pytest.approx(zp.viscosity(high), rel=0.01)
    assert cap_zero_shear(zp, 10.0) is zp
    with pytest.raises(InputError, match="cap above eta_inf"):
        cap_zero_shear(zp, 1e-3)


def test_disk_fraction_area_and_cell_counts() -> None:
    """Sub-cell sampling: the sampled disk area is within 0.2 % of pi r^2 at dx = 10 um."""
    geom = JunctionGeometry()
    layout = geom.layout(10.0, 1e5, 1e5)
    assert layout.n_cells == 75 * 25 + 25 * 25 + 100 * 25 + 25 * 50
    f = disk_fraction(layout.cell_centres(), 10.0, geom.cell_centre, 70.0)
    assert f.sum() * 100.0 == pytest.approx(math.pi * 70.0**2, rel=2e-3)
    assert set(layout.inlets) == {"inletA", "inletB"}
    with pytest.raises(InputError, match="multiple of dx"):
        geom.layout(7.0, 1e5, 1e5)


def test_inlet_profile_carries_the_mean_velocity() -> None:
    layout = JunctionGeometry().layout(5.0, 7e5, 3e5)
    ua, ub = layout.inlet_velocity("inletA"), layout.inlet_velocity("inletB")
    assert ua[:, 0].mean() == pytest.approx(7e5, rel=1e-3)
    assert ub[:, 1].mean() == pytest.approx(-3e5, rel=1e-3)  # B enters from +y


def test_shape_moments_of_an_ellipse() -> None:
    """A uniform ellipse with b/a = 0.8, sampled on a fine grid: ratio within 1e-3."""
    x, y = np.meshgrid(np.linspace(-80, 80, 641), np.linspace(-80, 80, 641))
    pts = np.column_stack([x.ravel() + 3.0, y.ravel()])
    inside = ((pts[:, 0] - 3.0) / 70.0) ** 2 + (pts[:, 1] / 56.0) ** 2 <= 1.0
    centre, ratio = shape_moments(pts, inside.astype(float))
    assert ratio == pytest.approx(0.8, abs=1e-3)
    assert centre == pytest.approx([3.0, 0.0], abs=1e-6)


LOG_OK = """Courant Number mean: 0.01 max: 0.2
deltaT = 1e-06
Time = 1e-06
medium volume fraction, min, max = 0.9 0 1
Phase-1 volume fraction = 0.0246875  Min(alpha.cell) = 0  Max(alpha.cell) = 1
    max(mag(U)) = 1.05 in cell 3 at location (0 0 0)
"""


@pytest.mark.parametrize(
    ("line", "mode"),
    [
        ("deltaT = 2e-08", "dt collapse"),
        ("Courant Number mean: 0.5 max: 75", "Courant"),
        ("    max(mag(U)) = 150 in cell 3 at location (0 0 0)", "velocity"),
        ("zp volume fraction, min, max = 0.01 -0.3 1", "alpha"),
        ("Phase-sum volume fraction, min, max = 1 0.5 1.4", "alpha"),
        ("Phase-1 volume fraction = 0.02  Min(alpha.cell) = -0.05  Max(alpha.cell) = 1", "alpha"),
        ("Courant Number mean: nan max: nan", "Courant"),
    ],
)
def test_monitor_names_each_silent_failure(line: str, mode: str) -> None:
    """dt = 1e-6 s, dx = 5 um, U_ref = 1.05 m/s: physical Co 0.21, bound 10 x that."""
    mon = SolverMonitor(1e-4, 1e-6, 5e-6, 1.05, Limits())
    for ok in LOG_OK.splitlines():
        assert mon.feed(ok) is None
    failure = mon.feed(line)
    assert failure is not None and failure.mode == mode
    assert failure.time == pytest.approx(1e-6)
    assert "1%" in mon.progress() or "t = 1e-06" in mon.progress()


def test_quick_case_without_openfoam_is_reported_skipped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """No OpenFOAM: the case is SKIPPED (not a failure: exit 0) with the install line as its
    reason, the report says SKIPPED, the Kelvin-Voigt estimate is still there; no traceback."""
    import oocyte_fe.kinds.microchannel_vof as kind

    def missing(_path: object = None) -> None:
        raise OpenFoamMissing(f"not found; install it with: {INSTALL_HINT}")

    monkeypatch.setattr(kind, "find_openfoam", missing)
    [result] = run_cases(plan([CASES / "microchannel_vof_quick"]), tmp_path)
    assert result.status == "SKIPPED" and result.ok and result.total == 0
    assert "apt-get install -y openfoam" in result.reason
    report = (tmp_path / "microchannel_vof_quick" / "report.md").read_text()
    assert "SKIPPED" in report and "apt-get install -y openfoam" in report
    assert "Kelvin-Voigt estimate" in report


def test_initial_velocity_carries_the_inflow_through_each_arm() -> None:
    """Flow per unit depth across a column: A's in the upstream arm, A + B's downstream,
    B's (downwards) in the branch; each arm a plane-Poiseuille profile."""
    from oocyte_fe.microchannel.vof.casewriter import initial_velocity

    layout = JunctionGeometry().layout(5.0, 7e5, 3e5)
    u, c = initial_velocity(layout), layout.cell_centres()
    up = np.isclose(c[:, 0], -402.5)
    down = np.isclose(c[:, 0], 502.5)
    branch = np.isclose(c[:, 1], 302.5)
    assert u[up, 0].sum() * 5.0 == pytest.approx(7e5 * 250.0, rel=1e-3)
    assert u[down, 0].sum() * 5.0 == pytest.approx(1e6 * 250.0, rel=1e-3)
    assert u[branch, 1].sum() * 5.0 == pytest.approx(-3e5 * 250.0, rel=1e-3)


def test_monitor_keeps_the_largest_courant_numbers_of_the_run() -> None:
    """A leap of the Courant number from 0.86 to 1.9 and back (under the failure bound of
    10 x 0.21) is kept as the run's largest, with the interface's 0.84, and by time: up to
    t = 2e-6 s the largest is 0.86. The case's ``max_courant_read`` check takes each run's
    largest until its cell passed the read window (the whole run's where that is unknown):
    it fails on a leap before, passes on a leap after (the whole runs' largest still in the
    metric ``max_courant`` and the check's text) and on a calm run."""
    from oocyte_fe.kinds.microchannel_vof_checks import courant_check
    from oocyte_fe.microchannel.vof.junction import JunctionRun

    mon = SolverMonitor(1e-4, 1e-6, 5e-6, 1.05, Limits())
    for k, (co, ico) in enumerate(((0.2, 0.3), (0.86, 0.52), (1.9, 0.84), (0.5, 0.4))):
        assert mon.feed(f"Time = {(k + 1) * 1e-6:g}") is None
        assert mon.feed(f"Courant Number mean: 0.01 max: {co}") is None
        assert mon.feed(f"Interface Courant Number mean: 0.001 max: {ico}") is None
    assert (mon.largest_courant, mon.largest_interface_courant) == (1.9, 0.84)
    assert mon.courant == 0.5  # the progress line's: the latest
    assert mon.largest_courant_until(2e-6) == 0.86 and mon.largest_courant_until(3e-6) == 1.9
    assert math.isnan(mon.largest_courant_until(0.5e-6))

    def run(co: float, read: float = math.nan) -> JunctionRun:
        return JunctionRun(Path("."), 1.0, 1.0, 1, 1, 0.0, None, 0.9, 0.0, 0.9, co, co / 2, read)  # type: ignore[arg-type]

    inp = SimpleNamespace(max_courant=1.0)
    metrics: dict = {}
    [check] = courant_check(inp, [run(0.3), run(1.9)], metrics)  # type: ignore[arg-type]
    assert not check.passed and check.computed == 1.9 and metrics["max_interface_courant"] == 0.95
    [check] = courant_check(inp, [run(0.3), run(1.9, read=1.2)], {})  # type: ignore[arg-type]
    assert not check.passed and check.computed == 1.2
    metrics = {}
    [check] = courant_check(inp, [run(0.3), run(1.3, read=0.95)], metrics)  # type: ignore[arg-type]
    assert check.passed and check.computed == 0.95 and "whole runs: 1.30" in check.tolerance
    assert metrics["max_courant"] == 1.3 and metrics["max_courant_read"] == 0.95
    [check] = courant_check(inp, [run(0.3), run(0.7)], {})  # type: ignore[arg-type]
    assert check.passed
    assert courant_check(inp, [run(math.nan)], {}) == []  # type: ignore[arg-type]
