"""Which alpha controls does the installed multiphaseInterFoam read? (issue 20)

interFoam's semi-implicit MULES is switched on in ``fvSolution``'s alpha solver dictionary by
``MULESCorr yes; nAlphaCorr N;``. This runs the VOF junction (dx = 12.5 um, 300 hPa, the cases'
1 x 24 setting) for 30 steps of 1e-6 s four times, changing only that dictionary:

* ``plain``: the cases' dictionary (``nAlphaSubCycles 1; cAlpha 1;``);
* ``MULESCorr``: plus ``MULESCorr yes; nAlphaCorr 2;``;
* ``invented``: plus a keyword no solver has (``thisKeywordDoesNotExist 7;``);
* ``cAlpha 0.5``: compression halved (a keyword the solver does read: the positive control);

and compares the written fields with the plain run's, byte for byte. On v1912 (Debian) the
MULESCorr and invented runs write fields identical to the plain one and the logs say nothing:
the keywords are silently ignored (multiphaseMixture::solve reads only nAlphaSubCycles and
cAlpha; its MULES is explicit), while cAlpha 0.5 changes every field. Prints the strings the
solver's library holds, too.

    nice -n 10 python benchmarks/vof_alpha_keywords.py      # ~1 CPU-min
"""

from __future__ import annotations

import filecmp
import subprocess
import tempfile
from pathlib import Path

from oocyte_fe.microchannel.vof.casewriter import Numerics, write_case
from oocyte_fe.microchannel.vof.geometry import JunctionGeometry
from oocyte_fe.microchannel.vof.junction import junction_setup, mean_velocity, seed_phases
from oocyte_fe.microchannel.vof.runner import SOLVER, find_openfoam, run_utility

VARIANTS = {
    "plain": "cAlpha 1;",
    "MULESCorr": "cAlpha 1; MULESCorr yes; nAlphaCorr 2;",
    "invented": "cAlpha 1; thisKeywordDoesNotExist 7;",
    "cAlpha 0.5": "cAlpha 0.5;",
}
FIELDS = ("U", "p_rgh", "alpha.medium", "alpha.zp", "alpha.cytoplasm")
KEYWORDS = ("nAlphaSubCycles", "cAlpha", "MULESCorr", "nAlphaCorr", "nLimiterIter")


def library_keywords() -> dict[str, list[str]]:
    """Which of KEYWORDS occur as strings in the solver and the libraries it links."""
    solver = subprocess.run(["which", SOLVER], capture_output=True, text=True).stdout.strip()
    linked = subprocess.run(["ldd", solver], capture_output=True, text=True).stdout
    files = [solver] + [
        line.split("=>")[1].split()[0]
        for line in linked.splitlines()
        if "=>" in line and "multiphaseInterFoam" in line
    ]
    found = {}
    for f in files:
        words = set(subprocess.run(["strings", f], capture_output=True, text=True).stdout.split())
        found[f] = [k for k in KEYWORDS if k in words]
    return found


def main() -> None:
    foam = find_openfoam()
    u = mean_velocity(300.0)
    num = Numerics(
        time_step=1e-6, end_time=3e-5, write_interval=3e-5, correctors=24, pressure_rel_tol=0.05
    )
    setup = junction_setup(JunctionGeometry(), 12.5, *seed_phases(), u, u, num)
    for f, words in library_keywords().items():
        print(f"{f}: holds {', '.join(words) or 'none'} of {', '.join(KEYWORDS)}")
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, alpha) in enumerate(VARIANTS.items()):
            case = write_case(setup, Path(tmp) / f"run{k}")  # no keyword in the log's Case line
            fv = case / "system" / "fvSolution"
            text = fv.read_text()
            assert text.count("cAlpha 1;") == 1
            fv.write_text(text.replace("cAlpha 1;", alpha))
            run_utility(foam, case, ["blockMesh"], 10)
            log = run_utility(foam, case, [SOLVER], 10).read_text()
            said = [ln for ln in log.splitlines() if "MULESCorr" in ln or "Exist" in ln]
            if name == "plain":
                plain = case
                continue
            same = [
                filecmp.cmp(plain / "3e-05" / f, case / "3e-05" / f, shallow=False) for f in FIELDS
            ]
            verdict = "identical to plain" if all(same) else "DIFFERENT from plain"
            print(
                f"{name:12s} ({alpha}): fields after 30 steps {verdict} "
                f"({sum(same)}/{len(FIELDS)} identical); log lines naming it: {len(said)}"
            )


if __name__ == "__main__":
    main()
