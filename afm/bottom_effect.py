"""Bottom-effect corrections for a layer of thickness ``h`` bonded to a rigid support, nu = 0.5.

Sphere of radius ``R`` (Dimitriadis et al. 2002, Biophys. J. 82:2798, eq. 12, bonded):

    F = 16/9 E R^(1/2) d^(3/2) [1 + 1.133 x + 1.283 x^2 + 0.769 x^3 + 0.0975 x^4],
    x = sqrt(R d) / h

(eq. 12's numbers; the first two are -2 alpha0/pi and 4 alpha0^2/pi^2 with their
alpha0 = -1.7795 at nu = 0.5). Checked against the project's FE in its own limit (docs/afm.md,
"Bottom-effect corrections").

Cone of half angle ``alpha`` (Garcia and Garcia 2018, Biophys. J. 114:2923, bonded):

    F = 8/(3 pi) E tan(alpha) d^2 [1 + 0.721 y + 0.650 y^2 + 0.491 y^3 + 0.225 y^4],
    y = d tan(alpha) / h

implemented from the paper; checked against the project's FE for a 70 deg cone (the FE cone is
verified for half angles of 55 deg and blunter, docs/fe.md): within 1.4 % for
0.11 <= y <= 0.99 (the heavy case ``afm_shell_correction``).

A half-space fit from contact to ``d`` with points uniform in depth (least squares in E) of a
curve that follows ``F = E s(d') f(d')`` reads ``E_fit = E int s^2 f / int s^2``
(:func:`fit_factor`); the corrected modulus is ``E = E_fit / fit_factor``. Units: um, kPa.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from afm.models import get_model
from oocyte_fe import checks
from oocyte_fe.errors import InputError

DIMITRIADIS_BONDED = (1.133, 1.283, 0.769, 0.0975)
"""Dimitriadis et al. (2002) eq. 12: bonded, nu = 0.5, coefficients of x = sqrt(R d)/h."""
GARCIA_CONE = (0.721, 0.650, 0.491, 0.225)
"""Garcia and Garcia (2018), cone, bonded, nu = 0.5, coefficients of y = d tan(alpha)/h."""
SPHERE_MODELS = ("hertz_sphere", "hertz_paraboloid")
CONE_MODELS = ("sneddon_cone",)


def _polynomial(coefficients: tuple[float, ...], x: np.ndarray) -> np.ndarray:
    return 1.0 + sum(c * x ** (k + 1) for k, c in enumerate(coefficients))


def _checked(
    where: str, depth_um: object, radius_um: object, layer_um: object
) -> tuple[np.ndarray, float, float]:
    """Depths (>= 0) and lengths (within a length's bounds) as numbers, or refused."""
    return (
        checks.numbers_array(where, "depth_um", depth_um, ge=0.0, le=1e6),
        checks.quantity(where, "radius_um", radius_um, "length_um"),
        checks.quantity(where, "layer_um", layer_um, "length_um"),
    )


def dimitriadis_factor(depth_um: np.ndarray, radius_um: float, layer_um: float) -> np.ndarray:
    """F / F_Hertz of a sphere on a bonded layer, nu = 0.5 (Dimitriadis 2002, eq. 12) [1]."""
    depth_um, radius_um, layer_um = _checked("dimitriadis_factor", depth_um, radius_um, layer_um)
    x = np.sqrt(radius_um * depth_um) / layer_um
    return _polynomial(DIMITRIADIS_BONDED, x)


def garcia_cone_factor(depth_um: np.ndarray, half_angle_deg: float, layer_um: float) -> np.ndarray:
    """F / F_Sneddon of a cone on a bonded layer, nu = 0.5 (Garcia and Garcia 2018) [1]."""
    where = "garcia_cone_factor"
    half_angle_deg = checks.quantity(where, "half_angle_deg", half_angle_deg, "cone_half_angle_deg")
    depth_um, _, layer_um = _checked(where, depth_um, 1.0, layer_um)
    y = depth_um * math.tan(math.radians(half_angle_deg)) / layer_um
    return _polynomial(GARCIA_CONE, y)


def factor(
    model: str, geometry: Mapping[str, float], depth_um: np.ndarray, layer_um: float
) -> np.ndarray:
    """F / F_half-space at ``depth_um``: Garcia's for a cone, Dimitriadis' for a sphere."""
    if model in CONE_MODELS:
        return garcia_cone_factor(depth_um, geometry["half_angle_deg"], layer_um)
    return dimitriadis_factor(depth_um, geometry["radius_um"], layer_um)


def fit_factor(
    model: str, geometry: Mapping[str, float], depth_um: float, layer_um: float
) -> float:
    """E_fit / E of a half-space fit of ``model`` (hertz_sphere, hertz_paraboloid:
    ``radius_um``; sneddon_cone: ``half_angle_deg``) from contact to ``depth_um`` (points
    uniform in depth) on a bonded layer of ``layer_um``: ``int s^2 f / int s^2`` [1]."""
    tip = get_model(model, "fit_factor")
    if not isinstance(geometry, Mapping):
        raise InputError("fit_factor", "geometry", "a table of tip parameters", got=geometry)
    geometry = tip.check_geometry(geometry, "fit_factor")
    depth_um = checks.quantity("fit_factor", "depth_um", depth_um, "length_um")
    x = np.linspace(0.0, depth_um, 2001)
    shape = tip.shape(x, geometry, 0.5)
    f = factor(model, geometry, x, layer_um)
    return float(np.trapezoid(shape**2 * f, x) / np.trapezoid(shape**2, x))
