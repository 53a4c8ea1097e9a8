"""Time of one viscoelastic ramp fit (issue 28, "Speed": under 50 ms for a 2 000-point ramp).

A synthetic approach of 2 000 points (500 before contact, 1 500 in contact, 1 um at 1 um/s)
made with Ting's force for a two-term Prony series (E_inf 0.4, E_i 0.3 and 0.3 kPa, tau 0.05
and 0.5 s), 1 % noise of the peak force, fitted with each relaxation model and tip (approach
only, the ramp). Then the same material as a 1 000-point approach plus a 1 000-point retract
(the approach-and-retract stage, which has no speed goal). Printed: the median wall and CPU
time of 5 fits, and the load average (the machine is shared). Run:
``OMP_NUM_THREADS=1 PYTHONPATH=. python benchmarks/afm_ramp_fit.py``.
"""

from __future__ import annotations

import os
import time

import numpy as np

from afm import RampCurve, fit_ramp
from afm.models import get_model
from afm.viscoelastic import get_relaxation_model, ting_force

GOAL_S = 0.05
TIPS = {
    "sneddon_cone": {"half_angle_deg": 20.0},
    "hertz_paraboloid": {"radius_um": 5.0},
    "hertz_sphere": {"radius_um": 5.0},
}
AMPLITUDES, TAUS = np.array([0.4, 0.3, 0.3]), np.array([0.05, 0.5])


def synthetic(model: str, n_approach: int, retract: bool, seed: int = 0) -> RampCurve:
    pre = n_approach // 4
    h = 1.0 / (n_approach - pre)
    n = n_approach + (n_approach if retract else 0)
    t = h * np.arange(n)
    x = t - pre * h
    if retract:
        turn = x[n_approach - 1]
        x[n_approach:] = turn - (t[n_approach:] - t[n_approach - 1])
    delta = np.clip(x, 0.0, None)
    rel = get_relaxation_model("prony")
    phi = rel.integrals(h * np.arange(n + 1), TAUS) @ AMPLITUDES
    force = ting_force(get_model(model).shape(delta, TIPS[model], 0.5), delta, phi, h)
    noise = 0.01 * force.max() * np.random.default_rng(seed).standard_normal(n)
    return RampCurve(t, x, force + noise, f"synthetic {model}")


def timed(ramp: RampCurve, model: str, relaxation: str, repeat: int = 5):
    fit_ramp(ramp, model, TIPS[model], relaxation=relaxation)  # warm up
    walls, cpus = [], []
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        fit = fit_ramp(ramp, model, TIPS[model], relaxation=relaxation)
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return float(np.median(walls)), float(np.median(cpus)), fit


def main() -> None:
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; goal {GOAL_S:g} s")
    print(f"{'ramp':28s} {'tip':18s} {'relaxation':22s} {'wall ms':>8s} {'cpu ms':>7s} "
          f"{'cpu/goal':>8s}  E0 kPa")  # fmt: skip
    for model in TIPS:
        ramp = synthetic(model, 2000, retract=False)
        for relaxation in ("power_law", "standard_linear_solid", "prony"):
            wall, cpu, fit = timed(ramp, model, relaxation)
            print(
                f"{'2000-point approach':28s} {model:18s} {relaxation:22s} {1e3 * wall:8.1f} "
                f"{1e3 * cpu:7.1f} {cpu / GOAL_S:8.2f}  {fit.E0_kPa:.3f}"
            )
    ramp = synthetic("hertz_paraboloid", 1000, retract=True)
    wall, cpu, fit = timed(ramp, "hertz_paraboloid", "prony", repeat=1)
    print(
        f"{'1000 approach + 1000 retract':28s} {'hertz_paraboloid':18s} {'prony':22s} "
        f"{1e3 * wall:8.1f} {1e3 * cpu:7.1f} {'-':>8s}  {fit.E0_kPa:.3f}"
    )


if __name__ == "__main__":
    main()
