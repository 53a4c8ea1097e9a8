"""Contact point estimation.

Two methods; a fit reports which one it used:

``deviation``
    The last point where the baseline-corrected force is still within ``n_sigma`` noise
    standard deviations of zero, before the force stays above it to the end of the approach.
    Model-free and fast, biased late by the force needed to exceed the noise band.
``fit``
    The contact point is a parameter of the least-squares model fit (see :mod:`afm.fit`), started
    from the ``deviation`` estimate.
"""

from __future__ import annotations

import numpy as np

from oocyte_fe.errors import InputError

METHODS = ("fit", "deviation")


def deviation_index(
    force_nN: np.ndarray, noise_nN: float, n_sigma: float = 5.0, source: str = "<input>"
) -> int:
    """Index of the contact estimate: last point with F <= n_sigma * noise before F stays above.

    Raises :class:`InputError` when the curve never leaves the noise band (no contact),
    saying why: the threshold, and the largest force or the last point against it.
    """
    force = np.asarray(force_nN, dtype=float)
    span = float(np.ptp(force))
    threshold = max(n_sigma * noise_nN, 1e-9 * max(span, 1e-12))
    inside = force <= threshold
    if not np.isfinite(threshold) or not inside.any() or inside[-1] or span <= 2 * threshold:
        expected = (
            "a curve that reaches contact (force rising above the noise: above "
            f"{n_sigma:g} noise SDs = {threshold:.3g} nN to the end of the approach)"
        )
        if not np.isfinite(threshold):
            got = "a noise level that is not a number"
        elif not inside.any():
            got = "no point within the noise band (no baseline before contact)"
        elif inside[-1]:
            got = f"no contact: the last point is {force[-1]:.3g} nN (largest {force.max():.3g} nN)"
        else:
            got = f"no contact: force range {span:.3g} nN, within twice the threshold"
        raise InputError(source, "force_nN", expected, got)
    return int(np.flatnonzero(inside)[-1])


def check_method(method: str, source: str = "<input>") -> str:
    """Return ``method`` if it is a known contact-point method, else raise."""
    if not isinstance(method, str) or method not in METHODS:
        raise InputError(source, "contact_method", f"one of {', '.join(METHODS)}", method)
    return method
