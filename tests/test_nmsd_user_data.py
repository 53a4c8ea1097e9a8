"""A lab's own force-displacement file in the NMSD route (outside tester 5, items 1-8).

Each of these once either crashed ``run`` after ``validate`` said ok (no model column; forces
recorded negative), fitted a file in the wrong unit and reported PASS, compared the NMSD with
itself, or reported a constant the data do not determine with no word. The data of the runs
are the docs' own press (k1 3, k2 8000 nN, d0 14.6, d1 0.55, nodal, 40 steps, 5-60 um), so the
truth is known.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nmsd.identifiability import FLOOR, identifiability
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import press_setup
from nmsd.tableII import ForceDisplacement, read_force_displacement
from oocyte_fe.errors import InputError
from oocyte_fe.runner import run_case
from tests.case_copies import refused_message

TRUTH = NmsdParameters(
    k1=3.0, k2=8000.0, d0=14.6, d1=0.55, dl_c=0.8, node_mass=node_mass_for(115.625, 231)
)
D_UM = np.arange(5.0, 65.0, 5.0)


@pytest.fixture(scope="module")
def truth_uN() -> np.ndarray:
    """The docs' press at the truth constants, uN at ``D_UM`` (40 steps, as the cases)."""
    setup = press_setup(n_steps=40)
    return setup.run(TRUTH, record_um=D_UM).force_at(D_UM) * 1e-3


def _table(path: Path, header: str, rows: np.ndarray) -> Path:
    path.write_text(header + "\n" + "\n".join(",".join(f"{v:.9g}" for v in r) for r in rows))
    return path


def _case(folder: Path, header: str, rows: np.ndarray, **inputs: object) -> Path:
    """An ``nmsd_calibration`` case on ``rows``: one start, few presses (a test, not a fit)."""
    folder.mkdir()
    _table(folder / "data.csv", header, rows)
    settings = {
        "data": '"data.csv"',
        "n_starts": 1,
        "max_evaluations": 6,
        "models": '["nmsd"]',
        "rate_speeds_um_s": "[30.0]",
        "snapshot_um": "[30.0]",
        **inputs,
    }
    body = "\n".join(f"{k} = {v}" for k, v in settings.items())
    (folder / "case.toml").write_text(
        f'kind = "nmsd_calibration"\ndescription = "lab data"\n\n[inputs]\n{body}\n'
    )
    return folder


# --- items 1, 4, 5, 8: a lab file without the paper's model column ---------------------------


def test_lab_file_without_model_column_runs_and_reports_what_was_fitted(tmp_path, truth_uN):
    folder = _case(tmp_path / "lab", "displacement_um,force_experiment_uN", np.c_[D_UM, truth_uN])
    res = run_case(folder, out=tmp_path / "out")
    assert res.status == "PASS", res.result
    # no model column, no linear MSD, no cubic MSD: nan (null in metrics.json), not the
    # NMSD's own RMSE
    for metric in ("paper_rmse_uN", "rmse_linear_msd_uN", "rmse_msd_d0_uN"):
        assert res.metrics[metric] is None, metric
    assert list(res.checks["check"]) == ["NMSD fit better than the mean force (R^2 >= 0)"]
    report = (res.folder / "report.md").read_text()
    assert "no force_simulation column" in report
    assert "data.csv against the calibrated model families" in report
    assert "Table II" not in report.split("## Inputs")[0]
    # k1 moves the force of this press by < 0.1 % per factor e (docs/nmsd.md): not identified
    assert res.metrics["nmsd_not_identified"] >= 1
    k1_row = next(line for line in report.splitlines() if line.startswith("| nmsd | k1 |"))
    assert "not identified" in k1_row


def test_fit_worse_than_the_mean_force_fails_its_check(tmp_path, truth_uN):
    # a force falling with the press: the press's force rises, so R^2 < 0 whatever the fit
    folder = _case(
        tmp_path / "falling", "displacement_um,force_experiment_uN", np.c_[D_UM, truth_uN[::-1]]
    )
    res = run_case(folder, out=tmp_path / "out")
    row = res.checks.set_index("check").loc["NMSD fit better than the mean force (R^2 >= 0)"]
    assert res.metrics["r2"] < 0 and row["status"] == "FAIL" and res.status == "FAIL"


# --- item 5: identifiability from the Jacobian -----------------------------------------------


def test_k1_of_the_docs_press_is_not_identified_and_the_others_are(truth_uN):
    setup = press_setup(n_steps=40)
    data = ForceDisplacement(D_UM, truth_uN * 1e3)
    ident = identifiability([(setup, data)], TRUTH, ("k1", "k2", "d0", "d1"))
    # the truth fits to round-off: the noise level is the floor, 1 % of the RMS force
    assert ident.sigma_nN == pytest.approx(FLOOR * np.sqrt(np.mean(data.force_nN**2)), rel=1e-12)
    assert ident.not_identified == ("k1",)
    assert ident.relative_se["k1"] > 10  # measured 95
    for name in ("k2", "d0", "d1"):
        assert ident.relative_se[name] < 0.2, name  # measured 0.06-0.10


