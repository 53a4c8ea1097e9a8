"""Benchmark: Sneddon-cone fits per second on synthetic curves, against nanite if installed.

Usage: python benchmarks/afm_fit.py [n_curves] [n_points]   (defaults 1000 curves, 2000 points)

Each curve has a known E drawn from N(7.01, 2.88) kPa (floored at 1 kPa), contact point 5 um,
1 % force noise and a baseline offset. Both tools fit the whole approach segment with the
contact point free; timed per curve from arrays to fitted E (nanite: building its Indentation
object, preprocessing tip position/force offset/tip offset, lmfit fit of ``hertz_cone``; afm:
``fit_indentation`` with baseline removal and contact estimate). The two tools fit each curve
in turn (alternately, in one process, so both see the same machine load). Prints curves per
second, the ratio, and how far each tool's E is from the known one and from the other's.
Run it from the repository root with ``PYTHONPATH=.`` so this checkout's ``afm`` is timed.
"""

from __future__ import annotations

import importlib.util
import sys
import time
from collections.abc import Callable

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


def fit_afm(curve: ForceCurve) -> float:
    """E [kPa] by ``fit_indentation`` (baseline, contact estimate, Sneddon cone, x0 free)."""
    return fit_indentation(curve).E_kPa


def fit_nanite(curve: ForceCurve) -> float:
    """E [kPa] by nanite's ``hertz_cone`` after its default preprocessing."""
    import nanite

    n = curve.piezo_um.size
    data = {
        "force": curve.force_nN * 1e-9,
        "height (measured)": -curve.piezo_um * 1e-6,
        "segment": np.zeros(n, dtype=bool),
        "time": np.linspace(0.0, 1.0, n),
    }
    meta = {
        "spring constant": curve.spring_constant_nN_per_um / 1e3,
        "sensitivity": 50e-9,
        "duration": 1.0,
        "rate approach": float(n),
        "point count": n,
        "imaging mode": "force-distance",
        "path": "synthetic",
        "enum": 0,
    }
    idnt = nanite.Indentation(data, meta)
    idnt.apply_preprocessing(["compute_tip_position", "correct_force_offset", "correct_tip_offset"])
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
    return idnt.fit_properties["params_fitted"]["E"].value * 1e-3  # Pa -> kPa


def timed(fit: Callable[[ForceCurve], float], curve: ForceCurve) -> tuple[float, float]:
    start = time.perf_counter()
    value = fit(curve)
    return value, time.perf_counter() - start


def main(n_curves: int = 1000, n_points: int = 2000) -> None:
    curves, truth = make_curves(n_curves, n_points)
    have_nanite = importlib.util.find_spec("nanite") is not None
    tools = [fit_afm, fit_nanite] if have_nanite else [fit_afm]
    for fit in tools:  # warm-up (imports, caches)
        fit(curves[0])
    moduli = np.zeros((len(tools), n_curves))
    seconds = np.zeros(len(tools))
    for i, curve in enumerate(curves):  # alternately, so both see the same machine load
        for j, fit in enumerate(tools):
            moduli[j, i], dt = timed(fit, curve)
            seconds[j] += dt
    err = np.abs(moduli[0] / truth - 1)
    print(f"{n_curves} curves x {n_points} points, Sneddon cone 10 deg, nu 0.5")
    rate_afm = n_curves / seconds[0]
    print(f"afm:    {rate_afm:8.1f} curves/s  |E/E_true - 1| median {np.median(err):.2%}")
    if not have_nanite:
        print("nanite: not installed (pip install nanite) - no comparison")
        return
    err_n = np.abs(moduli[1] / truth - 1)
    agree = np.abs(moduli[0] / moduli[1] - 1)
    rate_nan = n_curves / seconds[1]
    print(f"nanite: {rate_nan:8.1f} curves/s  |E/E_true - 1| median {np.median(err_n):.2%}")
    print(f"speed ratio afm / nanite: {rate_afm / rate_nan:.2f}x")
    print(
        f"E afm vs nanite: median {np.median(agree):.3%}, max {agree.max():.3%}, "
        f"within 1 %: {np.mean(agree < 0.01):.1%} of curves"
    )


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
