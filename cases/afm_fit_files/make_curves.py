"""Write the small curve files of the ``afm_fit_files`` case (run once; the files are shipped).

Usage, from the repository root: ``PYTHONPATH=. python3 cases/afm_fit_files/make_curves.py``

SYNTHETIC curves, not measurements: Sneddon cone (half angle 10 deg, nu 0.5), spring constant
0.07 N/m, 400 points over 6 um of piezo travel, contact at 3 um, baseline offset 0.2 nN and tilt
0.05 nN/um, Gaussian force noise 1 % of the maximum force. Six ZP curves (E drawn from
N(7.01, 2.88) kPa, seed 001's ZP mean and SD) under ``curves/zp/`` and six cytoplasm curves
(N(1.55, 0.56) kPa) under ``curves/cytoplasm/``, draws below 0.5 kPa redrawn; plus one curve
that never reaches contact (``curves/zp/zp_bad_no_contact.csv``), which the case must report
and skip. The moduli used are written to ``known_moduli.csv`` (file, E_kPa) for the case's
check. Also a force-clamp creep record for the ZP group (``creep/zp_creep.csv``: 5 nN for 6 s
at 200 Hz, E0 7.01 kPa, g = (0.3, 0.2), tau = (0.2, 1.5) s, 0.2 % indentation noise).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from afm.curve import ForceCurve
from afm.curve_io import write_creep, write_curve
from afm.prony_series import RelaxationProny
from afm.synthetic import creep_indentation, indentation_curve

HERE = Path(__file__).parent
K_N_PER_M = 0.07


def _draw(rng: np.random.Generator, mean: float, sd: float, n: int) -> np.ndarray:
    values = rng.normal(mean, sd, n)
    for _ in range(100):
        low = values < 0.5
        if not low.any():
            break
        values[low] = rng.normal(mean, sd, int(low.sum()))
    return values


def main() -> None:
    rng = np.random.default_rng(2026)
    known = []
    for group, mean, sd in (("zp", 7.01, 2.88), ("cytoplasm", 1.55, 0.56)):
        folder = HERE / "curves" / group
        folder.mkdir(parents=True, exist_ok=True)
        for i, e in enumerate(_draw(rng, mean, sd, 6), start=1):
            curve = indentation_curve(
                float(e),
                3.0,
                max_piezo_um=6.0,
                n_points=400,
                k_nN_per_um=1e3 * K_N_PER_M,
                offset_nN=0.2,
                tilt_nN_per_um=0.05,
                noise_fraction=0.01,
                seed=int(rng.integers(2**31)),
                group=group,
            )
            name = f"{group}_{i:02d}.csv"
            write_curve(curve, folder / name)
            known.append((f"curves/{group}/{name}", float(e)))
    flat = np.random.default_rng(1).normal(0.0, 0.01, 400)
    bad = ForceCurve(np.linspace(0, 6, 400), flat, 1e3 * K_N_PER_M, group="zp")
    write_curve(bad, HERE / "curves" / "zp" / "zp_bad_no_contact.csv")
    with (HERE / "known_moduli.csv").open("w") as fh:
        fh.write("# SYNTHETIC: moduli used by make_curves.py\nfile,E_kPa\n")
        fh.writelines(f"{f},{e!r}\n" for f, e in known)

    truth = RelaxationProny(7.01 / 3.0, (0.3, 0.2), (0.2, 1.5))
    t = np.arange(0.0, 6.0 + 1e-9, 1.0 / 200.0)
    delta = creep_indentation(truth, t, 5.0) * (1 + 0.002 * rng.standard_normal(t.size))
    force = 5.0 + 0.02 * rng.standard_normal(t.size)
    contact = 8.0 - delta[-1] - 5.0 / (1e3 * K_N_PER_M)
    (HERE / "creep").mkdir(exist_ok=True)
    write_creep(
        HERE / "creep" / "zp_creep.csv",
        t,
        force,
        contact + delta + force / (1e3 * K_N_PER_M),
        contact,
        K_N_PER_M,
        note="SYNTHETIC creep record (cases/afm_fit_files/make_curves.py), not measured data",
    )


if __name__ == "__main__":
    main()
