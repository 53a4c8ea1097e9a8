"""AFM kinds, the FE verification's observed order and sweeps: inputs ``validate`` once let
through (outside tester's report, items 1, 3, 5, 6, 8, 9, 15, 19, 22).

Each was accepted and then raised at run (an ``IndexError`` of an empty pierce batch), ran a
sweep whose samples all failed and called it PASS, or reported a number that could not be
right (an indentation deeper than the cell, a Prony time longer than its record, an observed
order that assumed a halving). Now each is refused at ``validate`` in one line naming
``case.toml``, the field and what was expected; the values just inside each bound are
accepted, so every rule is tested from both sides.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import pytest
import tomli_w
from typer.testing import CliRunner

from oocyte_fe.cli import app
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.verification import monotone_observed_order, observed_order
from tests.case_copies import edited_case, refused_message


def _refused(folder: Path) -> str:
    message = refused_message(folder)
    assert "case.toml" in message, message
    return message


def _write(folder: Path, text: str) -> Path:
    folder.mkdir(parents=True)
    (folder / "case.toml").write_text(text)
    return folder


def _with_sweep(folder: Path, parameters: dict[str, Any]) -> Path:
    """``folder/case.toml`` with its sweep's parameters replaced by ``parameters``."""
    raw = tomllib.loads((folder / "case.toml").read_text())
    raw["sweep"]["parameters"] = parameters
    (folder / "case.toml").write_text(tomli_w.dumps(raw))
    return folder


# --- 1, 8: afm_zp_cytoplasm: a pierce the batch fit cannot detect, a trigger below it --------

ZC_REFUSED = [
    # run: "IndexError: index 0 is out of bounds" (no curve's pierce detected)
    ({"tilt_nN_per_um": 3.4}, "inputs.tilt_nN_per_um: expected a pierce drop"),
    ({"tilt_nN_per_um": -2.7}, "inputs.tilt_nN_per_um: expected a pierce drop"),
    ({"tilt_nN_per_um": 1e6}, "inputs.tilt_nN_per_um: expected a pierce drop"),
    ({"pierce_force_nN": 1.6}, "inputs.pierce_force_nN: expected a pierce drop"),
    ({"pierce_force_nN": 1e-6}, "inputs.pierce_force_nN: expected a pierce drop"),
    # run: refused by the curve generator only
    ({"trigger_force_nN": 8.0}, "inputs.trigger_force_nN: expected trigger_force_nN > "),
    ({"trigger_force_nN": 5.0}, "inputs.trigger_force_nN: expected trigger_force_nN > "),
]
ZC_ACCEPTED = [
    {"tilt_nN_per_um": 3.1},
    {"tilt_nN_per_um": -2.5},
    {"pierce_force_nN": 1.9},
    {"trigger_force_nN": 8.01},
]


@pytest.mark.parametrize(("inputs", "fragment"), ZC_REFUSED)
def test_zp_cytoplasm_refused(tmp_path: Path, inputs: dict, fragment: str) -> None:
    assert fragment in _refused(edited_case(tmp_path, "afm_zp_cytoplasm", **inputs))


@pytest.mark.parametrize("inputs", ZC_ACCEPTED)
def test_zp_cytoplasm_accepted(tmp_path: Path, inputs: dict) -> None:
    load_case(edited_case(tmp_path, "afm_zp_cytoplasm", **inputs))


def test_zp_cytoplasm_exit_2_at_validate(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "afm_zp_cytoplasm", tilt_nN_per_um=5.0)
    result = CliRunner().invoke(app, ["validate", str(folder)])
    assert result.exit_code == 2, result.output
    assert "inputs.tilt_nN_per_um: expected a pierce drop" in result.output
    assert "Traceback" not in result.output


# --- 6, 9: afm_creep_prony: an indentation deeper than the cell, a tau beyond the record, a
# clamp force below its noise ------------------------------------------------------------

