"""Table 4 from the mesh limits (``mesh_check_pressures = "all"``): the runs it adds (every
pressure on every finer mesh, the time step scaled with 1/p on request), the refusal of a
single finer mesh, and the report's limits against closed-form power laws (no OpenFOAM)."""

from __future__ import annotations

import math
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.kinds.microchannel_vof_converged import (
    FINEST_JITTER,
    converged_section,
    pressure_limit,
    pressure_limits,
)
from oocyte_fe.kinds.microchannel_vof_inputs import VofInputs
from oocyte_fe.kinds.microchannel_vof_runs import mesh_label, run_specs
from oocyte_fe.microchannel.vof.junction import JunctionRun
from oocyte_fe.runner.casefile import load_case

CASES = Path(__file__).resolve().parents[1] / "cases"
THIRD = 12.5 / 3.0


def _inputs(**change: object) -> VofInputs:
    """The Table 4 case's inputs with ``change``; ``beside_model=None`` drops its settings too."""
    case = CASES / "microchannel_vof_table4"
    data = tomllib.loads((case / "case.toml").read_text())["inputs"]
    if "beside_model" in change and change["beside_model"] is None:
        data = {k: v for k, v in data.items() if not k.startswith("beside_")}
    return VofInputs.model_validate({**data, **change}, context={"case_dir": case})


def _run(ratio: float) -> JunctionRun:
    history = type("History", (), {"ratio": np.array([ratio])})()
    return JunctionRun(Path("."), 1.0, 1.0, 100, 10, 1.0, history, ratio, 0.0, ratio, 0.3)


def test_every_pressure_runs_on_every_finer_mesh_at_a_step_scaled_with_one_over_p() -> None:
    """Pressures 300, 600, 900 hPa on 12.5 / 6.25 / 4.17 um at 1e-6 s x 300 / p: nine runs of
    the model (the beside model aside), dt 1e-6, 5e-7, 3.33e-7 s on every mesh."""
    inp = _inputs(
        pressures_hPa=[300, 600, 900],
        mesh_check_dx_um=[6.25, THIRD],
        mesh_check_correctors=[48, 64],
        mesh_check_pressures="all",
        time_step_scaling="inverse_pressure",
        dt_refinements=1,
        beside_model=None,
        cap_sensitivity_Pa_s=None,
        zp_bound=False,
    )
    specs = {s.label: s for s in run_specs(inp, inp.pressures_hPa)}
    for p, dt in ((300, 1e-6), (600, 5e-7), (900, 1e-6 / 3)):
        assert specs[f"p{p}hPa"].dt == pytest.approx(dt, rel=1e-12)
        for m, n in ((6.25, 48), (THIRD, 64)):
            run = specs[mesh_label(p, m)]
            assert (run.dx, run.correctors, run.pressure_hPa) == (m, n, p)
            assert run.dt == pytest.approx(dt, rel=1e-12)
    assert specs["p300hPa_dt5e-07"].dt == pytest.approx(5e-7, rel=1e-12)
    assert len(specs) == 3 * 3 + 1
    fixed = _inputs(pressures_hPa=[300, 600], mesh_check_dx_um=[6.25], beside_model=None)
    labels = [s.label for s in run_specs(fixed, fixed.pressures_hPa)]
    assert mesh_label(600, 6.25) not in labels and mesh_label(300, 6.25) in labels
    main = [s for s in run_specs(fixed, fixed.pressures_hPa) if "_dt" not in s.label]
    assert {s.dt for s in main} == {fixed.time_step_s}


def test_all_pressures_on_one_finer_mesh_is_refused_with_the_field_named(tmp_path: Path) -> None:
    case = tmp_path / "converged"
    shutil.copytree(CASES / "microchannel_vof_table4_converged", case)
    toml = case / "case.toml"
    text = toml.read_text().replace(
        "mesh_check_dx_um = [6.25, 4.166666666666667]", "mesh_check_dx_um = [6.25]"
    )
    toml.write_text(text.replace("mesh_check_correctors = [48, 64]", "mesh_check_correctors = 48"))
    with pytest.raises(InputError) as err:
        load_case(case)
    says = "inputs.mesh_check_dx_um: expected two finer meshes or more with mesh_check_pressures"
    assert f"{toml}: {says}" in str(err.value).replace("\n", " ")


def test_the_limits_per_pressure_are_the_closed_form_power_laws() -> None:
    """1 - b/a = e0(p) + C h^q exactly on 12.5 / 6.25 / 4.17 um (q 1.2 and 1.8): the limit
    e0 and the order to 1e-6; where the differences alternate there is no limit; the mean
    error against the experiment is that of b/a = 1 - e0."""
    cases = {300: (0.0082, 1.8), 600: (0.0142, 1.2)}
    h = [12.5, 6.25, THIRD]
    runs, extra = [], {}
    for p, (e0, q) in cases.items():
        e = [e0 + 4e-5 * x**q for x in h]
        runs.append(_run(1 - e[0]))
        extra.update({mesh_label(p, m): _run(1 - v) for m, v in zip(h[1:], e[1:], strict=True)})
    limits = pressure_limits(12.5, [300.0, 600.0], runs, extra, h[1:])
    for lim, (e0, q) in zip(limits, cases.values(), strict=True):
        assert lim.limit == pytest.approx(e0, rel=1e-6)
        assert lim.order == pytest.approx(q, rel=1e-6)
        assert lim.where == "x = 0"
        lo, hi = lim.limit_range  # the finest value moved by +-0.3 %: the limit moves more
        assert lo < lim.limit < hi and hi - lo > 2 * FINEST_JITTER * lim.deformation[-1]
    exp, paper = [0.928, 0.912], [0.967, 0.934]
    text, m = converged_section(limits, exp, paper)
    assert m["converged_b_over_a"] == pytest.approx([1 - 0.0082, 1 - 0.0142], rel=1e-7)
    want = 100 * np.mean([abs((1 - 0.0082) / 0.928 - 1), abs((1 - 0.0142) / 0.912 - 1)])
    assert m["converged_mean_error_experiment_pct"] == pytest.approx(want, rel=1e-6)
    assert m["converged_liquid_mae"] == pytest.approx(
        np.mean([1 - 0.0082 - 0.928, 1 - 0.0142 - 0.912]), rel=1e-6
    )
    assert "Closer to the experiment: **paper VOF (Fluent, 3-D)**" in text
    alternating = pressure_limit(300.0, h, [_run(1 - v) for v in (0.0148, 0.0101, 0.0102)])
    assert math.isnan(alternating.limit) and math.isnan(alternating.b_over_a)
    text, m = converged_section([alternating], [0.928], [0.967])
    assert "none (the differences do not shrink)" in text
    assert "converged_mean_error_experiment_pct" not in m


def test_the_converged_case_runs_every_pressure_on_three_meshes() -> None:
    """The heavy case: seven pressures on 12.5 / 6.25 / 4.17 um at 1e-6 s x 300 / p, at most
    1e-6 s."""
    case = load_case(CASES / "microchannel_vof_table4_converged")
    inp = case.inputs
    assert case.spec.heavy and inp.mesh_check_pressures == "all"
    specs = run_specs(inp, inp.pressures_hPa)
    assert len(specs) == 7 * 3
    by = {s.label: s for s in specs}
    assert by[mesh_label(900, THIRD)].dt == pytest.approx(1e-6 / 3, rel=1e-9)
    assert by[mesh_label(300, THIRD)].dt == pytest.approx(1e-6, rel=1e-9)
    assert by[mesh_label(200, THIRD)].dt == 1e-6  # the bound, not 1.5e-6
