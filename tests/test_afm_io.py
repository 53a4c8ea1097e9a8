"""Curve files (units at the boundary), bad input, optional extra, batch statistics."""

import math
import sys

import numpy as np
import pytest

from afm.batch import curve_files, fit_batch, write_batch_table
from afm.curve import ForceCurve
from afm.curve_io import read_curve, write_curve
from afm.fit import fit_indentation
from afm.plotting import plot_batch
from afm.synthetic import indentation_curve
from oocyte_fe.errors import InputError, MissingExtraError


def _write(path, text):
    path.write_text(text)
    return path


def test_units_are_converted_at_the_file_boundary(tmp_path):
    curve = indentation_curve(7.01, 5.0, n_points=200)
    k_N_per_m = 0.07
    rows = "\n".join(
        f"{z * 1e3!r}\t{f * 1e3!r}"
        for z, f in zip(curve.piezo_um.tolist(), curve.force_nN.tolist(), strict=True)
    )
    path = _write(
        tmp_path / "c.tsv",
        f"# spring_constant_N_per_m = {k_N_per_m}\nheight_nm\tforce_pN\n{rows}\n",
    )
    read = read_curve(path)
    np.testing.assert_allclose(read.piezo_um, curve.piezo_um, rtol=1e-12)
    np.testing.assert_allclose(read.force_nN, curve.force_nN, rtol=1e-12)
    assert read.spring_constant_nN_per_um == pytest.approx(70.0)


def test_deflection_in_volts_needs_the_sensitivity(tmp_path):
    # F = V * s * k: 0.2 V * 50 nm/V * 0.1 N/m = 1 nN
    body = "piezo_um,deflection_V\n" + "\n".join(f"{i * 0.1},{0.2}" for i in range(20))
    path = _write(tmp_path / "v.csv", "# spring_constant_N_per_m = 0.1\n" + body)
    with pytest.raises(InputError, match="sensitivity_nm_per_V"):
        read_curve(path)
    curve = read_curve(path, sensitivity_nm_per_V=50.0)
    np.testing.assert_allclose(curve.force_nN, 1.0)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", "empty"),
        ("# spring_constant_N_per_m = 0.07\npiezo_um\n1\n2\n", "two columns"),
        ("# spring_constant_N_per_m = 0.07\npiezo_um,force_nN\n" + "1,nan\n" * 12, "NaN"),
        (
            "# spring_constant_N_per_m = 0.07\npiezo_um,force_nN\n"
            + "".join(f"{v},0\n" for v in [0, 1, 2, 1.5, 3, 4, 5, 6, 7, 8, 9, 10]),
            "monotonic",
        ),
        ("# spring_constant_N_per_m = -0.07\npiezo_um,force_nN\n1,0\n2,0\n", "positive spring"),
        ("piezo_um,force_nN\n1,0\n2,0\n", "spring_constant_N_per_m"),
        ("# spring_constant_N_per_m = 0.07\npiezo_um,force_nN\n1,abc\n2,0\n", "numbers"),
        # the file's own line, comments and blank lines counted (was "row 1" of the data)
        (
            "# spring_constant_N_per_m = 0.07\n# a comment\n\npiezo_um,force_nN\n1,0\n2,x\n",
            r"line 6: expected numbers in every data row, got .*2,x",
        ),
        (
            "# spring_constant_N_per_m = 0.07\npiezo_um,force_nN\n1,0\n2,0,5\n",
            "line 4: expected 2 cells, as the header, got 3",
        ),
    ],
)
def test_bad_files_name_the_file_and_the_problem(tmp_path, text, match):
    path = _write(tmp_path / "bad.csv", text)
    with pytest.raises(InputError, match=match) as info:
        read_curve(path)
    assert str(path) in str(info.value)


def test_negative_spring_constant_in_python_is_refused():
    with pytest.raises(InputError, match="spring"):
        ForceCurve(np.arange(20.0), np.zeros(20), -1.0)


def test_instrument_file_without_afmformats_names_the_extra(tmp_path, monkeypatch):
    path = _write(tmp_path / "curve.jpk-force", "not really")
    monkeypatch.setitem(sys.modules, "afmformats", None)  # import now raises ImportError
    with pytest.raises(MissingExtraError, match="needs afmformats"):
        read_curve(path)


def test_batch_of_30_reports_the_drawn_mean_and_sd_and_skips_a_bad_curve(tmp_path):
    rng = np.random.default_rng(2025)
    drawn = rng.normal(7.01, 2.88, 60)
    drawn = drawn[drawn > 0.5][:30]  # N(7.01, 2.88) kPa, seed 001; non-physical draws dropped
    folder = tmp_path / "zp"
    folder.mkdir()
    for i, e in enumerate(drawn):
        curve = indentation_curve(e, 5.0, n_points=800, noise_fraction=0.01, seed=i, group="zp")
        write_curve(curve, folder / f"curve_{i:02d}.csv")
    _write(folder / "curve_99_broken.csv", "# spring_constant_N_per_m = 0.07\npiezo_um\n1\n")
    result = fit_batch(curve_files(tmp_path))
    assert len(result.rows) == 31
    assert [r.file.endswith("broken.csv") for r in result.failures] == [True]
    (stats,) = result.stats()
    assert stats.n == 30
    assert stats.mean_kPa == pytest.approx(drawn.mean(), rel=0.02)
    assert stats.sd_kPa == pytest.approx(drawn.std(ddof=1), rel=0.02)
    table = write_batch_table(result, tmp_path / "fits.csv").read_text().splitlines()
    assert len(table) == 32 and "two columns" in table[-1]
    assert math.isfinite(float(table[1].split(",")[2]))
    plots = plot_batch(result, tmp_path / "plots")  # one figure per good curve, none for bad
    assert len(plots) == 30 and all(p.stat().st_size > 10_000 for p in plots)
    assert not (tmp_path / "plots" / "curve_99_broken.png").exists()


def test_unreadable_instrument_file_names_the_file(tmp_path):
    pytest.importorskip("afmformats")
    path = _write(tmp_path / "curve.jpk-force", "not really")
    with pytest.raises(InputError, match="afmformats can read") as info:
        read_curve(path)
    assert str(path) in str(info.value)


def test_jittering_piezo_is_accepted_and_fitted_as_recorded(tmp_path):
    # a height sensor steps back by a few nm; the fit must not need sorted data
    curve = indentation_curve(7.01, 5.0, n_points=1000, noise_fraction=0.01, seed=4)
    jitter = 0.004 * np.random.default_rng(4).standard_normal(curve.piezo_um.size)  # 4 nm
    path = write_curve(curve, tmp_path / "c.csv")
    text = path.read_text().splitlines()
    rows = [
        f"{float(z) + float(j)!r},{f}"
        for (z, f), j in zip((r.split(",") for r in text[3:]), jitter, strict=True)
    ]
    path.write_text("\n".join(text[:3] + rows) + "\n")
    read = read_curve(path)
    assert np.count_nonzero(np.diff(read.piezo_um) < 0) > 50
    fit = fit_indentation(read)
    assert fit.E_kPa == pytest.approx(7.01, rel=0.03)


def test_a_height_channel_a_text_table_lacks_is_refused(tmp_path):
    path = write_curve(indentation_curve(7.01, 5.0, n_points=100), tmp_path / "c.csv")
    assert read_curve(path).height_channel == "piezo"
    with pytest.raises(InputError, match="height_channel"):
        read_curve(path, height_channel="height (measured)")
