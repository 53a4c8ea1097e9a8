"""Conversions from the units used in files to the package's system (um, nN, kPa, s).

Derived internal units: viscosity kPa s, density nN s^2/um^4 (mass nN s^2/um = 1e-3 kg over
um^3 = 1e-18 m^3, so 1 nN s^2/um^4 = 1e15 kg/m^3 and 1008 kg/m^3 = 1.008e-12), velocity
um/s, pressure gradient kPa/um. 1 cP (centipoise) = 1 mPa s.
Each table maps a unit suffix, as it appears in a column or key name, to the factor that takes
a value in that unit to the internal one.
"""

from __future__ import annotations

VISCOSITY = {"Pa_s": 1e-3, "mPa_s": 1e-6, "cP": 1e-6, "kPa_s": 1.0}
PRESSURE = {"Pa": 1e-3, "hPa": 0.1, "kPa": 1.0, "mbar": 0.1, "bar": 100.0}
DENSITY = {"kg_m3": 1e-15, "g_cm3": 1e-12}
LENGTH = {"um": 1.0, "mm": 1e3, "m": 1e6}
SHEAR_RATE = {"1_s": 1.0}
VELOCITY = {"um_s": 1.0, "mm_s": 1e3, "m_s": 1e6}

QUANTITIES = {
    "viscosity": VISCOSITY,
    "pressure": PRESSURE,
    "density": DENSITY,
    "length": LENGTH,
    "shear_rate": SHEAR_RATE,
    "velocity": VELOCITY,
}
