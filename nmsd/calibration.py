"""Calibration of the NMSD constants to a force-displacement table (eqs 7-8 of seed 000).

Objective (eq 7): ``F(x) = sum_i (f_model(d_i) - f_exp(d_i))^2`` over the table's
displacements ``d_i`` (forces in nN). Constraints (eq 8): ``d0 >= 0``, ``d1 >= 0``,
``k2 >= 50 k1``. With the change of variables ``s = k1 / k2`` the constraints become simple
bounds (``0 <= s <= 1/50``, ``k2, d0, d1 >= 0``), solved by the bounded trust-region
least-squares of ``scipy.optimize.least_squares`` from several Latin-hypercube starts; the
best end point wins. A start whose first press diverges (too stiff or too lightly damped
for the press's steps) gives the trust region nothing to follow (a penalty residual with a
zero Jacobian): it is replaced by a draw of a further Latin hypercube, so that ``n_starts``
starts run (up to ``n_starts`` replacements; ``CalibrationResult.diverged_starts`` counts
them).

Reproducibility: the press's force jumps with the constants (snap-through events of the
lattice: a change of 0.1 % in d0 can change eq 7 several times over), and the trust region's
path on such a surface amplifies any change of the data, round-off included. The press is
therefore run only at free variables on a log10 grid (``resolution``, default 1e-3 decades):
a step proposal is rounded to the nearest grid point, so a change of the data that moves the
proposal by less than the grid spacing presses the same constants and ends at the same fit.
The press at given constants is itself that sensitive to its step ends and speed (the
snap-through moves with round-off of the time step); :func:`nmsd.press.simulate_press`
rounds them (1e-6 um, 6 significant digits).

Three model families (Section II.B.3):

- ``linear_msd``: linear links ``k1 dl`` (k2 = 0) and velocity damping d0 (d1 = 0);
- ``msd_d0``: the cubic-linear links of eqs 3-5 with velocity damping d0 only (d1 = 0);
- ``nmsd``: cubic-linear links and the full damping ``d0 + d1 |r - r0|`` of eq 6.

Optional extra free variables (``extra``), bounded: the critical strain ``dl_c`` (eqs 3-5,
0.05-2; the paper gives no value) and ``gap_um``, pipette travel before it touches the
lattice (0-20 um; e.g. the zona pellucida, which the lattice omits). Both are readings we
add, not constants the paper calibrates.

Jacobian (``jacobian="exact"``, the default): every residual evaluation runs the press with
forward sensitivities (:mod:`nmsd.sensitivity`), which give df/dp for k1, k2, d0, d1, dl_c
and the gap exactly; the chain rule to the free variables is

    df/dk2|_s = s df/dk1 + df/dk2,   df/ds = k2 df/dk1   (k1 = s k2),

and ``least_squares`` gets it as ``jac=`` (no extra press per Jacobian).
``jacobian="2-point"`` is the former forward-difference Jacobian (relative step 1e-3 or
two grid spacings, 1 + n_free presses per Jacobian). A press that diverges returns the
penalty residual and a zero Jacobian row block.

Fit measures over the n table points: ``RMSE = sqrt(mean((f_model - f_exp)^2))``,
``R^2 = 1 - SS_res / SS_tot`` and the similarity ``S = f_model . f_exp /
(|f_model| |f_exp|)`` (cosine of the angle between the two force vectors; 1 is a perfect
match up to scale; the paper stops its calibration at 0.999).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import qmc

from nmsd.errors import NmsdDivergence
from nmsd.identifiability import Identifiability, identifiability
from nmsd.parameters import NmsdParameters
from nmsd.press import PressSetup
from nmsd.tableII import ForceDisplacement
from oocyte_fe import checks
from oocyte_fe.errors import InputError

MODELS = ("linear_msd", "msd_d0", "nmsd")
K2_OVER_K1_MIN = 50.0
S_START_MAX = 1.0e4  # largest k1/k2 of the starts when eq 8's k2 >= 50 k1 is lifted

# search box of each free variable (log10 bounds of the starts, hard lower/upper bounds)
_START_BOX = {
    "k1": (1.0, 4.0),
    "k2": (2.0, 6.0),
    "d0": (-1.0, 2.5),
    "d1": (-3.0, 1.0),
    "dl_c": (-1.0, 0.3),
    "gap_um": (-0.3, 1.2),
}
_BOUNDS = {
    "k1": (0.0, np.inf),
    "k2": (0.0, np.inf),
    "d0": (0.0, np.inf),
    "d1": (0.0, np.inf),
    "dl_c": (0.05, 2.0),
    "gap_um": (0.0, 20.0),
}
_FREE = {"linear_msd": ("k1", "d0"), "msd_d0": ("k2", "s", "d0"), "nmsd": ("k2", "s", "d0", "d1")}
CONSTANTS = {
    "linear_msd": ("k1", "d0"),
    "msd_d0": ("k1", "k2", "d0"),
    "nmsd": ("k1", "k2", "d0", "d1"),
}
"""The constants each family fits (before ``extra``)."""
_PINS = {"k1": ("k1",), "k2": ("k1", "k2"), "s": ("k1",)}
"""Constants a free variable on its bound pins (k2 = 0 makes k1 = s k2 = 0 too)."""
EXTRA = ("dl_c", "gap_um")
JACOBIANS = ("exact", "2-point")


@dataclass(frozen=True)
class FitMetrics:
    """RMSE (nN), coefficient of determination R^2 and cosine similarity of a force curve."""

    rmse_nN: float
    r2: float
    similarity: float


@dataclass(frozen=True)
class StartEnd:
    """Where one start ended: RMSE over all fitted curves (nN), constants, gap (um or None)."""

    rmse_nN: float
    params: NmsdParameters
    gap_um: float | None = None


@dataclass(frozen=True)
class CalibrationResult:
    """Best constants, their fit, the model forces at the table points (nN) and the cost.

    ``metrics`` and ``force_nN`` are for the main curve; ``also_force_nN`` the model forces at
    the points of each further curve fitted with it (``calibrate(also=...)``);
    ``diverged_starts`` the starts whose first press diverged and were replaced; ``ends`` the
    end point of every start, best first: where eq 7 is flat, near-equal fits with other
    constants, whose predictions show how far the data pin them (:func:`near_best`).
    """

    model: str
    params: NmsdParameters
    metrics: FitMetrics
    force_nN: np.ndarray
    evaluations: int
    seconds: float
    success: bool
    message: str
    gap_um: float | None = None
    also_force_nN: tuple[np.ndarray, ...] = ()
    diverged_starts: int = 0
    ends: tuple[StartEnd, ...] = ()
    identifiability: Identifiability | None = None


def fit_metrics(model_nN: np.ndarray, measured_nN: np.ndarray) -> FitMetrics:
    """RMSE, R^2 and cosine similarity of model against measured forces."""
    model_nN, measured_nN = np.asarray(model_nN), np.asarray(measured_nN)
    residual = model_nN - measured_nN
    ss_tot = float(np.sum((measured_nN - measured_nN.mean()) ** 2))
    norm = float(np.linalg.norm(model_nN) * np.linalg.norm(measured_nN))
    return FitMetrics(
        float(np.sqrt(np.mean(residual**2))),
        1.0 - float(np.sum(residual**2)) / ss_tot,
        float(model_nN @ measured_nN) / norm if norm > 0 else 0.0,
    )


def params_for(
    model: str, values: np.ndarray, base: NmsdParameters, extra: tuple[str, ...] = ()
) -> NmsdParameters:
    """Constants of ``model`` from its free variables (see ``_FREE``, then ``extra``)."""
    v = {k: float(x) for k, x in zip(_FREE[model] + tuple(extra), values, strict=True)}
    if "dl_c" in v:
        base = base.with_values(dl_c=v["dl_c"])
    if model == "linear_msd":
        return base.with_values(k1=v["k1"], k2=0.0, d0=v["d0"], d1=0.0)
    k2 = v["k2"]
    return base.with_values(k1=v["s"] * k2, k2=k2, d0=v["d0"], d1=v.get("d1", 0.0))


def model_forces(setup: PressSetup, params: NmsdParameters, data: ForceDisplacement) -> np.ndarray:
    """Model force (nN) at the table displacements, the steps ending exactly on them."""
    return setup.run(params, record_um=data.displacement_um).force_at(data.displacement_um)


def model_forces_and_jacobian(
    setup: PressSetup,
    params: NmsdParameters,
    data: ForceDisplacement,
    model: str,
    extra: tuple[str, ...] = (),
) -> tuple[np.ndarray, np.ndarray]:
    """Model forces (nN) at the table points and their exact Jacobian (n_points, n_free).

    Columns follow the free variables of ``model`` then ``extra`` (as in :func:`params_for`;
    ``gap_um`` last), from one press with forward sensitivities and the chain rule
    ``df/dk2|_s = s df/dk1 + df/dk2``, ``df/ds = k2 df/dk1``.
    """
    d = data.displacement_um
    press = setup.run(params, record_um=d, sensitivities=True)
    sens = dict(zip(press.sensitivity_names, press.sensitivity_at(d).T, strict=True))
    columns = []
    for name in _FREE[model] + tuple(e for e in EXTRA if e in extra):
        if name == "k2":
            columns.append(sens["k2"] + params.k1 / params.k2 * sens["k1"])
        elif name == "s":
            columns.append(params.k2 * sens["k1"])
        else:
            columns.append(sens[name])
    return press.force_at(d), np.stack(columns, axis=1)


def calibrate(
    setup: PressSetup,
    data: ForceDisplacement,
    model: str = "nmsd",
    base: NmsdParameters | None = None,
    n_starts: int = 4,
    seed: int = 0,
    max_evaluations: int = 60,
    extra: tuple[str, ...] = (),
    jacobian: str = "exact",
    tolerance: float = 1e-3,
    k2_over_k1_min: float = K2_OVER_K1_MIN,
    resolution: float = 1e-3,
    also: Sequence[tuple[PressSetup, ForceDisplacement]] = (),
    on_press: Callable[[int, int], None] | None = None,
) -> CalibrationResult:
    """Minimise eq 7 under eq 8 for ``model`` from ``n_starts`` starts.

    ``base`` supplies the constants not fitted (dl_c, node mass, damping reading); ``extra``
    frees ``dl_c`` and/or ``gap_um`` (the latter moves the pipette start of ``setup``).
    ``jacobian``: ``"exact"`` (forward sensitivities, one press per evaluation) or
    ``"2-point"`` (forward differences, relative step 1e-3 or two grid spacings of
    ``resolution``, the larger). ``evaluations`` counts presses either way.
    ``tolerance``: ``ftol`` and ``xtol`` of ``least_squares`` (a start ends when a step
    changes the cost or the scaled variables by less than this fraction; 1e-3 reaches the
    RMSE of 1e-8 within 0.05 uN at half the presses; docs/nmsd.md, "Exact Jacobian").
    ``k2_over_k1_min``: the last constraint of eq 8, ``k2 >= k2_over_k1_min k1`` (50 in the
    paper; 0 lifts it: ``s = k1/k2`` is then bounded below only, its starts span 1e-5-1e4).
    ``resolution``: the press runs only at free variables on a log10 grid of this spacing
    (decades; 1e-3 = 0.23 %; 0: anywhere). Eq 7 jumps with the constants (snap-through
    events of the lattice, docs/nmsd.md "Reproducibility"), and on such a surface the trust
    region's path amplifies any change of the data; on the grid, a change of the data that
    moves the proposed step by less than the grid spacing presses the same constants, so the
    answer does not move with round-off of the data.
    ``also``: further presses and their curves (e.g. the same press at another speed) fitted
    together with the main one: eq 7 summed over all curves, one press per curve and
    evaluation (``evaluations`` counts presses).
    ``on_press(done, most)``: called after each evaluation with the presses so far and the
    most there can be (``n_starts x max_evaluations`` evaluations; a start may end sooner).
    """
    if jacobian not in JACOBIANS:
        raise InputError("calibrate", "jacobian", f"one of {JACOBIANS}", got=jacobian)
    if model not in MODELS:
        raise InputError("calibrate", "model", f"one of {', '.join(MODELS)}", got=model)
    if not set(extra) <= set(EXTRA) or len(set(extra)) < len(extra):
        raise InputError("calibrate", "extra", f"distinct names of {EXTRA}", got=extra)
    extra = tuple(e for e in EXTRA if e in extra)  # gap_um, if free, is the last variable
    n_starts = int(checks.number("calibrate", "n_starts", n_starts, ge=1, le=1000, integer=True))
    max_evaluations = int(
        checks.number(
            "calibrate", "max_evaluations", max_evaluations, ge=4, le=1_000_000, integer=True
        )
    )
    seed = int(checks.number("calibrate", "seed", seed, ge=0, integer=True))
    checks.number("calibrate", "tolerance", tolerance, gt=0, lt=1)
    checks.number("calibrate", "k2_over_k1_min", k2_over_k1_min, ge=0)
    checks.number("calibrate", "resolution", resolution, ge=0, le=0.1)
    if not 0 < tolerance < 1:
        raise InputError("calibrate", "tolerance", "in (0, 1)", got=tolerance)
    if not k2_over_k1_min >= 0:
        raise InputError("calibrate", "k2_over_k1_min", ">= 0 (eq 8: 50)", k2_over_k1_min)
    base = NmsdParameters() if base is None else base
    names = _FREE[model] + extra

    curves = [(setup, data), *also]
    for press, curve in curves:  # beyond its travel a press's force is held at the end value
        top = float(np.max(curve.displacement_um))
        if top > press.travel_um * (1 + 1e-9):
            raise InputError(
                curve.source or "calibrate",
                "displacement_um",
                f"displacements within the press travel ({press.travel_um:g} um)",
                got=top,
            )

    def press_for(values: np.ndarray, press: PressSetup) -> tuple[PressSetup, NmsdParameters]:
        params = params_for(model, values[: len(names) - ("gap_um" in extra)], base, extra_p)
        if "gap_um" in extra:
            return press.with_gap(float(values[-1])), params
        return press, params

    extra_p = tuple(e for e in extra if e != "gap_um")
    s_max = 1.0 / k2_over_k1_min if k2_over_k1_min > 0 else np.inf
    bounds = {**_BOUNDS, "s": (0.0, s_max)}
    start_box = {**_START_BOX, "s": (-5.0, np.log10(min(s_max, S_START_MAX)))}
    lower = np.array([bounds[n][0] for n in names])
    upper = np.array([bounds[n][1] for n in names])
    box = np.array([start_box[n] for n in names])

    def draws(generation: int) -> np.ndarray:
        rng = np.random.default_rng([seed, generation]) if generation else seed
        lhs = qmc.LatinHypercube(len(names), seed=rng)
        return 10.0 ** qmc.scale(lhs.random(n_starts), *box.T)

    starts, spares = list(draws(0)), list(draws(1))
    measured = np.concatenate([curve.force_nN for _, curve in curves])
    penalty = 10.0 * (np.abs(measured) + np.abs(measured).max())
    count = 0
    pressed: dict[bytes, tuple[np.ndarray, np.ndarray | None, bool]] = {}  # grid point -> press

    def on_grid(values: np.ndarray) -> np.ndarray:
        """The nearest point of the log10 grid (zero stays zero), within the bounds."""
        if resolution == 0:
            return values
        logs = np.log10(np.where(values > 0, values, 1.0))
        snapped = np.where(values > 0, 10.0 ** (np.round(logs / resolution) * resolution), 0.0)
        return np.clip(snapped, lower, upper)

    def press(values: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, bool]:
        """Residual, Jacobian (exact, or None for 2-point) and whether the press diverged."""
        nonlocal count
        values = on_grid(values)
        key = values.tobytes()
        if key in pressed:  # asked again, or a step that rounds to a grid point pressed before
            return pressed[key]
        count += len(curves)
        if on_press is not None:
            on_press(count, len(curves) * max_evaluations * n_starts)
        try:
            if jacobian == "2-point":
                forces = np.concatenate([model_forces(*press_for(values, p), c) for p, c in curves])
                jac = None
            else:
                parts = [
                    model_forces_and_jacobian(*press_for(values, p), c, model, extra)
                    for p, c in curves
                ]
                forces = np.concatenate([f for f, _ in parts])
                jac = np.vstack([j for _, j in parts])
            failed = False
        except NmsdDivergence:
            forces, jac = measured + penalty, np.zeros((len(measured), len(names)))
            failed = True
        pressed[key] = (forces - measured, jac, failed)
        return pressed[key]

    tic = time.perf_counter()
    best = None
    replaced = 0
    ends = []
    while starts:
        x0 = np.clip(starts.pop(0), lower, upper)
        if press(x0)[2] and spares:  # nothing to follow from here: draw another start
            starts.append(spares.pop(0))
            replaced += 1
            continue
        fit = least_squares(
            lambda v: press(v)[0].copy(),
            x0,
            jac="2-point" if jacobian == "2-point" else (lambda v: press(v)[1].copy()),
            bounds=(lower, upper),
            x_scale=x0,
            diff_step=max(1e-3, 10.0 ** (2.0 * resolution) - 1.0),  # two grid spacings
            ftol=tolerance,
            xtol=tolerance,
            max_nfev=max_evaluations,
        )
        rmse = float(np.sqrt(2.0 * fit.cost / len(measured)))
        fit.x = on_grid(fit.x)
        gap = float(fit.x[-1]) if "gap_um" in extra else None
        ends.append(StartEnd(rmse, press_for(fit.x, setup)[1], gap))
        if best is None or fit.cost < best.cost:
            best = fit
    params = press_for(best.x, setup)[1]
    forces = [model_forces(press_for(best.x, p)[0], params, c) for p, c in curves]
    x = best.x
    on_bound = np.isclose(x, lower, rtol=1e-6, atol=1e-12) | np.isclose(x, upper, rtol=1e-6)
    pinned = {c for n, b in zip(names, on_bound, strict=True) if b for c in _PINS.get(n, (n,))}
    ident = identifiability(
        [(press_for(x, p)[0], c) for p, c in curves],
        params,
        CONSTANTS[model] + extra,
        float(x[-1]) if "gap_um" in extra else 0.0,
        pinned,
    )
    return CalibrationResult(
        model,
        params,
        fit_metrics(forces[0], data.force_nN),
        forces[0],
        count + len(curves),
        time.perf_counter() - tic,
        bool(best.success),
        str(best.message),
        float(best.x[-1]) if "gap_um" in extra else None,
        tuple(forces[1:]),
        replaced,
        tuple(sorted(ends, key=lambda end: end.rmse_nN)),
        ident,
    )


def near_best(result: CalibrationResult, within: float = 0.1) -> list[StartEnd]:
    """The starts whose RMSE is within ``within`` (fraction) of the best one's, best first.

    Eq 7 cannot tell these fits apart at that level; a prediction made with each of them
    (a spindle path, a force at another speed) shows how far the calibration fixes it.
    """
    within = checks.number("near_best", "within", within, ge=0)
    best = result.ends[0].rmse_nN if result.ends else np.inf
    return [end for end in result.ends if end.rmse_nN <= (1.0 + within) * best]


def describe_starts(result: CalibrationResult) -> str:
    """One sentence on how the starts ended: RMSE range (uN), near-best count, replacements."""
    if not result.ends:
        return ""
    rmse = [end.rmse_nN * 1e-3 for end in result.ends]
    near = len(near_best(result, 0.1))
    return (
        f"{len(rmse)} starts ended at RMSE {rmse[0]:.3g}-{rmse[-1]:.3g} uN (all fitted curves), "
        f"{near} within 10 % of the best; {result.diverged_starts} replaced (first press "
        "diverged)."
    )
