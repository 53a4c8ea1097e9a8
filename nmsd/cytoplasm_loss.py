"""Cytoplasm lost with the spindle (Section III.D of seed 000).

The paper: removed volume = a cylinder of the removal pipette's inner diameter ``d`` over
the aspirated length ``L``; total = the oocyte without zona pellucida as a sphere of
diameter ``D``:

    loss = (pi d^2 L / 4) / (pi D^3 / 6)                               (3D, as printed)

The same reading in the focal plane (rectangle ``d L`` over the disc ``pi D^2 / 4``) is
given alongside, since the printed percentages imply aspirated lengths longer than the cell
in 3D (see :func:`aspirated_length_for`). Lengths um, fractions dimensionless.
"""

from __future__ import annotations

import numpy as np

from oocyte_fe import checks


def loss_fraction(
    length_um: float | np.ndarray, pipette_um: float, cell_um: float, plane: bool = False
) -> np.ndarray:
    """Fraction of the cell volume (or focal-plane area if ``plane``) aspirated.

    Lengths within the physical bounds of ``checks.QUANTITIES["length_um"]`` (the aspirated
    length may be 0); anything else is an :class:`InputError` naming the argument.
    """
    low, high, _ = checks.QUANTITIES["length_um"]
    length = checks.numbers_array("loss_fraction", "length_um", length_um, ge=0, le=high)
    pipette_um = checks.quantity("loss_fraction", "pipette_um", pipette_um, "length_um")
    cell_um = checks.quantity("loss_fraction", "cell_um", cell_um, "length_um")
    if plane:
        return pipette_um * length / (np.pi * cell_um**2 / 4)
    return (np.pi * pipette_um**2 / 4 * length) / (np.pi * cell_um**3 / 6)


def aspirated_length_for(
    fraction: float, pipette_um: float, cell_um: float, plane: bool = False
) -> float:
    """Aspirated length (um) that gives ``fraction`` (inverse of :func:`loss_fraction`)."""
    fraction = checks.number("aspirated_length_for", "fraction", fraction, ge=0, le=1)
    return float(fraction / loss_fraction(1.0, pipette_um, cell_um, plane))
