"""The runs of a ``microchannel_vof`` case: the pressures of its model and its studies.

One :class:`RunSpec` per OpenFOAM run, labelled so that the report can tell them apart:

- ``p<P>hPa``: the case's model at each pressure (``dx_um``, ``time_step_s``, ``correctors``);
- ``..._dx<dx>``: the first pressure (every pressure with ``mesh_check_pressures = "all"``)
  on each finer mesh, with ``mesh_check_correctors``;
- ``..._cap<c>``: a second zero-shear cap; ``..._zp``: the liquid cell with the ZP's curve
  (the bound on the ZP's effect);
- ``..._dt<dt>``: the first pressure at dt/2, dt/4, ... (``dt_refinements``);
- ``beside_...``: the other model (``beside_model``) at ``beside_pressures_hPa`` on
  ``beside_dx_um`` with ``beside_correctors``, and its first pressure at dt/2, ...
  (``beside_dt_refinements``).
"""

from __future__ import annotations

from dataclasses import dataclass

from oocyte_fe.kinds.microchannel_vof_inputs import VofInputs
from oocyte_fe.microchannel.vof.isoadvector import LIQUID_CELL

BESIDE = "beside_"


@dataclass(frozen=True)
class RunSpec:
    """One OpenFOAM run: label, pressure (hPa), cell size (um), viscosity cap (Pa s), time
    step (s), model, the liquid cell's curve ("cytoplasm" or "zp"), pressure correctors."""

    label: str
    pressure_hPa: float
    dx: float
    cap: float
    dt: float
    model: str
    curve: str
    correctors: int


def mesh_label(pressure_hPa: float, dx: float) -> str:
    """The label of the run of ``pressure_hPa`` on the finer mesh ``dx`` (um)."""
    return f"p{pressure_hPa:g}hPa_dx{dx:g}"


def run_specs(inp: VofInputs, pressures_hPa: list[float]) -> list[RunSpec]:
    """The case's runs: first one per pressure (in the given order), then the studies."""
    dt, cap, dx, n = inp.time_step_s, inp.zero_shear_cap_Pa_s, inp.dx_um, inp.correctors
    model, curve = inp.model, inp.cell_curve

    def spec(label: str, p: float, **kw: object) -> RunSpec:
        step = inp.time_step_at(p)
        base = {"dx": dx, "cap": cap, "dt": step, "model": model, "curve": curve, "correctors": n}
        factor = float(kw.pop("dt_factor", 1.0))  # type: ignore[arg-type]
        return RunSpec(label, p, **{**base, **kw, "dt": step * factor})  # type: ignore[arg-type]

    specs = [spec(f"p{p:g}hPa", p) for p in pressures_hPa]
    first = pressures_hPa[0]
    on_meshes = pressures_hPa if inp.mesh_check_pressures == "all" else [first]
    for p in on_meshes:
        for m, n_mesh in inp.mesh_checks:
            specs.append(spec(mesh_label(p, m), p, dx=m, correctors=n_mesh))
    if inp.cap_sensitivity_Pa_s:
        c = inp.cap_sensitivity_Pa_s
        specs.append(spec(f"p{first:g}hPa_cap{c:g}", first, cap=c))
    if inp.zp_bound and model == LIQUID_CELL:
        specs.append(spec(f"p{first:g}hPa_zp", first, curve="zp"))
    for k in range(1, inp.dt_refinements + 1):
        specs.append(spec(f"p{first:g}hPa_dt{dt / 2**k:g}", first, dt_factor=0.5**k))
    if inp.beside_model and inp.beside_pressures_hPa:
        other = {
            "model": inp.beside_model,
            "dx": inp.beside_dx_um or dx,
            "correctors": inp.beside_correctors or n,
            "curve": "cytoplasm",
        }
        for p in inp.beside_pressures_hPa:
            specs.append(spec(f"{BESIDE}p{p:g}hPa", p, **other))
        b = inp.beside_pressures_hPa[0]
        for k in range(1, inp.beside_dt_refinements + 1):
            label = f"{BESIDE}p{b:g}hPa_dt{inp.time_step_at(b) / 2**k:g}"
            specs.append(spec(label, b, dt_factor=0.5**k, **other))
    return specs
