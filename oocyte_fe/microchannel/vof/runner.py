"""Finding OpenFOAM and running a case: blockMesh, the solver (serial, or decomposePar + MPI
with N ranks + reconstructPar), with the log watched by :class:`.monitor.SolverMonitor`.

OpenFOAM is found from, in this order: the ``openfoam`` argument, the environment variable
``OOCYTE_FE_OPENFOAM``, ``WM_PROJECT_DIR``, or ``/usr/share/openfoam`` when the binaries are on
``PATH`` (Debian's package); a source build's ``platforms/*/bin`` is put on ``PATH``. Its
``etc/bashrc`` is not sourced (it aborts under ``set -u``); Debian's binaries only need
``WM_PROJECT_DIR`` (a source build also needs its libraries: source its bashrc first).
``mpirun`` as root needs the two ``OMPI_ALLOW_RUN_AS_ROOT`` variables, set here.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import threading
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

from oocyte_fe.errors import SolverError
from oocyte_fe.microchannel.vof.casewriter import Numerics, control_dict
from oocyte_fe.microchannel.vof.foamfile import write_dictionary
from oocyte_fe.microchannel.vof.monitor import Failure, SolverMonitor

INSTALL_HINT = "apt-get install -y openfoam  (Debian/Ubuntu: OpenFOAM v1912 with Open MPI)"
ENV_VAR = "OOCYTE_FE_OPENFOAM"
SOLVER = "multiphaseInterFoam"
PROJECTION_STEP = 1e-10  # s


_ACTIVE: set[subprocess.Popen] = set()
_ACTIVE_LOCK = threading.Lock()
_STOPPED: set[str] = set()  # keys of tasks whose run was stopped (never reused: uuids)
_TASK = threading.local()  # .key: the task this thread runs (:func:`as_task`)


def terminate_active() -> None:
    """Stop every solver this process started and that still runs (on a timeout or an
    interrupt of a case that runs several pressures at once)."""
    with _ACTIVE_LOCK:
        for proc in list(_ACTIVE):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)


@contextmanager
def as_task(key: str) -> Iterator[None]:
    """Run the block as task ``key``: once :func:`stop_tasks` names it, no OpenFOAM program
    starts in this thread (a task in a worker thread cannot be interrupted, e.g. in an FE
    cell between two flows; it ends at its next start with :class:`SolverError`)."""
    _TASK.key = key
    try:
        yield
    finally:
        _TASK.key = None


def stop_tasks(keys: Iterable[str]) -> None:
    """Refuse every later start of an OpenFOAM program in the tasks ``keys``."""
    with _ACTIVE_LOCK:
        _STOPPED.update(keys)


def _stopped() -> bool:
    """Whether the task this thread runs was stopped (call with ``_ACTIVE_LOCK`` held)."""
    return getattr(_TASK, "key", None) in _STOPPED


def _refuse_if_stopped(what: str) -> None:
    with _ACTIVE_LOCK:
        if _stopped():
            raise SolverError(f"{what} not started: the case's run was stopped")


class OpenFoamMissing(RuntimeError):
    """OpenFOAM is not installed or not found; the message holds the install line."""


class VofFailure(SolverError):
    """The solver stopped, or was stopped, with a named failure (:class:`.monitor.Failure`)."""

    def __init__(self, failure: Failure, log: Path) -> None:
        super().__init__(f"VOF run stopped: {failure.message} (log: {log})")
        self.failure = failure


@dataclass(frozen=True)
class OpenFoam:
    """An OpenFOAM installation: ``project_dir`` (WM_PROJECT_DIR) and where the binaries are."""

    project_dir: Path
    bin_dir: Path | None = None

    def env(self, case: Path | None = None) -> dict[str, str]:
        env = dict(os.environ)
        if case is not None:
            env["PWD"] = str(Path(case).resolve())
        env["WM_PROJECT_DIR"] = str(self.project_dir)
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
        env.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")  # shared cores: do not spin
        if self.bin_dir is not None:
            env["PATH"] = f"{self.bin_dir}{os.pathsep}{env.get('PATH', '')}"
        return env

    def executable(self, name: str) -> str:
        found = shutil.which(name, path=self.env()["PATH"])
        if found is None:
            raise OpenFoamMissing(f"OpenFOAM program {name!r} not found; install: {INSTALL_HINT}")
        return found


def find_openfoam(openfoam: str | Path | None = None) -> OpenFoam:
    """The OpenFOAM installation (module docstring), or :class:`OpenFoamMissing`."""
    for candidate in (openfoam, os.environ.get(ENV_VAR), os.environ.get("WM_PROJECT_DIR")):
        if candidate:
            root = Path(candidate)
            bins = [*sorted(root.glob("platforms/*/bin")), root / "bin"]
            with_solver = [d for d in bins if (d / SOLVER).exists()]
            found = OpenFoam(root, with_solver[0] if with_solver else None)
            if shutil.which(SOLVER, path=found.env()["PATH"]):
                return found
    if shutil.which(SOLVER) and Path("/usr/share/openfoam/etc").is_dir():
        return OpenFoam(Path("/usr/share/openfoam"))
    raise OpenFoamMissing(f"OpenFOAM ({SOLVER}) not found; install it with: {INSTALL_HINT}")


def openfoam_available() -> bool:
    try:
        find_openfoam()
    except OpenFoamMissing:
        return False
    return True


def _command(foam: OpenFoam, args: list[str], nice: int) -> list[str]:
    cmd = [foam.executable(args[0]), *args[1:]]
    return ["nice", "-n", str(nice), *cmd] if nice else cmd


def run_utility(foam: OpenFoam, case: Path, args: list[str], nice: int = 0) -> Path:
    """Run an OpenFOAM utility in ``case``; its output goes to ``log.<name>``. A non-zero exit
    raises :class:`SolverError` with the log's last lines."""
    _refuse_if_stopped(args[0])
    log = case / f"log.{args[0]}"
    with log.open("w") as fh:
        code = subprocess.call(
            _command(foam, args, nice),
            cwd=case,
            env=foam.env(case),
            stdout=fh,
            stderr=subprocess.STDOUT,
        )
    if code != 0:
        tail = "\n".join(log.read_text().splitlines()[-15:])
        raise SolverError(f"{' '.join(args)} failed (exit {code}) in {case}:\n{tail}")
    return log


