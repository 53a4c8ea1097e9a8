"""Backward-Euler time step of eq 1 with Newton iterations on a banded tangent.

Eq 1 of seed 000, per node i (um, nN, s):

    M_i a_i + F_i^d + F_i^k = F_i^ext

with the link forces ``F^k`` of eqs 2-5 (:mod:`nmsd.spring`), the nodal damping ``F^d`` of
eq 6 (:mod:`nmsd.damping`) and the pipette contact ``F^ext`` (:mod:`nmsd.pipette`). Backward
Euler takes ``v+ = (x+ - x)/dt``, ``a+ = (v+ - v)/dt`` and solves the residual

    R(x+) = M (x+ - x - dt v)/dt^2 + (d0 + d1 |x+ - X|)(x+ - x)/dt + F^k(x+) - F^ext(x+) = 0

by Newton with the exact tangent ``M/dt^2 + D/dt + d1 v+ (x) u_hat + K_links + K_contact``.
Backward Euler is A-stable (L-stable): for the linearised system every mode decays for any
dt > 0, so the step is set by accuracy and contact resolution, not by the explicit limit
``dt < 2 / omega_max`` (``omega_max^2`` the largest eigenvalue of ``M^-1 K``, see
:func:`explicit_time_step_limit`). The tangent is assembled with ``np.bincount`` straight into
LAPACK band storage (links join nodes in neighbouring grid rows only) and solved by
LAPACK ``dgbsv`` (banded LU); no Python loop over links or nodes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh
from scipy.linalg.lapack import dgbsv

from nmsd.damping import nodal_damping
from nmsd.lattice import Lattice
from nmsd.parameters import NmsdParameters
from nmsd.pipette import Pipette
from nmsd.spring import link_force


@dataclass(frozen=True)
class StepResult:
    """One converged step: positions and velocities (n, 2), contact forces (n, 2) in nN."""

    positions: np.ndarray
    velocities: np.ndarray
    contact_force: np.ndarray
    iterations: int


class NewtonFailure(Exception):
    """Newton did not converge within the iteration limit (the caller shortens the step)."""


def _block_indices(rows: np.ndarray, cols: np.ndarray, band: int, n_dof: int) -> np.ndarray:
    """Flat indices into LAPACK ``gbsv`` storage (3 band + 1, n_dof) of the 2x2 blocks."""
    p = np.array([0, 0, 1, 1])
    q = np.array([0, 1, 0, 1])
    r = 2 * rows[:, None] + p
    c = 2 * cols[:, None] + q
    return ((2 * band + r - c) * n_dof + c).ravel()


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
    ) -> None:
        self.lattice = lattice
        self.params = params
        self.pipette = pipette
        self.xtol = xtol_um
        self.max_iterations = max_iterations
        n = lattice.n_nodes
        self.n_dof = 2 * n
        a, b = lattice.edges[:, 0], lattice.edges[:, 1]
        self.band = int(2 * np.abs(a - b).max() + 1)
        pairs = ((a, a), (b, b), (a, b), (b, a))
        idx = [_block_indices(r, c, self.band, self.n_dof) for r, c in pairs]
        nodes = np.arange(n)
        self._index = np.concatenate([*idx, _block_indices(nodes, nodes, self.band, self.n_dof)])
        self._size = (3 * self.band + 1) * self.n_dof
        held_dof = np.zeros((n, 2), dtype=bool)
        held_dof[np.asarray(held, dtype=bool)] = True
        self.held_dof = held_dof.ravel()
        held_rows = np.flatnonzero(self.held_dof)
        cols = held_rows[:, None] + np.arange(-self.band, self.band + 1)
        rows = np.broadcast_to(held_rows[:, None], cols.shape)
        ok = (cols >= 0) & (cols < self.n_dof)
        self._held_band = (2 * self.band + rows[ok] - cols[ok]) * self.n_dof + cols[ok]
        self._held_diag = 2 * self.band * self.n_dof + held_rows
        self._a2 = np.concatenate([2 * a, 2 * a + 1, 2 * b, 2 * b + 1])

    def internal_force(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Link forces on the nodes (n, 2) nN and the 2x2 link tangents (m, 2, 2) nN/um."""
        lat, p = self.lattice, self.params
        d = x[lat.edges[:, 0]] - x[lat.edges[:, 1]]
        length = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
        n = d / length[:, None]
        l0 = lat.rest_length
        f, df = link_force(length / l0 - 1.0, p.k1, p.k2, p.dl_c)
        fvec = f[:, None] * n
        weights = np.concatenate([fvec.T.ravel(), -fvec.T.ravel()])
        force = np.bincount(self._a2, weights, self.n_dof)
        nn = n[:, :, None] * n[:, None, :]
        g = f / length
        tangent = (df / l0 - g)[:, None, None] * nn
        tangent[:, 0, 0] += g
        tangent[:, 1, 1] += g
        return force.reshape(-1, 2), tangent

    def contact(self, x: np.ndarray, advance: float) -> tuple[np.ndarray, np.ndarray]:
        """Contact forces on the nodes (n, 2) nN and 2x2 tangents (n, 2, 2) nN/um."""
        g, normal = self.pipette.gap(x, advance)
        kappa = self.pipette.contact_stiffness * (g < 0)
        force = (-kappa * g)[:, None] * normal
        tangent = kappa[:, None, None] * normal[:, :, None] * normal[:, None, :]
        return force, tangent

    def residual(
        self, x_new: np.ndarray, x: np.ndarray, v: np.ndarray, advance: float, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Residual R (n, 2) nN, its band-stored tangent and the contact forces."""
        p = self.params
        v_new = (x_new - x) / dt
        u = x_new - self.lattice.nodes
        damping, coefficient = nodal_damping(u, v_new, p.d0, p.d1)
        f_links, k_links = self.internal_force(x_new)
        f_contact, k_contact = self.contact(x_new, advance)
        res = p.node_mass * (v_new - v) / dt + damping + f_links - f_contact
        unorm = np.sqrt(u[:, 0] ** 2 + u[:, 1] ** 2)
        scale = np.divide(p.d1, unorm, out=np.zeros_like(unorm), where=unorm > 0)
        diag = p.node_mass / dt**2 + coefficient / dt
        node_blocks = k_contact + (scale[:, None] * v_new)[:, :, None] * u[:, None, :]
        node_blocks[:, 0, 0] += diag
        node_blocks[:, 1, 1] += diag
        k = k_links.ravel()
        values = np.concatenate([k, k, -k, -k, node_blocks.ravel()])
        ab = np.bincount(self._index, values, self._size)
        return res, ab.reshape(3 * self.band + 1, self.n_dof), f_contact

    def step(self, x: np.ndarray, v: np.ndarray, advance: float, dt: float) -> StepResult:
        """Advance one step of length dt (s) to the pipette advance ``advance`` (um)."""
        x_new = x + dt * v
        x_new[self.held_dof.reshape(-1, 2)] = x[self.held_dof.reshape(-1, 2)]
        for iteration in range(1, self.max_iterations + 1):
            res, ab, f_contact = self.residual(x_new, x, v, advance, dt)
            rhs = -res.ravel()
            rhs[self.held_dof] = 0.0
            ab = self._hold(ab)
            _, _, dx, info = dgbsv(self.band, self.band, ab, rhs, overwrite_ab=1, overwrite_b=1)
            if info != 0 or not np.all(np.isfinite(dx)):
                raise NewtonFailure("singular tangent or non-finite Newton update")
            x_new = x_new + dx.reshape(-1, 2)
            if np.max(np.abs(dx)) < self.xtol:
                f_contact = self.contact(x_new, advance)[0]
                return StepResult(x_new, (x_new - x) / dt, f_contact, iteration)
        raise NewtonFailure(f"no convergence in {self.max_iterations} Newton iterations")

    def _hold(self, ab: np.ndarray) -> np.ndarray:
        """Band matrix with the held DOFs' rows replaced by identity rows."""
        ab.flat[self._held_band] = 0.0
        ab.flat[self._held_diag] = 1.0
        return ab


def explicit_time_step_limit(stepper: BackwardEulerStepper) -> float:
    """Stability limit dt < 2/omega_max of an explicit (central-difference) scheme, s.

    ``omega_max^2`` is the largest eigenvalue of ``K / m`` for the rest lattice with the
    small-strain link stiffness ``k1 / l0`` (held nodes removed). Backward Euler has no such
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
