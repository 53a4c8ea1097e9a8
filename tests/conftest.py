"""Test order for pytest-xdist, and the quick case runs that several tests read.

The tests marked ``slow`` (a few minutes each, 46 of about 1300, three quarters of the CPU
time) run first, the rest after them in their usual order. With ``--dist load`` and small
chunks (pyproject's addopts) each worker takes the next test when it is free, so the long
tests are spread over the workers and the short ones fill in behind them, instead of a long
test starting last and leaving the other worker idle.

``quick_run(name)`` runs ``cases/<name>`` on its quick settings once per test run: the xdist
workers share it (the folder above each worker's temporary folder is the run's, and a file
lock lets one worker run it while the others wait), so the tests that read the same quick run
(its checks, its figures, the unperturbed side of a round-off test) do not each pay for it.

Hypothesis draws the same examples in every run (profile ``default``: derandomized, no example
database), so the test command passes or fails the same way on every machine and CI is not red
by a new draw; ``--hypothesis-profile=explore`` draws fresh examples to look for failures.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest
from hypothesis import settings

from tests.figure_checks import LABELS_FILE, recorded_labels

CASES = Path(__file__).resolve().parents[1] / "cases"

settings.register_profile("default", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile("default")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)  # stable: slow first


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory: pytest.TempPathFactory, worker_id: str) -> Callable[[str], Path]:
    """``quick_run(name)`` -> the output folder of ``cases/<name>`` run quick (``result.json``,
    ``metrics.json``, its figures; ``../figure_labels.json`` the label problems of each
    figure saved), run by the first worker to ask and read by the others."""
    from filelock import FileLock

    from oocyte_fe.runner.result import read_result
    from oocyte_fe.runner.run import plan, run_cases

    base = tmp_path_factory.getbasetemp()
    root = base if worker_id == "master" else base.parent

    def run(name: str) -> Path:
        out = root / f"shared_quick_{name}"
        folder = out / name
        with FileLock(f"{out}.lock"):
            if read_result(folder) is None:
                with recorded_labels() as seen:
                    run_cases(plan([CASES / name], quick=True), out, quick=True)
                (out / LABELS_FILE).write_text(json.dumps(seen))
        assert read_result(folder) is not None, f"no result in {folder}"
        return folder

    return run
