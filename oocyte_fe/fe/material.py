"""Nearly incompressible neo-Hookean solid with a quasi-linear Prony series, and its file.

Strain energy (mixed displacement-pressure form, ``p`` an independent field)::

    Pi(u, p) = int [ mu/2 (J^(-2/3) I1 - 3) + p (J - 1) - p^2 / (2 kappa) ] dV

``mu = E / (2 (1 + nu))`` [kPa], ``kappa = E / (3 (1 - 2 nu))`` [kPa]; ``nu = 0.5`` gives
``1/kappa = 0``, exact incompressibility ``J = 1`` weakly. The deviatoric stress relaxes as

    G(t) / G0 = g_inf + sum_i g_i exp(-t / tau_i),   g_inf = 1 - sum_i g_i,

applied to the deviatoric second Piola-Kirchhoff stress (Simo 1987; the ANSYS ``TB,PRONY``
shear series and FEBio's ``viscoelastic`` material with ``g_i``, ``t_i``). The material file is
the one :mod:`afm.material_file` writes and validates::

    [material]
    name = "zona_pellucida"
    source = "afm_creep_prony case"
    E_kPa = 7.01
    nu = 0.5
    [prony]          # optional
    g = [0.2, 0.1]
    tau_s = [0.1, 1.0]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from afm.material_file import read_material
from oocyte_fe import checks
from oocyte_fe.errors import InputError
from oocyte_fe.fe.kinematics import ACTIVE_I, ACTIVE_J, Kinematics, active, cross5, outer5


@dataclass(frozen=True)
class Prony:
    """Normalised Prony terms ``g_i`` [-] and relaxation times ``tau_i`` [s]."""

    g: tuple[float, ...] = ()
    tau_s: tuple[float, ...] = ()
    source: str = "Prony series"

    def __post_init__(self) -> None:
        if len(self.g) != len(self.tau_s):
            raise InputError(self.source, "prony.g", f"as many terms as tau_s ({len(self.tau_s)})")
        if any(not np.isfinite(g) or g < 0 for g in self.g):
            raise InputError(self.source, "prony.g", "non-negative terms g_i", got=list(self.g))
        if sum(self.g) >= 1.0:
            raise InputError(self.source, "prony.g", "sum of g_i < 1", got=sum(self.g))
        if any(not np.isfinite(t) or t <= 0 for t in self.tau_s):
            raise InputError(
                self.source, "prony.tau_s", "relaxation times > 0", got=list(self.tau_s)
            )

    @property
    def g_inf(self) -> float:
        return 1.0 - float(sum(self.g))

    def relaxation(self, t: NDArray) -> NDArray:
        """``G(t) / G0`` [-]."""
        t = np.asarray(t, dtype=float)
        return self.g_inf + sum(
            g * np.exp(-t / tau) for g, tau in zip(self.g, self.tau_s, strict=False)
        )


@dataclass(frozen=True)
class Material:
    """Young's modulus ``E_kPa`` [kPa], Poisson ratio ``nu`` (0.5 allowed) and Prony terms."""

    E_kPa: float
    nu: float
    prony: Prony = field(default_factory=Prony)
    name: str = "material"
    source: str = "material"

    def __post_init__(self) -> None:
        if not np.isfinite(self.E_kPa) or self.E_kPa <= 0:
            raise InputError(self.source, "material.E_kPa", "a positive modulus", got=self.E_kPa)
        if not (-1.0 < self.nu <= 0.5):
            raise InputError(self.source, "material.nu", "-1 < nu <= 0.5", got=self.nu)

    @property
    def mu(self) -> float:
        """Shear modulus ``E / (2 (1 + nu))`` [kPa]."""
        return self.E_kPa / (2.0 * (1.0 + self.nu))

    @property
    def inv_kappa(self) -> float:
        """Bulk compliance ``3 (1 - 2 nu) / E`` [1/kPa]; zero when incompressible."""
        return 3.0 * (1.0 - 2.0 * self.nu) / self.E_kPa


