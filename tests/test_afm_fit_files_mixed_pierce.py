"""Pierce-through and plain curves in one ``afm_fit_files`` case: ``pierce`` as a list of groups.

The curves are made by afm/synthetic.py (Sneddon cone, half angle 10 deg, nu 0.5): the group
``pierced`` holds :func:`~afm.synthetic.pierce_curve` curves (the ZP pierced at 8 nN, the force
dropping to 0.3 of it, the cytoplasm indented after the drop), the group ``shallow`` plain
:func:`~afm.synthetic.indentation_curve` curves; both with a baseline offset and tilt and
0.5 % noise. Only ``pierced`` is named in ``pierce``: its curves get both layers, the others
one.
"""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from afm.curve_io import write_curve
from afm.synthetic import indentation_curve, pierce_curve
from oocyte_fe.cli import app
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.run import plan, run_cases

PIERCED = {"p1": (7.0, 1.55), "p2": (5.0, 2.0)}  # file -> (E_ZP, E_cytoplasm) [kPa]
SHALLOW = {"s1": 3.0, "s2": 4.0}  # file -> E [kPa]
TOLERANCE = 0.02  # relative, every modulus (measured: within 0.5 %)
GROUP_PATTERNS = '\ngroups = { zona = "curves/pierced/*", plain = "curves/shallow/*" }'


def _case(folder: Path, pierce: str, extra: str = "") -> Path:
    """A case folder: the curves of :data:`PIERCED` in ``curves/pierced/``, those of
    :data:`SHALLOW` in ``curves/shallow/``, and ``case.toml`` with ``pierce`` (TOML)."""
    for sub in ("pierced", "shallow"):
        (folder / "curves" / sub).mkdir(parents=True)
    for seed, (name, (e_zp, e_cyt)) in enumerate(PIERCED.items()):
        curve = pierce_curve(
            e_zp, e_cyt, n_points=800, k_nN_per_um=70.0, offset_nN=0.3, tilt_nN_per_um=0.05,
            noise_fraction=0.005, seed=seed, geometry={"half_angle_deg": 10.0},
        )  # fmt: skip
        write_curve(curve, folder / "curves" / "pierced" / f"{name}.csv")
    for seed, (name, e) in enumerate(SHALLOW.items()):
        curve = indentation_curve(
            e, 5.0, n_points=800, offset_nN=0.3, tilt_nN_per_um=0.05, noise_fraction=0.005,
            seed=10 + seed, geometry={"half_angle_deg": 10.0},
        )  # fmt: skip
        write_curve(curve, folder / "curves" / "shallow" / f"{name}.csv")
    (folder / "case.toml").write_text(
        'kind = "afm_fit_files"\ndescription = "mixed"\n[inputs]\ncurves = "curves"\n'
        'model = "sneddon_cone"\ngeometry = { half_angle_deg = 10.0 }\nnu = 0.5\n'
        f"pierce = {pierce}{extra}\n"
    )
    return folder


