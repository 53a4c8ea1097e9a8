"""Sweep table: load-time errors (one line naming file, field, expectation), paths, designs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import tests.kinds_for_tests  # noqa: F401  (registers test_echo)
from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.sweep.paths import PathError, set_path
from oocyte_fe.sweep.sampling import design
from oocyte_fe.sweep.spec import SweepSpec
from oocyte_fe.sweep.store import sample_key

SWEEP = """
kind = "test_echo"
description = "echo sweep"
[inputs]
x_um = 2.0
[sweep]
samples = 8
seed = 1
[sweep.parameters.x_um]
distribution = "uniform"
low = 1.0
high = 3.0
[reference."y_um.mean"]
value = 4.0
source = "analytic: y = 2 x, x uniform on [1, 3]"
[tolerances."y_um.mean"]
rel = 0.05
"""


def write_case(tmp_path: Path, text: str) -> Path:
    d = tmp_path / "case"
    d.mkdir()
    (d / "case.toml").write_text(text)
    return d


def test_valid_sweep_case_loads(tmp_path: Path) -> None:
    case = load_case(write_case(tmp_path, SWEEP))
    assert case.spec.sweep is not None and case.spec.sweep.count(quick=False) == 8


@pytest.mark.parametrize(
    ("old", "new", "field", "fragment"),
    [
        ("parameters.x_um]", "parameters.nope]", "sweep.parameters.nope", "no such key"),
        ("parameters.x_um]", 'parameters."x_um.0"]', "sweep.parameters.x_um.0", "single value"),
        ("low = 1.0", "low = -1.0", "sweep.parameters.x_um", "greater than 0"),
        ("high = 3.0", "high = 0.5", "sweep.parameters.x_um.uniform", "high > low"),
        ('"uniform"', '"gamma"', "sweep.parameters.x_um", "normal"),
        ("samples = 8", 'samples = 10\nsampler = "sobol"', "sweep", "power of 2"),
        ("samples = 8", "samples = 1", "sweep.samples", "greater than or equal to 2"),
        ("seed = 1", "seed = 1\ncolour = 2", "sweep.colour", "unknown key"),
        ('[reference."y_um.mean"]', "[reference.y_um]", "reference.y_um", "sweep statistic"),
        ("seed = 1", 'seed = 1\nmetrics = ["z"]', "sweep.metrics", "metrics of kind"),
    ],
)
def test_malformed_sweep_messages(
    tmp_path: Path, old: str, new: str, field: str, fragment: str
) -> None:
    d = write_case(tmp_path, SWEEP.replace(old, new))
    with pytest.raises(InputError) as info:
        load_case(d)
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(str(d / "case.toml"))
    assert f": {field}:" in msg
    assert fragment in msg


def test_list_values_are_validated_each(tmp_path: Path) -> None:
    text = SWEEP.replace(
        'distribution = "uniform"\nlow = 1.0\nhigh = 3.0', 'distribution = "list"\nvalues = [1, -2]'
    )
    with pytest.raises(InputError, match=r"sweep\.parameters\.x_um: .*greater than 0\), got -2"):
        load_case(write_case(tmp_path, text))


def test_set_path_nested_and_list_items() -> None:
    data = {"zp": {"E_kPa": 7.0}, "x": (1.0, 2.0)}
    assert set_path(data, "zp.E_kPa", 9.0)["zp"]["E_kPa"] == 9.0
    assert set_path(data, "x.1", 5.0)["x"] == [1.0, 5.0]
    assert data == {"zp": {"E_kPa": 7.0}, "x": (1.0, 2.0)}  # a copy, not in place
    with pytest.raises(PathError, match="an index below 2"):
        set_path(data, "x.2", 0.0)
    with pytest.raises(PathError, match="not an input table"):
        set_path(data, "cyto.E_kPa", 0.0)


def spec(**params: dict) -> SweepSpec:
    return SweepSpec.model_validate({"samples": 16, "seed": 4, "parameters": params})


def test_latin_hypercube_takes_each_list_value_once() -> None:
    d = design(spec(k={"distribution": "list", "values": list(range(16))}))
    assert sorted(v["k"] for v in d.values) == list(range(16))


def test_distributions_map_strata_into_their_support() -> None:
    d = design(
        spec(
            e={"distribution": "normal", "mean": 1.0, "sd": 2.0},
            f={"distribution": "loguniform", "low": 0.01, "high": 1.0},
            g={"distribution": "uniform", "low": 0.1, "high": 0.3},
        )
    )
    e, f, g = (np.array([v[k] for v in d.values]) for k in "efg")
    assert e.min() > 0  # truncated to positive values
    assert 0.01 <= f.min() and f.max() <= 1.0
    # log-uniform: one Latin-hypercube point per decade quarter -> 8 below 0.1, 8 above
    assert np.sum(f < 0.1) == 8
    assert 0.1 <= g.min() and g.max() <= 0.3
    # uniform strata: exactly one point in each sixteenth of [0.1, 0.3]
    assert sorted(np.floor((g - 0.1) / 0.2 * 16).astype(int)) == list(range(16))


def test_design_and_keys_are_deterministic() -> None:
    s = spec(g={"distribution": "uniform", "low": 0.1, "high": 0.3})
    assert design(s).values == design(s).values
    base = {"x_um": 2.0}
    k1 = sample_key("test_echo", base, design(s).values[0])
    assert k1 == sample_key("test_echo", dict(base), dict(design(s).values[0]))
    assert k1 != sample_key("test_echo", {"x_um": 2.5}, design(s).values[0])
    assert k1 != sample_key("test_echo", base, design(s).values[1])
