"""Error types of the ``nmsd`` package (it never imports ``oocyte_fe``)."""

from __future__ import annotations


class NmsdInputError(ValueError):
    """Bad input to the NMSD model: one line naming the source, the field and the expectation."""

    def __init__(self, source: str, field: str, expected: str, got: object | None = None) -> None:
        self.source = source
        self.field = field
        self.expected = expected
        self.got = got
        msg = f"{source}: {field}: expected {expected}"
        if got is not None:
            text = repr(got)
            msg += f", got {text if len(text) <= 80 else text[:76] + ' ...'}"
        super().__init__(" ".join(msg.splitlines()))


class NmsdDivergence(RuntimeError):
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