# the shipped series (E0 7.01 kPa, g 0.3 0.2, tau 0.2 1.5 s, 10 deg, 6 s) reaches 115.625 um
# at 7148.4 nN
CP_REFUSED = [
    ({"clamp_force_nN": 7200.0}, "inputs.clamp_force_nN: expected clamp_force_nN < the force"),
    ({"clamp_force_nN": 1e6}, "inputs.clamp_force_nN: expected clamp_force_nN < the force"),
    (
        {"clamp_force_nN": 500.0, "cell_diameter_um": 20.0},
        "indenting cell_diameter_um deep by the end of the hold = 213.877, got 500.0",
    ),
    ({"prony_tau_s": [0.2, 6.0]}, "inputs.prony_tau_s: expected max(prony_tau_s) < hold_s"),
    ({"prony_tau_s": [0.2, 5000.0]}, "inputs.prony_tau_s: expected max(prony_tau_s) < hold_s"),
    ({"clamp_force_nN": 0.79}, "inputs.clamp_force_nN: expected clamp_force_nN >= force_noise"),
    ({"clamp_force_nN": 1e-9}, "inputs.clamp_force_nN: expected clamp_force_nN >= force_noise"),
]
CP_ACCEPTED = [
    {"clamp_force_nN": 7100.0},
    {"clamp_force_nN": 500.0, "cell_diameter_um": 40.0},
    {"prony_tau_s": [0.2, 5.99]},
    {"clamp_force_nN": 0.81},
    {"clamp_force_nN": 0.5, "force_noise_nN": 0.0},
]


@pytest.mark.parametrize(("inputs", "fragment"), CP_REFUSED)
def test_creep_prony_refused(tmp_path: Path, inputs: dict, fragment: str) -> None:
    assert fragment in _refused(edited_case(tmp_path, "afm_creep_prony", **inputs))


@pytest.mark.parametrize("inputs", CP_ACCEPTED)
def test_creep_prony_accepted(tmp_path: Path, inputs: dict) -> None:
    load_case(edited_case(tmp_path, "afm_creep_prony", **inputs))


# --- 15: afm_shell_correction's ranges ------------------------------------------------------

SC_REFUSED = [
    {"dimitriadis_x": [0.55, 0.16]},
    {"dimitriadis_x": [-0.01, 0.5]},
    {"dimitriadis_x": [0.16, 1.01]},
    {"dimitriadis_x": [0.16, 100.0]},
    {"dimitriadis_x": [0.78, 1.0]},  # past the deepest x (0.773) of the FE check: no point
    {"garcia_y": [1.0, 0.1]},
    {"garcia_y": [0.5, 0.5]},
    {"garcia_y": [0.1, 1.01]},
    {"garcia_y": [0.99, 1.0]},  # past the deepest y (0.989)
]
SC_ACCEPTED = [
    {"dimitriadis_x": [0.0, 1.0]},
    {"dimitriadis_x": [0.77, 1.0]},
    {"garcia_y": [0.0, 1.0]},
    {"garcia_y": [0.98, 1.0]},
]


@pytest.mark.parametrize("inputs", SC_REFUSED)
def test_shell_correction_ranges_refused(tmp_path: Path, inputs: dict) -> None:
    (field,) = inputs
    message = _refused(edited_case(tmp_path, "afm_shell_correction", **inputs))
    assert f"inputs.{field}: expected a range [lo, hi] with 0 <= lo < hi <= 1" in message


@pytest.mark.parametrize("inputs", SC_ACCEPTED)
def test_shell_correction_ranges_accepted(tmp_path: Path, inputs: dict) -> None:
    load_case(edited_case(tmp_path, "afm_shell_correction", **inputs))


# --- 22: afm_fit_files: viscoelastic options of another relaxation -------------------------

VE = {"relaxation": "prony", "terms": 2, "use_retract": True, "joint_speeds": True}


@pytest.mark.parametrize(
    ("viscoelastic", "fragment"),
    [
        (
            {**VE, "relaxation": "sls", "terms": 3},
            'inputs.viscoelastic.terms: expected terms only with relaxation = "prony"',
        ),
        (
            {**VE, "t0_s": 5.0},
            'inputs.viscoelastic.t0_s: expected t0_s only with relaxation = "power_law"',
        ),
    ],
)
def test_viscoelastic_option_of_another_relaxation_refused(
    tmp_path: Path, viscoelastic: dict, fragment: str
) -> None:
    folder = edited_case(tmp_path, "afm_ramp_viscoelastic", viscoelastic=viscoelastic)
    assert fragment in _refused(folder)


