"""The vectorised displacement blocks equal scikit-fem's assembly of the same weak forms."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import Basis, BilinearForm, ElementTriP1, ElementTriP2, ElementVector, LinearForm, asm

from oocyte_fe.fe.kinematics import grad5
from oocyte_fe.fe.vectorized import RegionOperators
from tests.fe_geometry import quarter_annulus


def _measure(w):
    return np.where(w.axisym > 0, 2.0 * np.pi * w.x[0], 1.0)


def _g5(v, w):
    return grad5(v, v.grad, w.x[0] if w.axisym > 0 else None)


@LinearForm
def _force(v, w):
    return np.einsum("a...,a...->...", w.P5, _g5(v, w)) * _measure(w)


@BilinearForm
def _stiffness(du, v, w):
    return np.einsum("a...,ab...,b...->...", _g5(v, w), w.A5, _g5(du, w)) * _measure(w)


@BilinearForm
def _coupling(dp, v, w):
    return np.einsum("a...,a...->...", w.JFinvT5, _g5(v, w)) * dp * _measure(w)


@pytest.mark.parametrize("axisym", [0.0, 1.0])
def test_vectorised_blocks_equal_scikit_fem_forms(axisym: float) -> None:
    mesh = quarter_annulus(10.0, 20.0, 3, 4)
    elements = np.arange(0, mesh.nelements, 2)  # a region: every other element
    ub = Basis(mesh, ElementVector(ElementTriP2()), intorder=4, elements=elements)
    pb = Basis(mesh, ElementTriP1(), intorder=4, elements=elements)
    ops = RegionOperators.of(ub, pb, bool(axisym))
    rng = np.random.default_rng(1)
    shape = ub.dx.shape
    P5 = rng.standard_normal((5, *shape))
    A5 = rng.standard_normal((5, 5, *shape))
    G5 = rng.standard_normal((5, *shape))
    f_ref = asm(_force, ub, P5=P5, axisym=axisym)
    K_ref = asm(_stiffness, ub, A5=A5, axisym=axisym).toarray()
    G_ref = asm(_coupling, pb, ub, JFinvT5=G5, axisym=axisym).toarray()
    scale = np.abs(K_ref).max()
    np.testing.assert_allclose(ops.internal_force(P5), f_ref, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(ops.stiffness(A5).toarray(), K_ref, atol=1e-12 * scale)
    rows, cols, vals = ops.coupling(G5)
    G = np.zeros_like(G_ref)
    np.add.at(G, (rows, cols), vals)
    np.testing.assert_allclose(G, G_ref, atol=1e-12 * np.abs(G_ref).max())
    # the stacked gradients reproduce grad5 of a field: u = (x y, x^2) exactly in P2
    u = ub.project(lambda x: np.stack([x[0] * x[1], x[0] ** 2]))
    uq = ub.interpolate(u)
    R = np.asarray(ub.global_coordinates())[0] if axisym else None
    np.testing.assert_allclose(
        np.einsum("iaeq,ie->aeq", ops.B, u[ops.dofs]), grad5(uq, uq.grad, R), atol=1e-10
    )


@pytest.mark.parametrize("axisym", [0.0, 1.0])
def test_vectorised_facet_blocks_equal_scikit_fem_forms(axisym: float) -> None:
    from skfem import FacetBasis

    from oocyte_fe.fe.contact import ContactEval
    from oocyte_fe.fe.vectorized import FacetOperators
    from tests.reference_forms import (
        contact_stiffness,
        contact_traction,
        pressure_force,
        pressure_stiffness,
    )

    mesh = quarter_annulus(10.0, 20.0, 3, 4)
    fb = FacetBasis(
        mesh, ElementVector(ElementTriP2()), facets=mesh.boundaries["outer"], intorder=4
    )
    ops = FacetOperators.of(fb)
    rng = np.random.default_rng(2)
    u = 0.3 * rng.standard_normal(fb.N)
    shape = fb.dx.shape
    pn = rng.standard_normal(shape)
    f, K = ops.pressure(u, pn, bool(axisym))
    np.testing.assert_allclose(ops.pressure_force(u, pn, bool(axisym)), f, atol=0)
    uq = fb.interpolate(u)
    f_ref = asm(pressure_force, fb, u=uq, pn=pn, axisym=axisym)
    K_ref = asm(pressure_stiffness, fb, u=uq, pn=pn, axisym=axisym).toarray()
    np.testing.assert_allclose(f, f_ref, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(K.toarray(), K_ref, atol=1e-12 * np.abs(K_ref).max())
    ang = rng.uniform(0, 2 * np.pi, shape)
    n = np.stack([np.cos(ang), np.sin(ang)])
    ev = ContactEval(
        gap=np.zeros(shape),
        normal=n,
        tangent=np.stack([-n[1], n[0]]),
        pressure=rng.uniform(0, 1, shape),
        shear=rng.standard_normal(shape),
        slip=np.zeros(shape),
        k_nn=rng.uniform(0, 5, shape),
        k_tt=rng.uniform(0, 5, shape),
        k_tn=rng.standard_normal(shape),
        k_nt=rng.standard_normal(shape),
    )
    f, K = ops.contact(ev, bool(axisym))
    f_ref = asm(contact_traction, fb, tr=ev.traction, axisym=axisym)
    K_ref = asm(
        contact_stiffness,
        fb,
        n_c=ev.normal,
        t_c=ev.tangent,
        k_nn=ev.k_nn,
        k_tt=ev.k_tt,
        k_tn=ev.k_tn,
        k_nt=ev.k_nt,
        axisym=axisym,
    ).toarray()
    np.testing.assert_allclose(f, f_ref, atol=1e-12 * np.abs(f_ref).max())
    np.testing.assert_allclose(K.toarray(), K_ref, atol=1e-12 * np.abs(K_ref).max())
    value, grad = ops.interpolate(u)
    np.testing.assert_allclose(value, np.asarray(uq), atol=1e-12)
    np.testing.assert_allclose(grad, uq.grad, atol=1e-12)
