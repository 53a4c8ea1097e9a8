"""Wall time of one 65 um NMSD press at 30 um/s and of a full Table II calibration.

Goals (issue 6): one press < 20 ms, full calibration < 2 s. Baselines in the same process:
the free (full-lattice, unsymmetrised) press against the symmetric half-lattice one;
the same press with twice the steps (ratio shows the cost per step is flat). Accuracy: the
forces at the Table II displacements against a 2600-step reference (backward Euler is first
order and the contact path is step-sensitive, so coarse presses are not converged in dt).
Calibration: the exact (forward-sensitivity) Jacobian against the finite-difference one in
the same process, with the former tolerance 1e-8 ("before") and the new default 1e-3; best
of two runs each (the machine is shared). Run: ``python benchmarks/nmsd_speed.py``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nmsd.calibration import calibrate
from nmsd.parameters import NmsdParameters, node_mass_for
from nmsd.press import press_setup
from nmsd.tableII import read_force_displacement

TABLE = (
    Path(__file__).parents[1] / "cases/nmsd_calibration_tableII/nmsd_force_displacement_tableII.csv"
)


def best_of(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        tic = time.perf_counter()
        fn()
        times.append(time.perf_counter() - tic)
    return min(times)


def main() -> None:
    data = read_force_displacement(TABLE)
    params = NmsdParameters(
        k1=3.0, k2=8000.0, dl_c=0.8, d0=14.6, d1=0.55, node_mass=node_mass_for(115.625, 231)
    )
    d = data.displacement_um
    reference = press_setup(n_steps=2600).run(params, record_um=d).force_at(d)
    for n_steps in (40, 80, 640):
        setup = press_setup(n_steps=n_steps)
        r = setup.run(params, record_um=d)
        t = best_of(lambda s=setup: s.run(params, record_um=d), 5 if n_steps < 200 else 2)
        steps = len(r.advance_um) - 1
        error = np.abs(r.force_at(d) - reference).max() / np.abs(reference).max()
        print(
            f"press 65 um, {steps} steps: {1e3 * t:.1f} ms (goal 20 ms), "
            f"{steps / t:.0f} steps/s, {r.newton_iterations / steps:.1f} Newton its/step, "
            f"force vs 2600-step reference: max {100 * error:.1f} % of the peak"
        )
    # baseline in the same process: the free press (full lattice, buckles sideways)
    setup = press_setup(n_steps=40)
    free = press_setup(n_steps=40, symmetric=False)
    t_sym = best_of(lambda: setup.run(params, record_um=d), 7)
    t_free = best_of(lambda: free.run(params, record_um=d), 7)
    r_free = free.run(params, record_um=d)
    reference_free = press_setup(n_steps=2600, symmetric=False).run(params, record_um=d)
    error = np.abs(r_free.force_at(d) - reference_free.force_at(d)).max()
    print(
        f"free press (full lattice, no symmetry), 52 steps: {1e3 * t_free:.1f} ms; symmetric "
        f"half-lattice press {1e3 * t_sym:.1f} ms = {t_sym / t_free:.2f} x; free press vs its "
        f"2600-step reference: max {100 * error / np.abs(reference_free.force_nN).max():.1f} % "
        "of the peak (sideways buckling, docs/nmsd.md)"
    )
    link = NmsdParameters(
        k1=85.7, k2=5.35e4, dl_c=0.8, d0=139.5, d1=2.74, node_mass=params.node_mass, damping="link"
    )
    r = setup.run(link, record_um=d)
    t = best_of(lambda: setup.run(link, record_um=d))
    steps = len(r.advance_um) - 1
    print(
        f"press 65 um, {steps} steps, link dampers (Table II constants): {1e3 * t:.1f} ms, "
        f"{r.newton_iterations / steps:.1f} Newton its/step"
    )
    t_plain = best_of(lambda: setup.run(params, record_um=d), 7)
    t_sens = best_of(lambda: setup.run(params, record_um=d, sensitivities=True), 7)
    print(
        f"press with forward sensitivities (6 constants): {1e3 * t_sens:.1f} ms, "
        f"{t_sens / t_plain:.2f} x the press without ({1e3 * t_plain:.1f} ms)"
    )
    for damping in ("nodal", "link"):
        base = NmsdParameters(dl_c=0.8, node_mass=node_mass_for(115.625, 231), damping=damping)
        times = {}
        for label, jacobian, tolerance in (
            ("before: finite differences, tol 1e-8", "2-point", 1e-8),
            ("finite differences, tol 1e-3", "2-point", 1e-3),
            ("exact Jacobian, tol 1e-3 (default)", "exact", 1e-3),
        ):
            for _ in range(2):
                tic = time.perf_counter()
                cal = calibrate(
                    setup, data, "nmsd", base, n_starts=2, max_evaluations=60,
                    jacobian=jacobian, tolerance=tolerance,
                )  # fmt: skip
                t = min(times.get(label, np.inf), time.perf_counter() - tic)
                times[label] = t
            print(
                f"calibration ({damping}, 2 starts x 60), {label}: {t:.2f} s (goal 2 s; "
                f"{t / next(iter(times.values())):.2f} x before), {cal.evaluations} presses, "
                f"RMSE {cal.metrics.rmse_nN / 1e3:.3f} uN"
            )


if __name__ == "__main__":
    main()
