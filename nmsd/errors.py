"""The NMSD simulation's failure: a :class:`~oocyte_fe.errors.SolverError` with a suggestion.

Bad input is :class:`oocyte_fe.errors.InputError`, as everywhere in the project.
"""

from __future__ import annotations

from oocyte_fe.errors import SolverError


class NmsdDivergence(SolverError):
    """A simulation that blew up (NaN, energy growth, no Newton convergence).

    The message names the step, the time and a time step to try instead.
    """

    def __init__(self, step: int, time_s: float, reason: str, suggested_dt_s: float) -> None:
        self.step = step
        self.time_s = time_s
        self.suggested_dt_s = suggested_dt_s
        super().__init__(
            f"NMSD simulation diverged at step {step} (t = {time_s:.6g} s): {reason}; "
            f"try a time step of {suggested_dt_s:.3g} s or less"
        )
