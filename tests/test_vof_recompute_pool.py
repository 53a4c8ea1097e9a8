"""The deform-recompute passes of ``microchannel_vof`` at several pressures on Dask (issue 30
item 4): :func:`oocyte_fe.kinds.microchannel_vof.recompute_at` through
:func:`~oocyte_fe.microchannel.vof.pool.run_concurrently` on a local cluster of two threads
gives the numbers of the same calls made one after another, and a pressure whose passes fail
gives its "not computed: ..." while the others keep theirs.

No OpenFOAM: the flows are synthetic fields (a cell at rest in the pressure
``-s (x^2 - y^2) / R^2``, ``s`` growing with the inlet velocity, so each pressure loads the FE
cell differently), written where the passes' flows would run; the FE cells are the real ones
(the case's defaults), two threads at once on an empty mesh cache (one mesh key).
"""

from __future__ import annotations

import threading
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import oocyte_fe.kinds.microchannel_vof as vof_kind
from oocyte_fe.microchannel.elastic_iteration import DeformRecompute
from oocyte_fe.microchannel.vof.junction import VELOCITY_300_HPA, JunctionRun
from oocyte_fe.microchannel.vof.pool import run_concurrently
from oocyte_fe.microchannel.vof.post import CellHistory
from oocyte_fe.microchannel.vof.runner import OpenFoam
from oocyte_fe.runner.casefile import load_case
from tests.conftest import CASES
from tests.test_elastic_junction import _synthetic_run

S_300_KPA = 0.05  # the synthetic flow's pressure mode at 300 hPa's inlet velocity


def _run(case: Path, ratio: float) -> JunctionRun:
    """A :class:`JunctionRun` of the synthetic fields in ``case`` (plain data: it is pickled)."""
    history = CellHistory(np.zeros(1), np.zeros((1, 2)), np.zeros(1), np.ones(1), {})
    return JunctionRun(case, 1.0, 1.0, 1, 1, 0.0, history, ratio, 0.0, ratio)


def _mode(velocity: float) -> float:
    return S_300_KPA * velocity / VELOCITY_300_HPA


def _numbers(result: DeformRecompute) -> list[float]:
    """Every number of the passes: each flow's and FE cell's b/a, shapes, residual."""
    out = []
    for p in result.passes:
        out += [p.flow_b_over_a, p.b_over_a, p.start_b_over_a, p.shape_b_over_a]
        out += [c.b_over_a for c in p.elastic.cells] + list(p.elastic.traction_x_um)
    return out