def project_initial_flow(foam: OpenFoam, case: Path, numerics: Numerics, nice: int = 0) -> None:
    """Make the initial flux divergence-free: one solver step of ``PROJECTION_STEP`` s, whose
    pressure correction projects the written initial velocity; its U and phi replace
    those at t = 0. The phases move by ``U dt`` ~ 1e-4 um, and their sum stays 1 (a
    non-solenoidal initial flux would change it by ``dt div(phi)`` in the first real step)."""
    dt = PROJECTION_STEP
    short = replace(numerics, time_step=dt, end_time=dt, write_interval=dt, adjustable=False)
    write_dictionary(case / "system" / "controlDict", control_dict(short))
    monitor = SolverMonitor(dt, dt, 1.0, 1e9)
    run_solver(foam, case, monitor, nice=nice, solver=numerics.solver)
    written = [
        d for d in case.iterdir() if d.is_dir() and d.name not in ("0", "constant", "system")
    ]
    step = next(d for d in written if (d / "phi").exists())
    for name in ("U", "phi"):
        shutil.copy(step / name, case / "0" / name)
    shutil.rmtree(step)
    shutil.rmtree(case / "postProcessing", ignore_errors=True)  # the real run starts its own
    write_dictionary(case / "system" / "controlDict", control_dict(numerics))


def run_solver(
    foam: OpenFoam,
    case: Path,
    monitor: SolverMonitor,
    ranks: int = 1,
    nice: int = 0,
    progress: Callable[[str], None] | None = None,
    every: int = 50,
    solver: str = SOLVER,
) -> SolverMonitor:
    """Run ``solver`` (``multiphaseInterFoam`` or ``interIsoFoam``) in ``case`` (``ranks`` > 1:
    decomposed, under mpirun) and watch its log; stop it at the first failure
    (:class:`VofFailure`). ``progress`` gets the monitor's line every ``every`` steps."""
    if ranks > 1:
        run_utility(foam, case, ["decomposePar", "-force"], nice)
        mpirun = shutil.which("mpirun", path=foam.env()["PATH"])
        if mpirun is None:
            raise OpenFoamMissing(f"mpirun not found; install it with: {INSTALL_HINT}")
        args = [mpirun, "-np", str(ranks), foam.executable(solver), "-parallel"]
        cmd = ["nice", "-n", str(nice), *args] if nice else args
    else:
        cmd = _command(foam, [solver], nice)
    _refuse_if_stopped(solver)
    log = case / f"log.{solver}"
    with log.open("w") as fh:
        proc = subprocess.Popen(
            cmd,
            cwd=case,
            env=foam.env(case),
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        assert proc.stdout is not None
        with _ACTIVE_LOCK:
            _ACTIVE.add(proc)
            if _stopped():  # stopped between the check above and this start
                os.killpg(proc.pid, signal.SIGTERM)
        try:
            last = 0
            for line in proc.stdout:
                fh.write(line)
                failure = monitor.feed(line)
                if failure is not None:
                    break
                if progress is not None and monitor.steps >= last + every:
                    last = monitor.steps
                    progress(monitor.progress())
        finally:
            if proc.poll() is None:  # a failure found, or an exception in this thread
                os.killpg(proc.pid, signal.SIGTERM)
            code = proc.wait()
            with _ACTIVE_LOCK:
                _ACTIVE.discard(proc)
    if monitor.failure is not None:
        raise VofFailure(monitor.failure, log)
    if code != 0:
        tail = "\n".join(log.read_text().splitlines()[-15:])
        raise SolverError(f"{solver} failed (exit {code}) in {case}:\n{tail}")
    if ranks > 1:
        run_utility(foam, case, ["reconstructPar"], nice)
    return monitor
