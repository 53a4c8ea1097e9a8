"""FE core scaling: assembly time, solve time and peak memory per Newton iteration vs dofs.

Layered oocyte (axisymmetric, P2/P1, ZP with a 2-term Prony series) under a follower pressure
on the part of its surface with Z > 60 um; one Newton iteration (assemble + LU solve) at
each of several mesh sizes (peak memory: of the assembly). The solve is the solver's own
(:class:`oocyte_fe.fe.linear.SparseLU`: nested-dissection order, threshold pivoting) and, as
the baseline on the same matrix, SuperLU with its default COLAMD ordering and partial pivoting
(what the solver used before); the table gives both, their ratio and the one-time cost of
ordering a new pattern. Prints the observed growth exponents ``time ~ dofs^k`` (least squares
over the sizes), and each size's time relative to the smallest one.

    python benchmarks/fe_scaling.py            # 5 sizes, up to ~500k dofs
    python benchmarks/fe_scaling.py --quick    # 3 small sizes
"""

from __future__ import annotations

import argparse
import logging
import time
import tracemalloc

import numpy as np
from scipy.sparse.linalg import splu
from skfem import condense

from oocyte_fe.fe.body import Body
from oocyte_fe.fe.linear import SparseLU
from oocyte_fe.fe.loads import FollowerPressure, PinnedPoint, Prescribed
from oocyte_fe.fe.material import Material, Prony
from oocyte_fe.fe.solver import Problem
from oocyte_fe.mesh import LayeredOocyte, layered_oocyte_mesh


def one_iteration(size_um: float) -> dict[str, float]:
    mesh = layered_oocyte_mesh(LayeredOocyte(size_um=size_um))
    materials = {
        "zona": Material(7.0, 0.5, Prony((0.3, 0.2), (0.2, 1.5))),
        "cytoplasm": Material(1.55, 0.5),
    }
    body = Body(mesh, materials, "axisymmetric")
    prob = Problem(
        body,
        [Prescribed("axis", 0), PinnedPoint((0.0, 0.0), 1)],
        [FollowerPressure("outer_surface", lambda t: 0.05 * t, where=lambda x: x[1] > 60.0)],
    )
    tracemalloc.start()
    t0 = time.perf_counter()
    r, K, _ = prob.assemble(prob.x, 0.1, 0.1)
    t1 = time.perf_counter()
    A, b, _, free = condense(K, -r, D=prob.fixed_dofs)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    lu = SparseLU()
    t_order = time.perf_counter()
    lu.factorize(A)  # the first factorization of a pattern also orders it (once per pattern)
    t1b = time.perf_counter()
    dx = lu.factorize(A).solve(b)  # what every later Newton iteration costs
    t2 = time.perf_counter()
    dx_colamd = splu(A.tocsc()).solve(b)
    t3 = time.perf_counter()
    t_order = t1b - t_order - (t2 - t1b)
    t1 = t1b
    assert np.all(np.isfinite(dx))
    assert np.allclose(dx, dx_colamd, rtol=1e-6, atol=1e-9 * np.abs(dx_colamd).max())
    return {
        "size_um": size_um,
        "elements": mesh.nelements,
        "dofs": body.n_dofs,
        "assemble_s": t1 - t0,
        "solve_s": t2 - t1,
        "colamd_s": t3 - t2,
        "order_s": t_order,
        "peak_MB": peak / 2**20,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="three small sizes only")
    args = parser.parse_args()
    logging.getLogger("skfem").setLevel(logging.WARNING)
    sizes = [8.0, 4.0, 2.0] if args.quick else [8.0, 4.0, 2.0, 1.0, 0.55]
    rows = [one_iteration(s) for s in sizes]
    base = rows[0]
    print(
        f"{'size um':>8} {'elements':>9} {'dofs':>8} {'assemble s':>11} {'solve s':>9} "
        f"{'COLAMD s':>9} {'speed-up':>8} {'order s':>8} {'peak MB':>8} {'x base (asm)':>12} "
        f"{'x base (solve)':>14}"
    )
    for row in rows:
        print(
            f"{row['size_um']:8.2f} {row['elements']:9d} {row['dofs']:8d} "
            f"{row['assemble_s']:11.3f} {row['solve_s']:9.3f} {row['colamd_s']:9.3f} "
            f"{row['colamd_s'] / row['solve_s']:8.2f} {row['order_s']:8.3f} {row['peak_MB']:8.1f} "
            f"{row['assemble_s'] / base['assemble_s']:12.1f} "
            f"{row['solve_s'] / base['solve_s']:14.1f}"
        )
    dofs = np.log([r["dofs"] for r in rows])
    for key in ("assemble_s", "solve_s", "colamd_s", "peak_MB"):
        k = np.polyfit(dofs, np.log([r[key] for r in rows]), 1)[0]
        print(f"observed growth {key}: dofs^{k:.2f}")


if __name__ == "__main__":
    main()
