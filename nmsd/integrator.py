"""Backward-Euler time step of eq 1 with (chord) Newton iterations on a banded tangent.

Eq 1 of seed 000, per node i (um, nN, s):

    M_i a_i + F_i^d + F_i^k = F_i^ext

with the link forces ``F^k`` of eqs 2-5 (:mod:`nmsd.spring`), the damping ``F^d`` of eq 6
(:mod:`nmsd.damping`, nodal or per link) and the pipette contact ``F^ext``
(:mod:`nmsd.pipette`). Backward Euler takes ``v+ = (x+ - x)/dt``, ``a+ = (v+ - v)/dt`` and
solves the residual

    R(x+) = M (x+ - x - dt v)/dt^2 + F^d(x+, v+) + F^k(x+) - F^ext(x+) = 0

by Newton iterations with the exact tangent (nodal reading:
``M/dt^2 + D/dt + d1 v+ (x) u_hat + K_links + K_contact``; link reading: the Voigt tangent
of :mod:`nmsd.assembly`). Backward Euler is A-stable (L-stable): for the linearised system
every mode decays for any dt > 0, so the step is set by accuracy and contact resolution, not
by the explicit limit ``dt < 2 / omega_max`` (``omega_max^2`` the largest eigenvalue of
``M^-1 K``, see :func:`explicit_time_step_limit`).

Cost: residual and tangent are filled by one compiled pass (:func:`nmsd.assembly.assemble`)
straight into LAPACK band storage (links join nodes in neighbouring grid rows only). The band
LU (``dgbtrf``) is computed at the predictor of each step and refreshed while the update is
large (``|dx| > chord_um``) or contracts slowly (``|dx_k| > refresh_rate |dx_k-1|``); near the
solution the factor is kept (chord Newton) and an iteration costs one residual and one pair
of triangular solves (``dgbtrs``). Convergence: ``|dx| < xtol`` as with full Newton. Reusing
the factor across steps was tried and is slower: a stale tangent at the predictor sends the
iterate into other contact states (more iterations and halvings).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh
from scipy.linalg.lapack import dgbtrf, dgbtrs

from nmsd.area import area_kappa
from nmsd.assembly import assemble
from nmsd.lattice import Lattice
from nmsd.parameters import NmsdParameters
from nmsd.pipette import Pipette
from nmsd.spring import link_force
from nmsd.symmetry import Mirror, fold, fold_map, reduction_of
from nmsd.zona import zona_link_factor
from oocyte_fe.errors import InputError


@dataclass(frozen=True)
class StepResult:
    """One converged step: positions and velocities (n, 2), contact forces (n, 2) in nN."""

    positions: np.ndarray
    velocities: np.ndarray
    contact_force: np.ndarray
    iterations: int


class NewtonFailure(Exception):
    """Newton did not converge within the iteration limit (the caller shortens the step)."""


class BackwardEulerStepper:
    """Implicit stepper for one lattice, parameter set, pipette and set of held nodes."""

    def __init__(
        self,
        lattice: Lattice,
        params: NmsdParameters,
        pipette: Pipette,
        held: np.ndarray,
        xtol_um: float = 1e-5,
        max_iterations: int = 30,
        refresh_rate: float = 0.2,
        chord_um: float = 1e-2,
        mirror: Mirror | None = None,
    ) -> None:
        self.lattice = lattice
        self.params = params
        self.pipette = pipette
        self.xtol = xtol_um
        self.max_iterations = max_iterations
        self.refresh_rate = refresh_rate
        self.chord_um = chord_um
        n = lattice.n_nodes
        self.n_dof = 2 * n
        a, b = lattice.edges[:, 0], lattice.edges[:, 1]
        spread = int(np.abs(a - b).max())
        if params.area_stiffness > 0:
            if lattice.cells is None or len(lattice.cells) == 0:
                raise InputError(
                    params.source,
                    "area_stiffness",
                    "0 for a lattice without cells",
                    got=params.area_stiffness,
                )
            for row in lattice.cells:
                spread = max(spread, int(np.ptp(row[row >= 0])))
            self._cells = np.ascontiguousarray(lattice.cells, dtype=np.int64)
            self._cell_area = np.ascontiguousarray(lattice.cell_rest_area)
            self._area_kappa = area_kappa(
                params.area_stiffness, params.k1, float(lattice.rest_length.min())
            )
        else:
            self._cells = np.zeros((0, 4), dtype=np.int64)
            self._cell_area = np.zeros(0)
            self._area_kappa = 0.0
        self.band = int(2 * spread + 1)
        held_dof = np.zeros((n, 2), dtype=bool)
        held_dof[np.asarray(held, dtype=bool)] = True
        self.held_dof = held_dof.ravel()
        self._held_nodes = held_dof
        self._normals, self._offsets = pipette.faces()
        self._edges = np.ascontiguousarray(lattice.edges, dtype=np.int64)
        self._rest = np.ascontiguousarray(lattice.rest_length)
        self.link_factor = np.ascontiguousarray(zona_link_factor(lattice, params))
        self._res = np.zeros(self.n_dof)
        self._ab = np.zeros((3 * self.band + 1, self.n_dof), order="F")
        self._contact = np.zeros((n, 2))
        self._lu: tuple[np.ndarray, np.ndarray] | None = None
        self.factorizations = 0
        # symmetric branch: Newton on the half lattice (nmsd.symmetry)
        self.reduction = (
            None
            if mirror is None
            else reduction_of(mirror, lattice.nodes, self._edges, held, self._cells)
        )
        if self.reduction is not None:
            cells = self._cells if self._area_kappa > 0 else None
            self._scatter = fold_map(self.reduction, n, self._edges, self.band, cells)
            self._res_h = np.zeros(self.reduction.n_dof)
            self._ab_h = np.zeros((3 * self.reduction.band + 1, self.reduction.n_dof), order="F")
        # the band system Newton factors: the full tangent, or its half-lattice fold
        self.system_band = self.band if self.reduction is None else self.reduction.band
        self._system_ab = self._ab if self.reduction is None else self._ab_h

    def internal_force(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Link spring forces on the nodes (n, 2) nN and the 2x2 link tangents (m, 2, 2) nN/um.

        The numpy reference of the compiled springs: :func:`nmsd.spring.link_force` times the
        ZP ring factor of each link (:mod:`nmsd.zona`).
        """
        lat, p = self.lattice, self.params
        d = x[lat.edges[:, 0]] - x[lat.edges[:, 1]]
        length = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
        n = d / length[:, None]
        l0 = lat.rest_length
        f, df = link_force(length / l0 - 1.0, p.k1, p.k2, p.dl_c)
        f, df = f * self.link_factor, df * self.link_factor
        force = np.zeros_like(x)
        np.add.at(force, lat.edges[:, 0], f[:, None] * n)
        np.add.at(force, lat.edges[:, 1], -f[:, None] * n)
        nn = n[:, :, None] * n[:, None, :]
        g = f / length
        tangent = (df / l0 - g)[:, None, None] * nn
        tangent[:, 0, 0] += g
        tangent[:, 1, 1] += g
        return force, tangent

    def residual(
        self,
        x_new: np.ndarray,
        x: np.ndarray,
        v: np.ndarray,
        advance: float,
        dt: float,
        with_tangent: bool = True,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
        """Residual (2n,) nN, band-stored tangent, contact forces (n, 2) nN, max |R| (nN).

        The returned arrays are the stepper's work buffers (overwritten by the next call).
        """
        p = self.params
        worst = assemble(
            x_new,
            x,
            v,
            self.lattice.nodes,
            self._edges,
            self._rest,
            self.link_factor,
            p.k1,
            p.k2,
            p.dl_c,
            p.d0,
            p.d1,
            p.damping == "link",
            p.node_mass,
            dt,
            self._normals,
            self._offsets,
            self.pipette.mouth(advance),
            self.pipette.contact_stiffness,
            self._cells,
            self._cell_area,
            self._area_kappa,
            self.held_dof,
            self.band,
            self._res,
            self._ab,
            self._contact,
            with_tangent,
        )
        return self._res, self._ab, self._contact, worst

    def _system(
        self,
        x_new: np.ndarray,
        x: np.ndarray,
        v: np.ndarray,
        advance: float,
        dt: float,
        refresh: bool,
    ) -> np.ndarray:
        """Residual of the system Newton solves (full, or kept rows of the half lattice); with
        ``refresh`` its band tangent is filled too (``_ab`` or ``_ab_h``)."""
        res, ab = self.residual(x_new, x, v, advance, dt, with_tangent=refresh)[:2]
        if self.reduction is None:
            return res
        self.fold(ab, res, self._ab_h, self._res_h, refresh)
        return self._res_h

    def fold(
        self,
        ab: np.ndarray,
        res: np.ndarray,
        ab_h: np.ndarray,
        res_h: np.ndarray,
        with_tangent: bool,
    ) -> None:
        """Fold the full band tangent ``ab`` and residual ``res`` onto the half lattice of the
        symmetric branch (:func:`nmsd.symmetry.fold`), into ``ab_h`` / ``res_h``; ``ab`` and
        ``res`` are left intact."""
        red = self.reduction
        fold(
            ab,
            res,
            red.kept_row,
            red.fixed,
            *self._scatter,
            ab_h,
            red.band,
            res_h,
            with_tangent,
        )

    def _factor(self) -> None:
        band = self.system_band
        lu, piv, info = dgbtrf(self._system_ab, band, band, overwrite_ab=1)
        if info != 0:
            self._lu = None
            raise NewtonFailure("singular tangent")
        self._lu = (lu, piv)
        self.factorizations += 1

    def step(self, x: np.ndarray, v: np.ndarray, advance: float, dt: float) -> StepResult:
        """Advance one step of length dt (s) to the pipette advance ``advance`` (um)."""
        x_new = x + dt * v
        x_new[self._held_nodes] = x[self._held_nodes]
        band = self.system_band
        refresh = True  # a fresh tangent at the predictor (a stale one strays in contact)
        fresh = False
        previous = np.inf
        for iteration in range(1, self.max_iterations + 1):
            res = self._system(x_new, x, v, advance, dt, refresh)
            if refresh:
                self._factor()
                fresh, refresh = True, False
            lu, piv = self._lu
            dx, info = dgbtrs(lu, band, band, -res, piv)
            if info != 0 or not np.all(np.isfinite(dx)):
                if fresh:
                    raise NewtonFailure("non-finite Newton update")
                refresh = True
                continue
            if self.reduction is None:
                x_new += dx.reshape(-1, 2)
            else:
                self.reduction.expand(x_new, dx)
            size = float(np.max(np.abs(dx)))
            if size < self.xtol:
                f_contact = self.residual(x_new, x, v, advance, dt, with_tangent=False)[2]
                return StepResult(x_new, (x_new - x) / dt, f_contact.copy(), iteration)
            # slow contraction with an old factor: refresh it; a fresh one: plain Newton
            refresh = size > self.chord_um or size > self.refresh_rate * previous
            fresh = False
            previous = size
        self._lu = None
        raise NewtonFailure(f"no convergence in {self.max_iterations} Newton iterations")


def explicit_time_step_limit(stepper: BackwardEulerStepper) -> float:
    """Stability limit dt < 2/omega_max of an explicit (central-difference) scheme, s.

    ``omega_max^2`` is the largest eigenvalue of ``K / m`` for the rest lattice with the
    small-strain link stiffness ``k1 / l0`` (held nodes removed; the optional area term of
    :mod:`nmsd.area` is left out, it would shorten the limit). Backward Euler has no such
    limit; this figure shows how far beyond it the implicit step goes.
    """
    x = stepper.lattice.nodes.copy()
    _, tangent = stepper.internal_force(x)
    n_dof = stepper.n_dof
    a, b = stepper.lattice.edges[:, 0], stepper.lattice.edges[:, 1]
    k = np.zeros((n_dof, n_dof))
    for r, c, sign in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
        for p in range(2):
            for q in range(2):
                np.add.at(k, (2 * r + p, 2 * c + q), sign * tangent[:, p, q])
    free = ~stepper.held_dof
    mass = max(stepper.params.node_mass, np.finfo(float).tiny)
    omega_max = np.sqrt(eigh(k[np.ix_(free, free)], eigvals_only=True)[-1] / mass)
    return 2.0 / omega_max
