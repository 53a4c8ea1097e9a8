"""Tip-model registry: style of every entry and each formula against its closed form."""

import importlib
import math

import numpy as np
import pytest

from afm.models import FIT_PARAMETERS, MODELS, POISSON_RATIO, get_model
from oocyte_fe.errors import InputError

GEOMETRIES = {
    "sneddon_cone": {},
    "flat_punch": {"radius_um": 2.0},
    "hertz_paraboloid": {"radius_um": 5.0},
    "hertz_sphere": {"radius_um": 5.0},
    "pyramid": {"face_angle_deg": 35.0},
    "pyramid_3s": {"face_angle_deg": 35.0},
}


def test_registry_lists_the_six_tip_models():
    assert set(MODELS) == {
        "flat_punch",
        "sneddon_cone",
        "hertz_paraboloid",
        "hertz_sphere",
        "pyramid",
        "pyramid_3s",
    }


@pytest.mark.parametrize("key", sorted(MODELS))
def test_model_style(key):
    """Key = module name, docstring with equation and units, parameters with units/bounds."""
    model = MODELS[key]
    module = importlib.import_module(f"afm.models.{key}")
    assert model.shape.__module__ == module.__name__
    doc = module.__doc__ or ""
    for word in ("[nN]", "[kPa]", "[um]", "Reference"):
        assert word in doc, f"{key}: module docstring lacks {word}"
    assert model.equation.startswith(("F =", "delta ="))
    for p in model.geometry_parameters:
        assert p.unit in {"um", "deg"}
        assert p.lower < p.upper
    assert model.exponent > 0


def test_parameter_keys_keep_one_unit_in_every_model():
    units: dict[str, str] = {p.key: p.unit for p in (*FIT_PARAMETERS, POISSON_RATIO)}
    for model in MODELS.values():
        for p in model.geometry_parameters:
            assert units.setdefault(p.key, p.unit) == p.unit, (model.key, p.key)


@pytest.mark.parametrize("key", sorted(MODELS))
def test_dshape_is_the_derivative_of_shape(key):
    model = MODELS[key]
    geometry = model.check_geometry(GEOMETRIES[key])
    d = np.array([0.05, 0.4, 1.3])
    h = 1e-6
    numeric = (model.shape(d + h, geometry, 0.5) - model.shape(d - h, geometry, 0.5)) / (2 * h)
    np.testing.assert_allclose(model.dshape(d, geometry, 0.5), numeric, rtol=1e-6)


def test_sneddon_cone_gives_nanonewtons_from_kilopascals_and_micrometres():
    # F = (2/pi) E/(1-nu^2) tan(alpha) delta^2 with E = 7.01 kPa, delta = 2 um, alpha = 10 deg
    expected = 2 / math.pi * 7.01 / 0.75 * math.tan(math.radians(10)) * 4.0
    got = get_model("sneddon_cone").force(np.array([2.0]), 7.01, {"half_angle_deg": 10.0}, 0.5)
    assert got[0] == pytest.approx(expected, rel=1e-14)
    # same in SI: 7010 Pa, 2e-6 m -> N, times 1e9 -> nN
    si = 2 / math.pi * 7010 / 0.75 * math.tan(math.radians(10)) * (2e-6) ** 2 * 1e9
    assert got[0] == pytest.approx(si, rel=1e-12)


def test_pyramid_and_paraboloid_closed_forms():
    d = np.array([1.0])
    pyr = get_model("pyramid").force(d, 2.0, {"face_angle_deg": 35.0}, 0.5)[0]
    assert pyr == pytest.approx(0.7453 * 2.0 / 0.75 * math.tan(math.radians(35.0)))
    pyr3 = get_model("pyramid_3s").force(d, 2.0, {"face_angle_deg": 35.0}, 0.5)[0]
    assert pyr3 == pytest.approx(0.8887 * 2.0 / 0.75 * math.tan(math.radians(35.0)))
    par = get_model("hertz_paraboloid").force(d, 2.0, {"radius_um": 4.0}, 0.5)[0]
    assert par == pytest.approx(4 / 3 * 2.0 / 0.75 * 2.0)


def test_exact_sphere_tends_to_paraboloid_for_shallow_indentation():
    d = np.array([1e-4, 1e-3])
    g = {"radius_um": 5.0}
    ratio = MODELS["hertz_sphere"].shape(d, g, 0.5) / MODELS["hertz_paraboloid"].shape(d, g, 0.5)
    np.testing.assert_allclose(ratio, 1.0, atol=3e-4)
    # deep: the exact sphere is softer than the paraboloid (contact radius grows slower)
    assert (
        MODELS["hertz_sphere"].shape(np.array([2.0]), g, 0.5)[0]
        < MODELS["hertz_paraboloid"].shape(np.array([2.0]), g, 0.5)[0]
    )


def test_geometry_is_validated_with_names():
    with pytest.raises(InputError, match="radius_um"):
        MODELS["hertz_paraboloid"].check_geometry({})
    with pytest.raises(InputError, match="half_angle_deg"):
        MODELS["sneddon_cone"].check_geometry({"half_angle_deg": 95.0})
    with pytest.raises(InputError, match="radius"):
        MODELS["sneddon_cone"].check_geometry({"radius": 1.0})
    with pytest.raises(InputError, match="one of"):
        get_model("berkovich")
    assert MODELS["sneddon_cone"].check_geometry({}) == {"half_angle_deg": 10.0}