def read_material_file(path: str | Path) -> Material:
    """Read the material file written by :mod:`afm` (format and validation live there).

    The file is checked first through :mod:`oocyte_fe.checks` (a regular UTF-8 file, not a
    folder, FIFO or symlink loop); nesting too deep for the TOML parser is one clear line.
    """
    checks.read_text(path)
    try:
        record = read_material(path)
    except RecursionError:
        raise InputError(path, "", "a material file of [material] and [prony] tables") from None
    prony = Prony(record.g, record.tau_s, source=str(path))
    return Material(record.E_kPa, record.nu, prony, name=record.name, source=str(path))


@dataclass
class ViscousHistory:
    """Prony history at quadrature points: last converged elastic deviatoric ``S0`` and ``h_i``."""

    S0: NDArray  # (3, 3, nel, nqp)
    h: NDArray  # (nterms, 3, 3, nel, nqp)

    @classmethod
    def zeros(cls, nterms: int, shape: tuple[int, int]) -> ViscousHistory:
        return cls(np.zeros((3, 3, *shape)), np.zeros((nterms, 3, 3, *shape)))


def _prony_factors(prony: Prony, dt: float) -> tuple[NDArray, NDArray]:
    """``e_i = exp(-dt/tau_i)`` and ``c_i = (1 - e_i) / (dt/tau_i)`` (``c_i -> 1`` as dt -> 0)."""
    x = dt / np.asarray(prony.tau_s, dtype=float)
    e = np.exp(-x)
    c = np.where(x > 1e-12, -np.expm1(-x) / np.where(x > 1e-12, x, 1.0), 1.0)
    return e, c


@dataclass(frozen=True)
class Response:
    """Stress and tangents at quadrature points, in active (5-component) form."""

    P5: NDArray  # first Piola-Kirchhoff stress [kPa]
    A5: NDArray  # dP/dF (5x5) [kPa]
    JFinvT5: NDArray  # dJ/dF = J F^-T
    S0: NDArray  # elastic deviatoric 2nd PK stress (3x3), for the history update


def response(
    kin: Kinematics, p: NDArray, material: Material, history: ViscousHistory | None, dt: float
) -> Response:
    """Stress ``P`` and tangent ``dP/dF`` for the current ``F``, pressure ``p`` and step ``dt``.

    Elastic deviatoric part (``a = mu J^(-2/3)``)::

        P0 = a (F - I1/3 F^-T)
        A0 = a [ d_ik d_JL - 2/3 (F_iJ F^-T_kL + F^-T_iJ F_kL) + 2/9 I1 F^-T_iJ F^-T_kL
                 + I1/3 F^-1_Li F^-1_Jk ]

    Viscous part, with ``S0 = F^-1 P0`` and the exact update for ``S0`` linear in the step::

        h_i(n+1) = e_i h_i(n) + c_i (S0(n+1) - S0(n))
        S_dev    = g_inf S0 + sum g_i h_i(n+1) = gamma S0 + H,   gamma = g_inf + sum g_i c_i
        P_dev    = gamma P0 + F H,   dP_dev/dF = gamma A0 + d_ik H_LJ

    Pressure part: ``P_p = p J F^-T``, ``dP_p/dF = p J (F^-T_iJ F^-T_kL - F^-1_Li F^-1_Jk)``.

    With small-strain kinematics (``kin.small``) the linear solid instead:
    ``P0 = 2 mu dev(eps)``, ``eps = sym(Grad u)``, ``A0 = 2 mu (I_sym - 1/3 I x I)``, the
    same Prony recursion on ``S0 = P0`` (``P_dev = gamma P0 + H``), ``P_p = p I``.
    """
    if kin.small:
        return _small_strain_response(kin, p, material, history, dt)
    F, FinvT = kin.F, kin.FinvT
    a = material.mu * kin.J ** (-2.0 / 3.0)
    P0 = a * (F - kin.I1 / 3.0 * FinvT)
    cross = cross5(kin.Finv)
    A0 = a * (
        np.eye(5)[:, :, None, None]
        - 2.0 / 3.0 * (outer5(F, FinvT) + outer5(FinvT, F))
        + 2.0 / 9.0 * kin.I1 * outer5(FinvT, FinvT)
        + kin.I1 / 3.0 * cross
    )
    S0 = np.einsum("iJ...,iK...->JK...", kin.Finv.swapaxes(0, 1), P0)
    P = P0
    A = A0
    if history is not None and material.prony.g:
        g = np.asarray(material.prony.g)
        e, c = _prony_factors(material.prony, dt)
        gamma = material.prony.g_inf + float(np.sum(g * c))
        H = np.einsum("i,i...->...", g * e, history.h) - float(np.sum(g * c)) * history.S0
        P = gamma * P0 + np.einsum("iK...,KJ...->iJ...", F, H)
        same_i = (ACTIVE_I[:, None] == ACTIVE_I[None, :]).astype(float)
        A = gamma * A0 + same_i[:, :, None, None] * H[ACTIVE_J[None, :], ACTIVE_J[:, None]]
    JFinvT = kin.J * FinvT
    P5 = active(P) + p * active(JFinvT)
    A5 = A + p * kin.J * (outer5(FinvT, FinvT) - cross)
    return Response(P5=P5, A5=A5, JFinvT5=active(JFinvT), S0=S0)