@pytest.mark.parametrize(
    ("zona", "plain", "extra"),
    [("pierced", "shallow", ""), ("zona", "plain", GROUP_PATTERNS)],
    ids=["subfolders", "group_patterns"],
)
def test_pierce_groups_get_both_layers_and_the_others_one(tmp_path, zona, plain, extra):
    case = _case(tmp_path / "mixed", f'["{zona}"]', extra)
    assert load_case(case).inputs.pierce == [zona]
    [result] = run_cases(plan([case], quick=True), tmp_path / "out", quick=True)
    assert result.status == "PASS", result.reason
    out = tmp_path / "out" / "mixed"
    with (out / "fits.csv").open() as fh:
        rows = {Path(r["file"]).stem: r for r in csv.DictReader(fh)}
    for name, (e_zp, e_cyt) in PIERCED.items():
        row = rows[name]
        assert (row["group"], row["quality"]) == (zona, "good"), row["rating"]
        assert float(row["E_kPa"]) == pytest.approx(e_zp, rel=TOLERANCE)
        assert float(row["E_cytoplasm_kPa"]) == pytest.approx(e_cyt, rel=TOLERANCE)
        assert (out / "curve_plots" / f"{name}_pierce.png").is_file()
    for name, e in SHALLOW.items():
        row = rows[name]
        assert (row["group"], row["quality"], row["E_cytoplasm_kPa"]) == (plain, "good", "")
        assert float(row["E_kPa"]) == pytest.approx(e, rel=TOLERANCE)
        assert not (out / "curve_plots" / f"{name}_pierce.png").exists()
    metrics = json.loads((out / "metrics.json").read_text())["metrics"]
    assert (metrics["n_fitted"], metrics["n_failed"], metrics["n_no_pierce"]) == (4, 0, 0)

    def material(name: str) -> dict:
        return tomllib.loads((out / f"material_{name}.toml").read_text())["material"]

    # the pierce group: one material per layer, each the mean of its curves' moduli
    mean_zp, mean_cyt = (sum(v) / len(PIERCED) for v in zip(*PIERCED.values(), strict=True))
    assert material(f"{zona}_zp")["E_kPa"] == pytest.approx(mean_zp, rel=TOLERANCE)
    assert material(f"{zona}_cytoplasm")["E_kPa"] == pytest.approx(mean_cyt, rel=TOLERANCE)
    assert not (out / f"material_{zona}.toml").exists()
    # the plain group: its one material
    mean_plain = sum(SHALLOW.values()) / len(SHALLOW)
    assert material(plain)["E_kPa"] == pytest.approx(mean_plain, rel=TOLERANCE)
    assert not (out / f"material_{plain}_zp.toml").exists()
    assert not (out / f"material_{plain}_cytoplasm.toml").exists()
    report = (out / "report.md").read_text()
    for line in (f"| {zona} | ZP | 2 | 0 |", f"| {zona} | cytoplasm | 2 | 0 |"):
        assert line in report
    assert f"| {plain} | one layer | 2 | 0 |" in report
    assert f'Pierce-through curves (pierce = ["{zona}"])' in report
    assert "0 without a detectable pierce" in report


@pytest.mark.parametrize(
    ("pierce", "extra", "groups"),
    [('["pierced", "zq"]', "", "pierced, shallow"), ('["zq"]', GROUP_PATTERNS, "plain, zona")],
    ids=["subfolders", "group_patterns"],
)
def test_validate_refuses_a_pierce_name_that_is_no_group(tmp_path, pierce, extra, groups):
    case = _case(tmp_path / "bad", pierce, extra)
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [
        f"invalid {case}/case.toml: inputs.pierce: expected true, false or names of groups of "
        f"the curve files (one of {groups}: their subfolders, '# group' metadata or "
        "inputs.groups), got 'zq'"
    ]


def test_a_pierce_list_refuses_what_pierce_cannot_take(tmp_path):
    case = _case(tmp_path / "nanite", '["pierced"]', '\nanalysis = "nanite"')
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [
        f'invalid {case}/case.toml: inputs.analysis: expected analysis = "default" with pierce '
        "= [\"pierced\"] (both layers are fitted by afm.fit), got 'nanite'"
    ]


def test_validate_refuses_a_pierce_that_is_no_bool_and_no_list(tmp_path):
    case = _case(tmp_path / "string", '"pierced"')
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [
        f"invalid {case}/case.toml: inputs.pierce: expected true, false or a list of one or "
        "more group names, e.g. [\"zp\"], got 'pierced'"
    ]


@pytest.mark.parametrize(
    ("pierce", "expected"),
    [
        ("[]", 'true, false or a list of one or more group names, e.g. ["zp"]'),
        ('["pierced", "pierced"]', "each group once (named twice: pierced)"),
    ],
    ids=["empty", "twice"],
)
def test_validate_refuses_an_empty_pierce_list_or_a_group_named_twice(tmp_path, pierce, expected):
    case = _case(tmp_path / "list", pierce)
    result = CliRunner().invoke(app, ["validate", str(case)])
    assert result.exit_code == 2, result.output
    (line,) = result.output.strip().splitlines()
    assert line.startswith(f"invalid {case}/case.toml: inputs.pierce: expected {expected}, got")
