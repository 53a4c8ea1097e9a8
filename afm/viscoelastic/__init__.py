"""Viscoelastic fits of force ramps with Ting's method: relaxation models, Ting's force, fit.

Modules: :mod:`~afm.viscoelastic.kernel` (registry), :mod:`~afm.viscoelastic.power_law`,
:mod:`~afm.viscoelastic.standard_linear_solid`, :mod:`~afm.viscoelastic.prony` (relaxation
moduli), :mod:`~afm.viscoelastic.ting` (the force), :mod:`~afm.viscoelastic.ramp` (the data),
:mod:`~afm.viscoelastic.fit` (the fit and its material record).
"""

from afm.viscoelastic import power_law, prony, standard_linear_solid
from afm.viscoelastic.fit import RampFit, fit_ramp
from afm.viscoelastic.kernel import RELAXATION_MODELS, RelaxationModel, get_relaxation_model
from afm.viscoelastic.ramp import RampCurve, ramp_from_piezo
from afm.viscoelastic.ting import ting_force

__all__ = [
    "RELAXATION_MODELS",
    "RampCurve",
    "RampFit",
    "RelaxationModel",
    "fit_ramp",
    "get_relaxation_model",
    "power_law",
    "prony",
    "ramp_from_piezo",
    "standard_linear_solid",
    "ting_force",
]