_EYE5 = active(np.eye(3))
_SAME = (ACTIVE_I[:, None] == ACTIVE_I[None, :]) & (ACTIVE_J[:, None] == ACTIVE_J[None, :])
_SWAP = (ACTIVE_I[:, None] == ACTIVE_J[None, :]) & (ACTIVE_J[:, None] == ACTIVE_I[None, :])
_SYM5 = 0.5 * (_SAME.astype(float) + _SWAP.astype(float))  # d sym(G) / d G
_DEV5 = _SYM5 - np.outer(_EYE5, _EYE5) / 3.0  # d dev(sym G) / d G, active components


def _small_strain_response(
    kin: Kinematics, p: NDArray, material: Material, history: ViscousHistory | None, dt: float
) -> Response:
    """The linear (small-strain) solid of :func:`response`."""
    G = kin.F - np.eye(3)[:, :, None, None]
    eps = 0.5 * (G + G.swapaxes(0, 1))
    dev = eps - np.trace(eps) / 3.0 * np.eye(3)[:, :, None, None]
    P0 = 2.0 * material.mu * dev
    P, gamma = P0, 1.0
    if history is not None and material.prony.g:
        g = np.asarray(material.prony.g)
        e, c = _prony_factors(material.prony, dt)
        gamma = material.prony.g_inf + float(np.sum(g * c))
        H = np.einsum("i,i...->...", g * e, history.h) - float(np.sum(g * c)) * history.S0
        P = gamma * P0 + H
    A5 = np.broadcast_to(
        (2.0 * material.mu * gamma * _DEV5)[:, :, None, None], (5, 5, *p.shape)
    ).copy()
    eye5 = np.broadcast_to(_EYE5[:, None, None], (5, *p.shape))
    return Response(P5=active(P) + p * eye5, A5=A5, JFinvT5=eye5.copy(), S0=P0)


def update_history(
    history: ViscousHistory, material: Material, S0_new: NDArray, dt: float
) -> ViscousHistory:
    """History after a converged step: ``h_i += ...`` (see :func:`response`), ``S0 <- S0_new``."""
    if not material.prony.g:
        return history
    e, c = _prony_factors(material.prony, dt)
    dS = S0_new - history.S0
    h = e[:, None, None, None, None] * history.h + c[:, None, None, None, None] * dS[None]
    return ViscousHistory(S0=S0_new.copy(), h=h)