@pytest.mark.parametrize(
    "viscoelastic",
    [
        {**VE, "terms": 3},
        {**VE, "relaxation": "sls"},  # the default terms: nothing ignored
        {**VE, "relaxation": "power_law", "t0_s": 5.0},
    ],
)
def test_viscoelastic_options_accepted(tmp_path: Path, viscoelastic: dict) -> None:
    load_case(edited_case(tmp_path, "afm_ramp_viscoelastic", viscoelastic=viscoelastic))


# --- 5: fe_verification's observed order from the meshes' own ratios -------------------------


@pytest.mark.parametrize(
    "sizes", [(0.5, 0.25, 0.125), (1.0, 0.5, 0.0625), (0.5, 0.4, 0.1), (4.0, 0.02, 0.0101)]
)
@pytest.mark.parametrize("order", [-1.0, 0.5, 2.4])
def test_observed_order_with_uneven_ratios(sizes: tuple[float, ...], order: float) -> None:
    values = [1.0 + 0.3 * h**order for h in sizes]
    assert observed_order(values, sizes=sizes) == pytest.approx(order, rel=1e-9)


def test_observed_order_constant_ratio_unchanged() -> None:
    forces = [0.42040, 0.42117, 0.42132]  # docs/fe.md, table row 7
    old = math.log(abs((forces[0] - forces[1]) / (forces[1] - forces[2]))) / math.log(2.0)
    assert observed_order(forces, sizes=[0.5, 0.25, 0.125]) == old
    assert observed_order(forces, 2.0) == old
    # fv_hertz_uneven's forces: the assumed ratio 2 gave -5.04, the ratios 2 and 8 give -1.49
    uneven = [0.420433, 0.420399, 0.421514]
    assert observed_order(uneven, sizes=[1.0, 0.5, 0.0625]) == pytest.approx(-1.4889, abs=1e-4)


def test_observed_order_refuses_sizes_not_refining() -> None:
    with pytest.raises(InputError, match="sizes: expected three positive, strictly decreasing"):
        observed_order([1.0, 2.0, 3.0], sizes=[0.5, 0.5, 0.25])


@pytest.mark.parametrize(
    ("fractions", "ok"), [([0.5, 0.25, 0.25], False), ([0.5, 0.25, 0.2499], True)]
)
def test_verification_fractions_strictly_decreasing(
    tmp_path: Path, fractions: list, ok: bool
) -> None:
    folder = edited_case(tmp_path, "fe_verification", hertz_fractions=fractions)
    if ok:
        load_case(folder)
    else:
        assert "inputs.hertz_fractions: expected strictly decreasing sizes" in _refused(folder)


# --- 3, 19: sweeps ---------------------------------------------------------------------------

LINEAR = """
kind = "analytic_linear"
description = "linear sweep"
[inputs]
x = [1.0, 2.0]
a = [1.0, 1.0]
c = 0.0
[sweep]
samples = 4
seed = 0
sensitivity = "none"
"""


def test_sweep_parameter_inside_another_refused(tmp_path: Path) -> None:
    text = LINEAR + (
        '[sweep.parameters."x.0"]\ndistribution = "uniform"\nlow = 0.0\nhigh = 1.0\n'
        '[sweep.parameters.x]\ndistribution = "list"\nvalues = [[100.0, 100.0]]\n'
    )
    message = _refused(_write(tmp_path / "lin", text))
    assert (
        "sweep.parameters.x.0: expected a path apart from sweep.parameters.x (both would set "
        "the same input)" in message
    )


def test_sweep_parameters_side_by_side_accepted(tmp_path: Path) -> None:
    text = LINEAR + (
        '[sweep.parameters."x.0"]\ndistribution = "uniform"\nlow = 0.0\nhigh = 1.0\n'
        '[sweep.parameters."x.1"]\ndistribution = "uniform"\nlow = 0.0\nhigh = 1.0\n'
    )
    load_case(_write(tmp_path / "lin", text))


