"""A flow-curve fit's file read by the channel flow, and the fluids' flow withheld outside the
rates the flow curve was measured at (``microchannel_carreau_fit`` -> ``fitted_rheology.toml``
-> ``microchannel_flow``).

Numbers against closed forms: a Newtonian "Carreau" fluid (eta0 = eta_inf = mu) has the wall
rate ``4 U / R`` and ``U = G R^2 / (8 mu)`` in the pipe; the file keeps every parameter to the
last bit (floats written in full).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from oocyte_fe.errors import InputError
from oocyte_fe.microchannel.rheology_file import read_rheology_file, rheology_toml
from oocyte_fe.microchannel.viscosity import Rheology
from oocyte_fe.runner import run_case
from tests.case_copies import edited_case, refused_message, set_inputs

KPA_S = 1e-3  # 1 Pa s in kPa s
HAND = {"carreau": None, "power_law_consistency_Pa_s_n": None, "power_law_n": None}
SMALL = {"rectangle_cells": [4], "radial_cells": [4, 8]}


def _newtonian_flow(tmp_path: Path, rates: list[float] | None, **more: object) -> Path:
    """The shipped flow case with a Newtonian 'Carreau' fluid of 0.8 Pa s, its wall rates at
    200-900 hPa between 31 and 140 1/s (G R / (2 mu), G = Dp / L)."""
    return edited_case(
        tmp_path,
        "microchannel_flow",
        **{
            "carreau.eta0_Pa_s": 0.8,
            "carreau.eta_inf_Pa_s": 0.8,
            "shear_rate_range_1_s": rates,
            **SMALL,
            **more,
        },
    )


def _wall_rate(m: dict[str, float], pressure_hpa: float, mu_pa_s: float = 0.8) -> float:
    g = pressure_hpa * 0.1 / m["hydraulic_length"]  # kPa/um
    return 4.0 * (g * 125.0**2 / (8.0 * mu_pa_s * KPA_S)) / 125.0


def test_the_file_gives_back_every_parameter_exactly(tmp_path: Path) -> None:
    fits = {
        "carreau": Rheology.of(
            "carreau", eta0=1.434, eta_inf=1.368e-3, time_constant=661.3, n=0.04713
        ),
        "power_law": Rheology.of("power_law", consistency=4.132e-3, n=0.1319),
        "cross": Rheology.of("cross", eta0=0.9, eta_inf=1e-3, time_constant=3.0, m=0.7),
    }
    path = tmp_path / "fitted_rheology.toml"
    r2 = {"carreau": 0.9994, "power_law": 0.97, "cross": 0.99}
    path.write_text(rheology_toml(fits, r2, "table2.csv", (0.00172, 0.0524)))
    text = path.read_text()
    assert "eta0_Pa_s = 1434.0" in text and "consistency_Pa_s_n = 4.132" in text  # Pa s, Pa s^n
    back = read_rheology_file(path)
    assert back.shear_rate_range == (0.00172, 0.0524) and back.data == "table2.csv"
    for key, rheology in fits.items():
        assert dict(back.models[key].params) == pytest.approx(dict(rheology.params), rel=1e-15)


DATA = "[data]\nshear_rate_min_1_s = 0.1\nshear_rate_max_1_s = 1.0\n"


@pytest.mark.parametrize(
    ("edit", "field", "expected"),
    [
        (
            "[data]\nshear_rate_min_1_s = 1.0\nshear_rate_max_1_s = 0.1\n",
            "data.shear_rate_max_1_s",
            "above",
        ),
        ("[data]\nshear_rate_min_1_s = 0.1\n", "data.shear_rate_max_1_s", "a number"),
        (f"{DATA}[bingham]\nk = 1\n", "bingham", "a model table"),
        (f"{DATA}[power_law]\nn = 0.5\n", "power_law.consistency_Pa_s_n", "required"),
        (
            f"{DATA}[power_law]\nn = 0.5\nK = 2.0\nconsistency_Pa_s_n = 2.0\n",
            "power_law.K",
            "one of",
        ),
        (f"{DATA}[power_law]\nn = -0.5\nconsistency_Pa_s_n = 2.0\n", "power_law.n", ""),
    ],
)
def test_a_bad_file_names_itself_and_the_field(
    tmp_path: Path, edit: str, field: str, expected: str
) -> None:
    path = tmp_path / "r.toml"
    path.write_text(edit)
    with pytest.raises(InputError) as err:
        read_rheology_file(path)
    assert err.value.field == field and str(path) in str(err.value)
    assert expected in err.value.expected


def test_wall_rates_outside_the_measured_rates_are_withheld(tmp_path: Path) -> None:
    # wall rates 31 (200 hPa) ... 140 (900 hPa) 1/s; the reference 300 hPa at 47
    inside = run_case(_newtonian_flow(tmp_path / "in", [1.0, 1e3]), out=tmp_path / "o1")
    m = inside.scalars()
    assert m["carreau_mean_velocity_ref"] == pytest.approx(
        _wall_rate(m, 300.0) * 125.0 / 4.0, rel=1e-9
    )
    # measured up to 40 1/s: 200 hPa (31) shown, 300 hPa and above withheld
    cut = run_case(_newtonian_flow(tmp_path / "cut", [1.0, 40.0]), out=tmp_path / "o2")
    m = cut.scalars()
    assert "carreau_mean_velocity_ref" not in m  # NaN: not a figure
    assert 1.0 < _wall_rate(m, 200.0) < 40.0 < _wall_rate(m, 300.0)
    report = (cut.folder / "report.md").read_text()
    rows = {
        line.split("|")[1].strip(): line.split("|")[3:5]
        for line in report.splitlines()
        if line.startswith("| ") and line.count("|") == 9
    }
    assert [c.strip() for c in rows["300"]] == ["-", "-"]
    u200 = float(rows["200"][1]) * 1e3  # mm/s -> um/s
    assert u200 == pytest.approx(_wall_rate(m, 200.0) * 125.0 / 4.0, rel=1e-3)
    assert "measured at 1-40 1/s" in report
    # asked for: shown and marked
    shown = run_case(
        _newtonian_flow(tmp_path / "x", [1.0, 40.0], extrapolate=True), out=tmp_path / "o3"
    )
    assert shown.scalars()["carreau_mean_velocity_ref"] == pytest.approx(
        inside.scalars()["carreau_mean_velocity_ref"], rel=1e-12
    )
    assert "*" in (shown.folder / "report.md").read_text().split("fluids at each pressure")[1]


def test_the_shipped_case_withholds_the_fluids_at_the_channels_rates(tmp_path: Path) -> None:
    # Table 2's rates end at 0.0524 1/s; the channel's wall rates start at 16 (Carreau) and
    # 8e5 (power law) 1/s: before, the power law's extrapolation gave U up to 1e9 mm/s
    result = run_case(edited_case(tmp_path, "microchannel_flow"), out=tmp_path / "o", quick=True)
    m = result.scalars()
    assert result.status == "PASS"
    assert "carreau_mean_velocity_ref" not in m and "power_law_mean_velocity_ref" not in m
    assert "14 of 14 flows have a wall rate outside it" in (result.folder / "report.md").read_text()


def test_a_flow_case_runs_on_a_fits_file_as_on_its_numbers(tmp_path: Path) -> None:
    """A synthetic flow curve (Carreau eta0 50, eta_inf 0.5 Pa s, lambda 10 s, n 0.4 at
    1e-3-1e3 1/s) fitted; its fitted_rheology.toml copied into the flow case gives every
    metric of the same case with the fitted numbers typed in (to 1e-12)."""
    rates = np.logspace(-3, 3, 25)
    eta = 0.5 + 49.5 * (1.0 + (10.0 * rates) ** 2) ** (-0.3)
    fit = tmp_path / "fit"
    fit.mkdir()
    (fit / "curve.csv").write_text(
        "strain_rate_1_s,viscosity_Pa_s\n"
        + "".join(f"{r:.10g},{e:.10g}\n" for r, e in zip(rates, eta, strict=True))
    )
    (fit / "case.toml").write_text(
        'kind = "microchannel_carreau_fit"\ndescription = "a lab curve"\n[inputs]\n'
        'data = "curve.csv"\nmodels = ["carreau", "power_law"]\n'
    )
    fitted = run_case(fit, out=tmp_path / "fit_out").folder / "fitted_rheology.toml"
    back = read_rheology_file(fitted)
    assert back.shear_rate_range == pytest.approx((1e-3, 1e3), rel=1e-9)
    carreau = back.models["carreau"].params
    assert carreau["eta0"] / KPA_S == pytest.approx(50.0, rel=1e-6)
    from_file = _newtonian_flow(tmp_path / "file", None, extrapolate=True, **HAND)
    shutil.copy(fitted, from_file / "fitted_rheology.toml")
    set_inputs(from_file, rheology_file="fitted_rheology.toml")
    power = back.models["power_law"].params
    by_hand = _newtonian_flow(
        tmp_path / "hand",
        [float(x) for x in back.shear_rate_range],
        extrapolate=True,
        **{
            "carreau.eta0_Pa_s": carreau["eta0"] / KPA_S,
            "carreau.eta_inf_Pa_s": carreau["eta_inf"] / KPA_S,
            "carreau.time_constant_s": carreau["time_constant"],
            "carreau.n": carreau["n"],
            "power_law_consistency_Pa_s_n": power["consistency"] / KPA_S,
            "power_law_n": power["n"],
        },
    )
    a = run_case(from_file, out=tmp_path / "o1").scalars().to_dict()
    b = run_case(by_hand, out=tmp_path / "o2").scalars().to_dict()
    assert list(a.keys()) == list(b.keys()) and "power_law_mean_velocity_ref" in a
    for key in a:
        assert np.allclose(a[key], b[key], rtol=1e-12, atol=0.0, equal_nan=True), key


@pytest.mark.parametrize(
    ("inputs", "says"),
    [
        (
            {"rheology_file": "fitted_rheology.toml"},
            "inputs.carreau: expected not given with rheology_file",
        ),
        ({"carreau": None}, "inputs.carreau: expected a value (or a rheology_file"),
        ({"power_law_n": None}, "inputs.power_law_n: expected a value (or a rheology_file"),
        ({"shear_rate_range_1_s": [1.0, 0.5]}, "inputs.shear_rate_range_1_s: expected the lowest"),
        (
            {"rheology_file": "fitted_rheology.toml", **HAND},
            "fitted_rheology.toml (from case.toml: inputs.rheology_file): power_law: expected a "
            "[power_law] table (the file has carreau",
        ),
    ],
)
def test_the_fluids_come_from_one_source(tmp_path: Path, inputs: dict, says: str) -> None:
    folder = edited_case(tmp_path, "microchannel_flow", shear_rate_range_1_s=None)
    (folder / "fitted_rheology.toml").write_text(
        rheology_toml(
            {"carreau": Rheology.of("carreau", eta0=1.0, eta_inf=1e-3, time_constant=1.0, n=0.5)},
            {"carreau": 0.99},
            "curve.csv",
            (0.01, 10.0),
        )
    )
    assert says in refused_message(set_inputs(folder, **inputs))