def test_a_constant_on_a_bound_is_not_identified(truth_uN):
    setup = press_setup(n_steps=40)
    data = ForceDisplacement(D_UM, truth_uN * 1e3)
    ident = identifiability([(setup, data)], TRUTH, ("k1", "k2", "d0", "d1"), pinned={"d1"})
    assert ident.relative_se["d1"] == math.inf and "d1" in ident.not_identified


def test_fewer_displacements_than_constants_are_refused(tmp_path, truth_uN):
    rows = np.c_[D_UM, truth_uN][[3, 7, 11]]
    message = refused_message(_case(tmp_path / "few", "displacement_um,force_experiment_uN", rows))
    assert "inputs.data: expected at least 4 displacements above gap_um = 0 um" in message
    assert message.endswith("got 3")


# --- items 2, 3, 6, 7: the reader ------------------------------------------------------------


@pytest.mark.parametrize(
    ("header", "d_scale", "f_scale"),
    [
        ("displacement_nm,force_experiment_nN", 1e3, 1e3),
        ("displacement_mm,force_experiment_mN", 1e-3, 1e-3),
        ("displacement_m,force_experiment_N", 1e-6, 1e-6),
    ],
)
def test_other_units_are_converted_at_the_boundary(tmp_path, truth_uN, header, d_scale, f_scale):
    data = read_force_displacement(
        _table(tmp_path / "t.csv", header, np.c_[D_UM * d_scale, truth_uN * f_scale])
    )
    np.testing.assert_allclose(data.displacement_um, D_UM, rtol=1e-8)
    np.testing.assert_allclose(data.force_nN, truth_uN * 1e3, rtol=1e-8)
    assert data.paper_model_nN is None


@pytest.mark.parametrize(
    ("separator", "decimal"),
    [("\t", "."), (";", ","), (";", ".")],
    ids=["tab", "semicolon-comma", "semicolon"],
)
def test_a_spreadsheet_export_reads_as_the_comma_file(tmp_path, truth_uN, separator, decimal):
    """Tab- and semicolon-separated exports (with a decimal comma: a European spreadsheet's)
    give the comma file's numbers exactly (the same cells, written with 9 digits)."""
    rows = np.c_[D_UM, truth_uN, 1.1 * truth_uN]
    header = ["displacement_um", "force_experiment_uN", "force_simulation_uN"]
    comma = read_force_displacement(_table(tmp_path / "t.csv", ",".join(header), rows))
    lines = [separator.join(header)] + [
        separator.join(f"{v:.9g}".replace(".", decimal) for v in row) for row in rows
    ]
    (tmp_path / "t.txt").write_text("\n".join(lines) + "\n")
    export = read_force_displacement(tmp_path / "t.txt")
    for name in ("displacement_um", "force_nN", "paper_model_nN"):
        np.testing.assert_array_equal(getattr(export, name), getattr(comma, name))


def test_a_bad_cell_of_a_semicolon_table_is_named_by_column_and_line(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("displacement_um;force_experiment_uN\n5;1,5\n10;2,x\n15;3\n")
    with pytest.raises(InputError, match=r"force_experiment_uN: expected numbers in every row "):
        read_force_displacement(path)
    with pytest.raises(InputError, match=r"\(line 3\)"):
        read_force_displacement(path)


@pytest.mark.parametrize(
    ("rows", "fragment"),
    [
        # compression recorded negative
        (lambda d, f: np.c_[d, -f], "force_experiment_uN: expected forces >= 0: compression is "),
        # nN written under uN: a peak of 5e4 "uN"
        (lambda d, f: np.c_[d, f * 1e3], "the values look like nN"),
        # mm written under um: a press of 0.055 "um"
        (lambda d, f: np.c_[d / 1e3, f], "the values look like mm"),
    ],
)
def test_sign_and_unit_mistakes_are_refused(tmp_path, truth_uN, rows, fragment):
    path = _table(tmp_path / "t.csv", "displacement_um,force_experiment_uN", rows(D_UM, truth_uN))
    with pytest.raises(InputError, match=fragment):
        read_force_displacement(path)


def test_negative_forces_name_their_line_and_baseline_noise_is_kept(tmp_path):
    text = "displacement_um,force_experiment_uN\n0,0\n2,-0.4\n4,10\n6,-1\n"
    path = tmp_path / "neg.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=r"\(line 5;.*got -1\.0"):
        read_force_displacement(path)
    path.write_text(text.replace("6,-1", "6,20"))  # -0.4 is 2 % of the peak: baseline noise
    assert read_force_displacement(path).force_nN[1] == pytest.approx(-400.0)


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("", "a header row and data rows (the file is empty)"),
        ("displacement_um,force_experiment_uN\n", "data rows below the header (the file has none)"),
        (
            "displacment_um,force_experiment_uN\n1,1\n2,2\n3,3\n",
            "expected a column displacement_nm or displacement_um or displacement_mm or "
            "displacement_m (units in the name) (did you mean 'displacement_um' for "
            "'displacment_um'?)",
        ),
    ],
)
def test_empty_or_misnamed_files_say_so(tmp_path, text, fragment):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(InputError) as err:
        read_force_displacement(path)
    assert fragment in str(err.value)
