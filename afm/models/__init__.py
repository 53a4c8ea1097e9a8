"""Tip models for AFM indentation, one module each, registered in :data:`MODELS` by key.

Importing this package imports every model module so that the registry is complete.
"""

from afm.models import (
    flat_punch,
    hertz_paraboloid,
    hertz_sphere,
    pyramid,
    pyramid_3s,
    sneddon_cone,
)
from afm.models.registry import (
    CONTACT_POINT,
    FIT_PARAMETERS,
    MODELS,
    POISSON_RATIO,
    YOUNGS_MODULUS,
    IndentationModel,
    Parameter,
    get_model,
    indentation_model,
)

__all__ = [
    "CONTACT_POINT",
    "FIT_PARAMETERS",
    "MODELS",
    "POISSON_RATIO",
    "YOUNGS_MODULUS",
    "IndentationModel",
    "Parameter",
    "flat_punch",
    "get_model",
    "hertz_paraboloid",
    "hertz_sphere",
    "indentation_model",
    "pyramid",
    "pyramid_3s",
    "sneddon_cone",
]
