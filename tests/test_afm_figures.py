"""Issue 28 A items 5 and 6: per-curve plots, the moduli per group and the modulus map show
what a reader needs (contact region, residuals, every contact point, the curve's name, why a
curve was refused; a log axis; the map's own grid pixels, poor fits marked)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from afm.batch import fit_batch
from afm.curve import ForceCurve
from afm.curve_plots import BASELINE_SHOWN, MAX_BASELINE_POINTS, CurveFigure, plot_curves
from afm.fit import fit_indentation
from afm.plotting import modulus_map_figure, strip_figure
from afm.synthetic import indentation_curve


def _long_curve() -> ForceCurve:
    # 10 000 points over 25 um with contact at 20 um: the contact region is 5 um of 25
    curve = indentation_curve(
        5.0, 20.0, max_piezo_um=25.0, n_points=10_000, noise_fraction=0.01, seed=2
    )
    return ForceCurve(
        curve.piezo_um,
        curve.force_nN,
        curve.spring_constant_nN_per_um,
        "map.h5",
        height_channel="height (measured)",
    )


def test_curve_plot_shows_the_contact_region_every_contact_point_and_residuals(tmp_path):
    fit = fit_indentation(_long_curve())
    figure = CurveFigure()
    figure.draw(fit, tmp_path / "c.png", "map.h5, curve 7 at (1, 2) um")
    delta = figure.data.get_xdata()
    depth = fit.max_indentation_um
    assert np.count_nonzero(delta > 0) == fit.n_contact_points  # none thinned away
    assert np.count_nonzero(delta <= 0) <= MAX_BASELINE_POINTS + 1
    assert delta.min() >= -BASELINE_SHOWN * depth - 1e-9  # not the whole 20 um approach
    left, right = figure.ax_f.get_xlim()
    assert right - left < 2.0 * depth
    np.testing.assert_allclose(
        figure.residual.get_ydata(), figure.data.get_ydata() - figure.model.get_ydata()
    )
    d_e, e = fit.pointwise_modulus(0.1 * depth)
    assert figure.pointwise.get_xdata().size == d_e.size  # E(delta) not thinned either
    assert "curve 7 at (1, 2) um" in figure.title.get_text()
    assert "measured height - F/k" in figure.ax_r.get_xlabel()
    assert (tmp_path / "c.png").stat().st_size > 10_000
    figure.close()


def _map_batch() -> tuple:
    # a 3 x 2 map, 10 um pitch, positions jittered by up to 0.3 um; curve 4 a paraboloid's
    # (rated poor with a cone), curve 5 without contact (refused)
    rng = np.random.default_rng(3)
    moduli = [2.0, 4.0, 8.0, 16.0, 5.0, 5.0]
    curves = []
    for i, e in enumerate(moduli):
        options = {"model": "hertz_paraboloid", "geometry": {"radius_um": 5.0}} if i == 4 else {}
        base = indentation_curve(
            e,
            9.0 if i == 5 else 3.0,
            max_piezo_um=6.0,
            n_points=400,
            noise_fraction=0.01,
            seed=i,
            **options,
        )
        xy = (10.0 * (i % 3) + rng.uniform(-0.3, 0.3), 10.0 * (i // 3) + rng.uniform(-0.3, 0.3))
        curves.append(
            ForceCurve(
                base.piezo_um,
                base.force_nN,
                base.spring_constant_nN_per_um,
                f"m.h5 (curve {i})",
                map_position_um=xy,
                curve_index=i,
            )
        )
    result = fit_batch([Path("m.h5")], reader=lambda _file: curves)
    return result, moduli


def test_modulus_map_fills_the_maps_grid_and_marks_poor_and_refused():
    result, moduli = _map_batch()
    assert [r.good for r in result.rows] == [True, True, True, True, False, False]
    fig = modulus_map_figure(result, "m.h5")
    ax = fig.axes[0]
    [mesh] = ax.collections[:1]
    grid = mesh.get_array()
    fitted = [r.fit.E_kPa for r in result.rows[:5]]
    np.testing.assert_allclose(grid.compressed(), fitted, rtol=1e-12)  # rows of the grid
    assert grid.mask.ravel().tolist() == [False] * 5 + [True]  # refused: a grey pixel
    # pixels are the map's 10 um pitch, not fixed-size squares
    corners = mesh.get_coordinates()
    assert list(np.diff(corners[0, :, 0])) == pytest.approx([10.0] * 3, abs=0.6)
    assert list(np.diff(corners[:, 0, 1])) == pytest.approx([10.0] * 2, abs=0.6)
    rings = ax.collections[1].get_offsets()
    assert len(rings) == 1  # the poor curve 4
    assert fitted[1] == pytest.approx(moduli[1], rel=0.05)
    assert "m.h5: modulus map (6 curves)" in ax.get_title()
    plt.close(fig)


def test_moduli_per_group_on_a_log_axis_with_poor_fits_open():
    result, _ = _map_batch()
    fits = {"map": [r.fit for r in result.rows if r.fit is not None]}
    fig = strip_figure(fits)
    ax = fig.axes[0]
    assert ax.get_yscale() == "log"
    good, poor = ax.collections[0].get_offsets(), ax.collections[1].get_offsets()
    np.testing.assert_allclose(sorted(good[:, 1]), sorted(f.E_kPa for f in fits["map"][:4]))
    np.testing.assert_allclose(poor[:, 1], [fits["map"][4].E_kPa])
    plt.close(fig)


def test_refused_curves_get_a_plot_and_poor_ones_can_be_picked(tmp_path):
    result, _ = _map_batch()
    every = plot_curves(result, tmp_path / "all")
    assert len(every) == 6  # the refused curve 5 too
    picked = sorted(p.name for p in plot_curves(result, tmp_path / "poor", which="poor"))
    assert picked == ["m_curve0004.png", "m_curve0005.png"]
    assert plot_curves(result, tmp_path / "none", which="none") == []
