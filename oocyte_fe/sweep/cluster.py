"""The Dask client a sweep submits its samples to: a local cluster, or an existing scheduler.

Local: ``distributed.LocalCluster`` with one single-threaded worker process per core (the
kinds are numpy/scipy code holding the GIL between calls, so processes, not threads). Remote:
``--scheduler tcp://host:8786`` connects to a running scheduler, e.g. one started by
``dask-jobqueue`` on an HPC system; its workers must import ``oocyte_fe`` and see the case
and result folders at the same paths (a shared file system).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from oocyte_fe.errors import InputError

if TYPE_CHECKING:
    from distributed import Client


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None) -> Iterator[Client]:
    """A connected client; the local cluster it started (if any) is closed on exit."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(
                "--scheduler",
                "",
                "a reachable Dask scheduler address (tcp://host:8786)",
                got=f"{scheduler} ({type(exc).__name__})",
            ) from None
        with client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    with (
        LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",  # any free port (8787 is often taken)
            silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client
