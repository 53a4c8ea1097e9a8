"""AFM indentation analysis for oocyte-fe: tip models, curve fitting, pierce-through curves,
creep to a Prony series, viscoelastic fits of the ramp (Ting), and the material file the FE
models read.

Internal units: um, nN, kPa, s. ``afm`` never imports ``oocyte_fe``.
"""

from afm.creep import CreepData, CreepFit, fit_creep, fit_creep_tip, material_from_creep_csv
from afm.curve import ForceCurve
from afm.fit import FitRange, IndentationFit, fit_indentation
from afm.material_file import MaterialFile, read_material, write_material
from afm.models import MODELS, get_model
from afm.pierce import PierceFit, fit_pierce
from afm.prony_series import (
    CreepProny,
    RelaxationProny,
    creep_from_relaxation,
    relaxation_from_creep,
)
from afm.viscoelastic import RampCurve, RampFit, fit_ramp, ramp_from_piezo
from oocyte_fe.errors import InputError, MissingExtraError

__all__ = [
    "MODELS",
    "InputError",
    "CreepData",
    "CreepFit",
    "CreepProny",
    "FitRange",
    "ForceCurve",
    "IndentationFit",
    "MaterialFile",
    "MissingExtraError",
    "PierceFit",
    "RampCurve",
    "RampFit",
    "RelaxationProny",
    "creep_from_relaxation",
    "fit_creep",
    "fit_creep_tip",
    "fit_indentation",
    "fit_pierce",
    "fit_ramp",
    "get_model",
    "material_from_creep_csv",
    "ramp_from_piezo",
    "read_material",
    "relaxation_from_creep",
    "write_material",
]
