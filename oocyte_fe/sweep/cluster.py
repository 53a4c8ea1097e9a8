"""The Dask client a sweep submits its samples to: a local cluster, or an existing scheduler.

Local: ``distributed.LocalCluster`` with one single-threaded worker process per core (the
kinds are numpy/scipy code holding the GIL between calls, so processes, not threads). Remote:
``--scheduler tcp://host:8786`` connects to a running scheduler, e.g. one started by
``dask-jobqueue`` on an HPC system; its workers must import ``oocyte_fe`` and see the case
and result folders at the same paths (a shared file system).
"""

from __future__ import annotations

import asyncio
import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from oocyte_fe.errors import InputError

if TYPE_CHECKING:
    from distributed import Client, LocalCluster

CLOSE_TIMEOUT_S = 60.0
"""A local worker's time to stop once the work is done, before it is killed: generous for a
loaded machine (distributed's own close kills a worker process after 4 s, mid-message, and a
close that still overruns raises and leaves the cluster half-closed)."""


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None) -> Iterator[Client]:
    """A connected client; the local cluster it started (if any) is closed on exit."""
    from distributed import Client

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
    with local_client(n_workers=n, threads_per_worker=1, processes=True) as client:
        yield client


@contextmanager
def local_client(**options: object) -> Iterator[Client]:
    """A client of a new ``LocalCluster(**options)``; both are closed on exit.

    After a normal exit each worker first gets :data:`CLOSE_TIMEOUT_S` to stop; after an
    error, distributed's quick close (a task still running is not waited for).
    """
    from distributed import Client, LocalCluster

    with LocalCluster(
        dashboard_address=":0",  # any free port (8787 is often taken)
        silence_logs=logging.ERROR,
        **options,
    ) as cluster:
        with Client(cluster) as client:
            yield client
        cluster.sync(_stop_workers, cluster)


async def _stop_workers(cluster: LocalCluster) -> None:
    """Close every worker (and its process) of ``cluster``, each within CLOSE_TIMEOUT_S."""
    workers = list(cluster.workers.values())
    await asyncio.gather(*(w.close(timeout=CLOSE_TIMEOUT_S) for w in workers))
