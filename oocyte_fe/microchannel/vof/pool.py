"""Running several VOF cases at once on the project's Dask machinery (:mod:`oocyte_fe.sweep`).

Each task is one OpenFOAM run (``ranks`` MPI ranks of its own); ``concurrent`` of them run at
the same time, so a machine needs ``concurrent x ranks`` cores.

* **In this process** (no scheduler, a single run): the run without Dask (a local cluster
  costs about 1.5 CPU s to start, nothing to gain for one run).
* **Local** (no scheduler, several runs): a ``distributed.LocalCluster`` of
  ``concurrent`` single-thread workers inside this process. A task only waits on its OpenFOAM
  subprocesses, so threads cost nothing; each task gets its ``progress`` callback (Dask
  pickles a task's arguments even in process, so the callbacks stay in this process and the
  task looks its own up by key); a stop (a failed run, the case's ``timeout_s``) reaches
  every solver this process started (:func:`.runner.terminate_active`), and a task still
  running in a thread (an FE cell between two flows) starts no further OpenFOAM program
  (:func:`.runner.stop_tasks`).
* **Remote** (``scheduler = "tcp://host:8786"``): the tasks go to a running Dask scheduler, e.g.
  one started by dask-jobqueue on a cluster (docs/microchannel.md, "On a cluster"); its
  workers must import ``oocyte_fe``, find OpenFOAM and see the case's output folder at the same
  path (a shared file system). One worker thread per job of ``ranks`` cores.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING, TypeVar

from oocyte_fe.microchannel.vof.runner import as_task, stop_tasks, terminate_active
from oocyte_fe.sweep.cluster import dask_client, local_client

if TYPE_CHECKING:
    from distributed import Client

T = TypeVar("T")

_PROGRESS: dict[str, Callable[[str], None]] = {}  # in-process callbacks by task key


@contextmanager
def vof_client(concurrent: int, scheduler: str | None = None) -> Iterator[Client]:
    """A Dask client: ``scheduler``'s, or an in-process cluster of ``concurrent`` threads."""
    if scheduler:
        with dask_client(scheduler) as client:
            yield client
        return
    with local_client(n_workers=concurrent, threads_per_worker=1, processes=False) as client:
        yield client


def _with_progress(task: Callable[..., T], key: str, *job: object) -> T:
    """Run ``task(*job, progress=...)`` as task ``key`` (:func:`.runner.as_task`) with the
    callback registered under ``key`` here (none on a remote worker)."""
    with as_task(key):
        return task(*job, progress=_PROGRESS.get(key))


def _in_this_process(
    task: Callable[..., T], job: tuple, progress: Callable[[str], None] | None
) -> list[T]:
    """The one job here; a stop (its failure, a timeout) terminates its solvers."""
    try:
        return [task(*job, progress=progress)]
    except BaseException:
        terminate_active()
        raise


def run_concurrently(
    task: Callable[..., T],
    jobs: Sequence[tuple],
    concurrent: int = 1,
    scheduler: str | None = None,
    progress: Sequence[Callable[[str], None] | None] | None = None,
) -> list[T]:
    """``[task(*job, progress=p) for job, p in zip(jobs, progress)]``, ``concurrent`` at a time
    on Dask, in the jobs' order; ``progress`` (optional, one callback per job) reaches the
    tasks of a local cluster only.

    The first task that raises stops the others (cancelled; local solvers terminated, and a
    local task still running starts no further OpenFOAM program) and its
    exception is raised here.
    """
    if not scheduler and len(jobs) == 1:
        return _in_this_process(task, jobs[0], progress[0] if progress else None)
    keys = [uuid.uuid4().hex for _ in jobs]
    if progress is not None and not scheduler:
        _PROGRESS.update({k: p for k, p in zip(keys, progress, strict=True) if p is not None})
    try:
        with vof_client(concurrent, scheduler) as client:
            futures = [
                client.submit(_with_progress, task, k, *job, pure=False)
                for k, job in zip(keys, jobs, strict=True)
            ]
            try:
                return client.gather(futures)
            except BaseException:
                client.cancel(futures)
                stop_tasks(keys)  # a task still running here starts no further solver
                terminate_active()
                raise
    finally:
        for k in keys:
            _PROGRESS.pop(k, None)
