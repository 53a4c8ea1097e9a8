"""Boundary conditions and loads: fixed/prescribed displacement, follower pressure.

Follower pressure ``p`` [kPa] on a boundary acts on the deformed surface (Nanson,
``n da = J F^-T N dA``). In the section plane, per reference arc length ``dS``::

    f = -p a cof(F2) N,   cof(F2) = [[F22, -F21], [-F12, F11]],
    a = 2 pi r = 2 pi (R + u_R)  (axisymmetric)  or 1 (plane strain, per unit thickness)

A ``where(x)`` mask (evaluated in the current configuration) restricts the pressure to part of
the boundary, for example the surface inside a pipette (suction = negative pressure). Its
derivative is not in the tangent (the mask may depend on the whole surface, e.g. a seal's rear
edge); where that stalls Newton, ``lagged=True`` evaluates the mask once per step, in the last
converged configuration, and holds it on the same material points during the step (an explicit
update of the loaded region: its error is one step's motion of the region's edge).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from numpy.typing import NDArray


def _zero(_t: float) -> float:
    return 0.0


@dataclass(frozen=True)
class Prescribed:
    """Displacement component ``component`` (0: x/R, 1: y/Z) on ``boundary`` equals ``value(t)``
    [um]. ``Prescribed("axis", 0)`` is the axis of symmetry, ``u_R = 0``."""

    boundary: str
    component: int
    value: Callable[[float], float] = _zero


@dataclass(frozen=True)
class PinnedPoint:
    """Displacement component ``component`` of the mesh vertex at ``point`` [um] equals
    ``value(t)`` [um]: removes a rigid-body motion (e.g. ``u_Z`` at the centre of a sphere)."""

    point: tuple[float, float]
    component: int
    value: Callable[[float], float] = _zero


@dataclass(frozen=True)
class FollowerPressure:
    """Pressure ``pressure(t)`` [kPa] on ``boundary``; positive pushes against the normal."""

    boundary: str
    pressure: Callable[[float], float]
    where: Callable[[NDArray], NDArray] | None = None  # current x (2, ...) -> bool mask
    name: str = "pressure"
    lagged: bool = False  # evaluate ``where`` at the start of each step (see module docstring)


@dataclass(frozen=True)
class ReactionControl:
    """Load control by a reaction: the magnitude of the pressure load named ``load`` becomes an
    unknown [kPa], found in every step together with the displacements so that the net reaction
    on the prescribed ``component`` of ``boundary`` equals ``target_nN`` (nN; axisymmetric: the
    ring sum). The prescribed boundary then sets the progress (a displacement control) while
    the pressure carries the load: e.g. the suction that pulls an oocyte through a pipette at a
    given advance with no net push from the rear. Solved with the bordered Newton system::

        [K_ff  -g_f] [dx]    [-r_f    ]
        [s     -g_c] [dp] =  [T - R   ],   s = sum of the rows of K on the boundary dofs

    (``g`` the load vector of a unit pressure, ``R`` the current net reaction). While the load
    has no resultant along ``component`` (e.g. a mask still empty) the pressure is held.
    The load's own ``pressure(t)`` is not used.
    """

    load: str
    boundary: str
    component: int
    target_nN: float = 0.0


@dataclass(frozen=True)
class SurfaceTraction:
    """A dead traction ``scale(t) T(X)`` [kPa] on ``boundary``, per reference area.

    ``traction`` maps reference points (2, ...) [um] to nominal tractions (2, ...) [kPa]; the
    load does not follow the deformation (the one-way reading of a flow's traction on the
    undeformed cell), so it adds no stiffness. Per reference arc length ``dS``::

        f_i = scale(t) T(X) . v_i A dS,   A = 2 pi R (axisymmetric) or 1 (plane strain)
    """

    boundary: str
    traction: Callable[[NDArray], NDArray]
    scale: Callable[[float], float]
    name: str = "traction"


@dataclass(frozen=True)
class BodyForce:
    """A dead body force ``scale(t) b(X)`` [nN/um^3] per reference volume:
    ``f_i = scale(t) int b(X) . v_i dV`` (``dV = 2 pi R dA`` axisymmetric, ``dA`` plane strain);
    e.g. the inertia relief of a free cell, ``b = -rho a`` of its rigid-body acceleration."""

    force: Callable[[NDArray], NDArray]
    scale: Callable[[float], float]
    name: str = "body force"


@dataclass(frozen=True)
class TorqueRelief:
    """The turning part of a free cell's inertia relief, in the current configuration
    (plane strain). Dead loads balanced on the reference configuration (zero resultant and
    moment there) keep a zero resultant as the cell deforms, but their moment about the
    deformed cell does not stay zero; without this the two pins of a free cell carry it as
    a pair of point forces. Each residual evaluation adds the body force of the rotation
    mode ``b = c (-(Y - Y_c), X - X_c)`` [nN/um^3] per reference area (about the reference
    centroid, so that it has no resultant) with ``c`` such that the external forces have no
    moment in the current configuration::

        sum_i (x_i f_iy - y_i f_ix) = 0   over the displacement nodes at x_i = X_i + u_i

    It is the d'Alembert force of the cell's angular acceleration, spread over the reference
    section rather than the deformed one. Newton's tangent includes its derivative, the
    rank-one ``g (grad M_f + c grad M_g)^T / M_g`` (``g`` the mode's load vector, ``M`` the
    moments above).

    ``translation``: also the resultant, for follower loads whose resultant changes as the
    cell deforms (balanced on the reference by the dead inertia relief): each residual adds
    first the uniform body force ``b = -F(x) / A`` [nN/um^3] (``F`` the resultant of the
    external forces at ``x``, ``A`` the reference area), so that no pin carries it. Its
    tangent is rank two, ``g_d (sum of the rows d of K_loads) / G_d`` per direction ``d``
    (``K_loads = -d f / d u`` of the follower loads), and the rotation mode's ``grad M_f``
    takes their ``-(x . K_loads[y] - y . K_loads[x])``: Newton keeps its quadratic rate
    (three iterations a step under a flow's traction, where leaving them out took up to 25).
    The low-rank parts are solved by Woodbury on the one factorisation."""

    name: str = "torque relief"
    translation: bool = False
