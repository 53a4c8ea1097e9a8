"""Benchmark: Sneddon-cone fits per second on synthetic curves, against nanite if installed.

Usage: python benchmarks/afm_fit.py [n_curves] [n_points]   (defaults 1000 curves, 2000 points)

Each curve has a known E drawn from N(7.01, 2.88) kPa (floored at 1 kPa), contact point 5 um,
1 % force noise and a baseline offset. Both tools fit the whole approach segment with the
contact point free; timed per curve from arrays to fitted E (nanite: building its Indentation
object, preprocessing tip position/force offset/tip offset, lmfit fit of ``hertz_cone``; afm:
``fit_indentation`` with baseline removal and contact estimate). Prints fits per second, the
ratio, and how far each tool's E is from the known one and from the other's.
"""

from __future__ import annotations

import importlib.util
import sys
import time

import numpy as np

from afm.curve import ForceCurve
from afm.fit import fit_indentation
from afm.synthetic import indentation_curve


def make_curves(n_curves: int, n_points: int, seed: int = 1) -> tuple[list[ForceCurve], np.ndarray]:
    rng = np.random.default_rng(seed)
    moduli = np.maximum(rng.normal(7.01, 2.88, n_curves), 1.0)
    curves = [
        indentation_curve(
            e, 5.0, n_points=n_points, noise_fraction=0.01, offset_nN=0.2, seed=int(i)
        )
        for i, e in enumerate(moduli)
    ]
    return curves, moduli


def fit_afm(curves: list[ForceCurve]) -> tuple[np.ndarray, float]:
    start = time.perf_counter()
    moduli = np.array([fit_indentation(c).E_kPa for c in curves])
    return moduli, time.perf_counter() - start


def fit_nanite(curves: list[ForceCurve]) -> tuple[np.ndarray, float]:
    import nanite

    moduli = []
    start = time.perf_counter()
    for c in curves:
        n = c.piezo_um.size
        data = {
            "force": c.force_nN * 1e-9,
            "height (measured)": -c.piezo_um * 1e-6,
            "segment": np.zeros(n, dtype=bool),
            "time": np.linspace(0.0, 1.0, n),
        }
        meta = {
            "spring constant": c.spring_constant_nN_per_um / 1e3,
            "sensitivity": 50e-9,
            "duration": 1.0,
            "rate approach": float(n),
            "point count": n,
            "imaging mode": "force-distance",
            "path": "synthetic",
            "enum": 0,
        }
        idnt = nanite.Indentation(data, meta)
        idnt.apply_preprocessing(
            ["compute_tip_position", "correct_force_offset", "correct_tip_offset"]
        )
        params = idnt.get_initial_fit_parameters(model_key="hertz_cone")
        params["alpha"].set(10.0)
        params["nu"].set(0.5)
        idnt.fit_model(
            model_key="hertz_cone",
            params_initial=params,
            range_type="absolute",
            range_x=(-np.inf, np.inf),
            x_axis="tip position",
            y_axis="force",
        )
        moduli.append(idnt.fit_properties["params_fitted"]["E"].value * 1e-3)  # Pa -> kPa
    return np.array(moduli), time.perf_counter() - start


def main(n_curves: int = 1000, n_points: int = 2000) -> None:
    curves, truth = make_curves(n_curves, n_points)
    fit_afm(curves[:5])  # warm-up
    e_afm, t_afm = fit_afm(curves)
    err = np.abs(e_afm / truth - 1)
    print(f"{n_curves} curves x {n_points} points, Sneddon cone 10 deg, nu 0.5")
    print(f"afm:    {n_curves / t_afm:8.1f} fits/s  |E/E_true - 1| median {np.median(err):.2%}")
    if importlib.util.find_spec("nanite") is None:
        print("nanite: not installed (pip install nanite) - no comparison")
        return
    e_nan, t_nan = fit_nanite(curves)
    err_n = np.abs(e_nan / truth - 1)
    agree = np.abs(e_afm / e_nan - 1)
    print(f"nanite: {n_curves / t_nan:8.1f} fits/s  |E/E_true - 1| median {np.median(err_n):.2%}")
    print(f"speed ratio afm / nanite: {t_nan / t_afm:.2f}x")
    print(
        f"E afm vs nanite: median {np.median(agree):.3%}, max {agree.max():.3%}, "
        f"within 1 %: {np.mean(agree < 0.01):.1%} of curves"
    )


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