def test_the_passes_at_two_pressures_on_dask_are_the_passes_one_after_another(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("OOCYTE_FE_CACHE", str(tmp_path / "mesh_cache"))  # both threads ask it
    inp = load_case(CASES / "microchannel_vof_quick").inputs
    inp = inp.model_copy(update={"recompute_passes": 2, "recompute_pressures": "all"})
    centre = np.array(inp.geometry.to_geometry().cell_centre)

    def flow(foam, directory: Path, setup, ranks=1, nice=0) -> JunctionRun:  # run_junction's
        outline = setup.disks[0].points - centre  # the FE's shape the pass starts from
        s = _mode(next(iter(setup.layout.inlets.values())).velocity)
        _synthetic_run(directory, setup.layout, s, 0.0, outline)
        a, b = np.ptp(outline, axis=0)
        return _run(directory, min(a, b) / max(a, b))

    monkeypatch.setattr(vof_kind, "find_openfoam", lambda _path=None: OpenFoam(tmp_path))
    monkeypatch.setattr(vof_kind, "run_junction", flow)
    monkeypatch.setattr(vof_kind, "step_pair", lambda _foam, _nice=0: None)  # the writes' own
    specs = vof_kind.run_specs(inp, [300.0, 600.0, 450.0])
    layout = inp.geometry.to_geometry().layout(inp.dx_um, 1.0, 1.0)
    channel = inp.channel.to_internal()
    firsts = []
    for spec in specs[:2]:  # pass 0: the runs of the case, 300 and 600 hPa
        u = float(channel.mean_velocity(spec.pressure_hPa * vof_kind.HPA))
        case = _synthetic_run(tmp_path / "runs" / spec.label, layout, _mode(u), 0.0)
        firsts.append(_run(case, 0.99))
    (tmp_path / "runs" / "none").mkdir()
    firsts.append(_run(tmp_path / "runs" / "none", 0.99))  # 450 hPa: the run wrote nothing

    def jobs(root: Path) -> list[tuple]:
        return [
            (inp, spec, first, None, root / f"p{spec.pressure_hPa:g}hPa")
            for spec, first in zip(specs, firsts, strict=True)
        ]

    said: list[str] = []
    guard = threading.Lock()  # the callbacks stay in this process (not picklable)

    def say(msg: str) -> None:
        with guard:
            said.append(msg)

    on_dask = run_concurrently(vof_kind.recompute_at, jobs(tmp_path / "dask"), 2, None, [say] * 3)
    assert sorted(said) == [
        f"deform-recompute {p} hPa: pass1, the flow past the FE's shape" for p in (300, 600)
    ]
    cache = tmp_path / "mesh_cache"  # one FE mesh, written whole (temporary name, renamed)
    assert len(list(cache.glob("*.msh"))) == 1 and not list(cache.glob(".tmp-*"))
    said.clear()
    in_turn = [vof_kind.recompute_at(*job, progress=say) for job in jobs(tmp_path / "seq")]
    for p, (a, b) in zip((300, 600), zip(on_dask[:2], in_turn[:2], strict=True), strict=True):
        assert isinstance(a, DeformRecompute) and isinstance(b, DeformRecompute)
        assert len(a.passes) == 2 and a.stopped == b.stopped == "converged after 2 passes"
        assert _numbers(a) == pytest.approx(_numbers(b), rel=1e-12, abs=0.0)
        assert a.residual == pytest.approx(b.residual, rel=1e-12, abs=1e-15)
        assert (tmp_path / "dask" / f"p{p}hPa" / "pass1" / "flow").is_dir()
    deformation = [1 - r.ratios[-1] for r in in_turn[:2]]  # type: ignore[union-attr]
    assert 0 < deformation[0] < deformation[1]  # each pressure its own load
    assert on_dask[2] == in_turn[2] and on_dask[2].startswith("not computed: ")  # type: ignore[union-attr]
    assert "time folders" in on_dask[2]
    assert said == [
        f"deform-recompute {p} hPa: pass1, the flow past the FE's shape" for p in (300, 600)
    ]


def test_the_case_sends_every_pressures_passes_and_one_pressures_stay_here(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``recompute_pressures = "all"``: one job per pressure, with the reading of
    ``recompute_load`` of its one-way cell and its folder ``recompute/p<P>hPa``, ``concurrent``
    at a time on the case's scheduler; the first pressure alone: no scheduler (in this
    process, as before)."""
    seen: list[tuple] = []

    def submit(task, jobs, concurrent, scheduler, progress=None):  # run_concurrently's place
        seen.append((task, jobs, concurrent, scheduler, progress))
        return [f"result {k}" for k in range(len(jobs))]

    monkeypatch.setattr(vof_kind, "run_concurrently", submit)
    base = load_case(CASES / "microchannel_vof_quick").inputs
    ctx = SimpleNamespace(scheduler=None, output=lambda rel: tmp_path / rel, step=lambda _msg: None)
    specs = vof_kind.run_specs(base, [300.0, 600.0])
    runs = [_run(tmp_path, 0.99), _run(tmp_path, 0.98)]
    cells = [SimpleNamespace(follower=f"follower {p}") for p in (300, 600)]
    every = {"recompute_passes": 3, "recompute_pressures": "all", "concurrent": 2}
    expected = [(300.0, "result 0"), (600.0, "result 1")]
    for update, n in (
        ({**every, "scheduler": "tcp://host:1", "recompute_load": "follower"}, 2),
        ({**every, "recompute_load": "dead"}, 2),
        ({"recompute_passes": 3, "scheduler": "tcp://host:1"}, 1),  # the first pressure
    ):
        inp = base.model_copy(update=update)
        out = vof_kind._recompute_all(ctx, inp, specs, runs, cells)  # type: ignore[arg-type]
        assert out == expected[:n]
    (t1, jobs1, n1, where1, say1), (_, jobs2, _, where2, _), (_, jobs3, _, where3, _) = seen
    assert t1 is vof_kind.recompute_at and n1 == 2 and len(say1) == 2
    assert where1 == "tcp://host:1" and where2 is None and where3 is None
    assert [j[3] for j in jobs1] == ["follower 300", "follower 600"]
    assert [j[3] for j in jobs2] == cells
    assert [j[4] for j in jobs1] == [tmp_path / "recompute/p300hPa", tmp_path / "recompute/p600hPa"]
    assert [(j[1], j[2]) for j in jobs3] == [(specs[0], runs[0])]