def test_list_of_vectors_samples_whole_vectors(tmp_path: Path) -> None:
    from oocyte_fe.sweep.run import plan_samples

    text = LINEAR + (
        '[sweep.parameters.x]\ndistribution = "list"\nvalues = [[100.0, 100.0], [1.0, 2.0]]\n'
    )
    planned = plan_samples(load_case(_write(tmp_path / "lin", text)))
    assert len(planned) == 4 and all(p.case is not None and not p.error for p in planned)
    assert (
        sorted(map(tuple, (p.values["x"] for p in planned)))
        == [(1.0, 2.0)] * 2 + [(100.0, 100.0)] * 2
    )
    assert all(isinstance(p.values["x"], list) for p in planned)


def test_sweep_message_names_the_field_of_a_cross_field_rule(tmp_path: Path) -> None:
    folder = edited_case(tmp_path, "sweep_spindle_offset")
    bad = {"spindle_initial_um.0": {"distribution": "uniform", "low": 10.0, "high": 120.0}}
    message = _refused(_with_sweep(folder, bad))
    assert (
        "sweep.parameters.spindle_initial_um.0: expected values that inputs.spindle_initial_um "
        "accepts (norm(spindle_initial_um) < cell_diameter_um" in message
    )
    good = {"spindle_initial_um.0": {"distribution": "uniform", "low": 10.0, "high": 20.0}}
    load_case(_with_sweep(folder, good))


def test_sweep_whose_every_sample_fails_is_not_pass(tmp_path: Path) -> None:
    import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
    from oocyte_fe.sweep.cluster import dask_client
    from oocyte_fe.sweep.run import run_sweep

    text = (
        'kind = "test_echo"\ndescription = "every sample crashes"\n[inputs]\nx_um = 1.0\n'
        "[sweep]\nsamples = 2\nseed = 0\n"
        '[sweep.parameters.crash]\ndistribution = "list"\nvalues = [true]\n'
    )
    case = load_case(_write(tmp_path / "echo", text))
    with dask_client(workers=1) as client:
        result = run_sweep(case, tmp_path / "out", client)
    assert result.status == "ERROR", result
    assert "all 2 samples failed" in result.reason and "deliberate crash" in result.reason


def test_sample_the_model_refuses_names_the_field(tmp_path: Path) -> None:
    import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
    from oocyte_fe.sweep.run import plan_samples

    text = (
        'kind = "test_echo"\ndescription = "some samples below 0"\n[inputs]\nx_um = 1.0\n'
        "[sweep]\nsamples = 16\nseed = 0\n"
        '[sweep.parameters.x_um]\ndistribution = "normal"\nmean = 1.0\nsd = 5.0\nlower = -10.0\n'
    )
    planned = plan_samples(load_case(_write(tmp_path / "echo", text)))
    refused = [p for p in planned if p.case is None]
    assert refused and all(p.values["x_um"] <= 0 for p in refused)
    assert all(p.error.startswith("inputs.x_um: Input should be greater than 0") for p in refused)


@pytest.mark.parametrize(
    "sizes", [(0.5, 0.25, 0.125), (1.0, 0.5, 0.0625), (0.5, 0.4, 0.1), (4.0, 0.02, 0.0101)]
)
@pytest.mark.parametrize("order", [0.5, 2.4])
def test_monotone_order_is_the_order_of_a_converging_series(
    sizes: tuple[float, ...], order: float
) -> None:
    """``f = 1 + 0.3 h^p`` with p > 0 converges monotonically: its order, as ``observed_order``."""
    values = [1.0 + 0.3 * h**order for h in sizes]
    assert monotone_observed_order(values, sizes) == pytest.approx(order, rel=1e-9)


@pytest.mark.parametrize(
    "values",
    [
        [0.420433, 0.420399, 0.421167],  # the shipped Hertz forces: down, then up
        [1.0 + 0.3 * h**-1.0 for h in (0.5, 0.25, 0.125)],  # diverging (p = -1)
        [1.0, 1.1, 1.0],  # oscillating
        [1.0, 1.0, 1.1],  # no change, then a change
    ],
)
def test_monotone_order_is_nan_outside_the_asymptotic_range(values: list[float]) -> None:
    assert math.isnan(monotone_observed_order(values, (0.5, 0.25, 0.125)))
