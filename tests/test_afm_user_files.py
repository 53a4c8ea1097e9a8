"""Curve tables as a lab writes them (outside tester 4): metres under an um column, a height
decreasing towards the sample, approach then retract in one file, a retract only, semicolons,
SI column names and no header.

Every curve is Sneddon's cone in closed form (E in kPa, delta in um, F in nN)::

    F = 2/pi E/(1 - nu^2) tan(alpha) delta^2,   delta = x - x0 >= 0
    piezo = x + F/k   (tip position x plus the cantilever deflection F/k)

with E = 7 kPa, nu = 0.5, alpha = 10 deg, k = 0.07 N/m = 70 nN/um and contact x0 = 5 um of
an 8 um tip travel, noise-free: the fit recovers E within 0.5 % and the contact within
10 nm (docs/afm.md: E to < 0.01 %, contact < 1 nm on noise-free curves).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from afm.batch import fit_batch, write_batch_table
from afm.curve_io import read_curve
from afm.fit import fit_indentation
from oocyte_fe.errors import InputError

E_KPA = 7.0
NU = 0.5
HALF_ANGLE_DEG = 10.0
K_N_PER_M = 0.07
CONTACT_UM = 5.0
TRAVEL_UM = 8.0
E_REL = 0.005
CONTACT_ABS_UM = 0.010


def _cone_curve(n: int = 1000) -> tuple[np.ndarray, np.ndarray]:
    """Piezo travel towards the sample [um] and force [nN] of the closed-form cone curve."""
    x = np.linspace(0.0, TRAVEL_UM, n)
    delta = np.clip(x - CONTACT_UM, 0.0, None)
    c = 2 / math.pi * E_KPA / (1 - NU**2) * math.tan(math.radians(HALF_ANGLE_DEG))
    force = c * delta**2
    return x + force / (1e3 * K_N_PER_M), force


def _table(path: Path, header: str, rows: list[str]) -> Path:
    path.write_text(f"# spring_constant_N_per_m = {K_N_PER_M}\n{header}\n" + "\n".join(rows))
    return path


def _csv(path: Path, header: str, a: np.ndarray, b: np.ndarray, sep: str = ",") -> Path:
    return _table(
        path, header, [f"{u!r}{sep}{v!r}" for u, v in zip(a.tolist(), b.tolist(), strict=True)]
    )


def _fit(path: Path):
    return fit_indentation(read_curve(path), "sneddon_cone", {"half_angle_deg": HALF_ANGLE_DEG})


def _assert_recovered(path: Path) -> None:
    fit = _fit(path)
    assert fit.E_kPa == pytest.approx(E_KPA, rel=E_REL)
    from_start = fit.contact_point_um - float(fit.tip_position_um[0])
    assert from_start == pytest.approx(CONTACT_UM, abs=CONTACT_ABS_UM)


# --- 1. a unit that no AFM force curve can have is refused, naming the unit it looks like ---


def test_metres_and_newtons_under_um_and_nN_columns_are_refused(tmp_path: Path) -> None:
    piezo, force = _cone_curve()
    path = _csv(tmp_path / "m.csv", "piezo_um,force_nN", piezo * 1e-6, force * 1e-9)
    with pytest.raises(InputError) as info:
        read_curve(path)
    message = str(info.value)
    assert message.startswith(f"{path}: piezo_um: expected an approach travel")
    travel = f"{np.ptp(piezo) * 1e-6:.3g} um"  # 8.13e-06 um: 8 um plus the deflection
    assert f"got 'an approach travel of {travel}: looks like metres" in message
    assert "\n" not in message


def test_newtons_under_a_nN_column_are_refused(tmp_path: Path) -> None:
    piezo, force = _cone_curve()
    path = _csv(tmp_path / "n.csv", "piezo_um,force_nN", piezo, force * 1e-9)
    with pytest.raises(InputError, match=r"force_nN: expected a force range.*looks like newtons"):
        read_curve(path)


def test_nanometres_under_an_um_column_are_refused(tmp_path: Path) -> None:
    piezo, force = _cone_curve()  # 8 um written as 8000 "um" = 8 mm of travel
    path = _csv(tmp_path / "nm.csv", "height_um,force_nN", piezo * 1e3, force)
    with pytest.raises(InputError, match=r"height_um: .*looks like nanometres"):
        read_curve(path)


# --- 2. a height decreasing towards the sample --------------------------------------------


def test_a_height_decreasing_towards_the_sample_is_fitted(tmp_path: Path) -> None:
    piezo, force = _cone_curve()
    path = _csv(tmp_path / "jpk.csv", "height_um,force_nN", 10.0 - piezo, force)
    _assert_recovered(path)


def test_contact_from_start_is_the_distance_along_the_approach_either_sign(
    tmp_path: Path,
) -> None:
    piezo, force = _cone_curve()
    folder = tmp_path / "curves"
    folder.mkdir()
    _csv(folder / "up.csv", "piezo_um,force_nN", piezo, force)
    _csv(folder / "down.csv", "height_um,force_nN", 10.0 - piezo, force)
    result = fit_batch(sorted(folder.glob("*.csv")))
    table = write_batch_table(result, tmp_path / "fits.csv")
    rows = list(csv.DictReader(table.open()))
    assert [r["error"] for r in rows] == ["", ""]
    for row in rows:
        assert float(row["E_kPa"]) == pytest.approx(E_KPA, rel=E_REL)
        assert float(row["contact_from_start_um"]) == pytest.approx(CONTACT_UM, abs=CONTACT_ABS_UM)


# --- 3. approach then retract is split at the turn; a retract only is refused --------------


def test_approach_then_retract_is_split_at_the_turn_and_the_approach_fitted(
    tmp_path: Path,
) -> None:
    piezo, force = _cone_curve()
    # the retract: back along the same path, 0.05 nN lower (hysteresis), both directions
    both = (np.concatenate([piezo, piezo[::-1]]), np.concatenate([force, force[::-1] - 0.05]))
    _assert_recovered(_csv(tmp_path / "ar.csv", "piezo_um,force_nN", *both))
    _assert_recovered(_csv(tmp_path / "ar_h.csv", "height_um,force_nN", 10.0 - both[0], both[1]))


def test_a_retract_only_is_refused_saying_so(tmp_path: Path) -> None:
    piezo, force = _cone_curve()
    path = _csv(tmp_path / "r.csv", "piezo_um,force_nN", piezo[::-1], force[::-1])
    with pytest.raises(
        InputError, match=r"piezo_um: .*a retract only.*falling to 0 nN at row 1000'$"
    ) as info:
        read_curve(path)
    assert "\n" not in str(info.value)


# --- 4. separators, SI columns and the header ----------------------------------------------


def test_semicolons_with_decimal_points_or_commas_are_read(tmp_path: Path) -> None:
    piezo, force = _cone_curve()
    _assert_recovered(_csv(tmp_path / "dot.csv", "piezo_um;force_nN", piezo, force, sep=";"))
    rows = [
        f"{u!r};{v!r}".replace(".", ",")
        for u, v in zip(piezo.tolist(), force.tolist(), strict=True)
    ]
    _assert_recovered(_table(tmp_path / "comma.csv", "piezo_um;force_nN", rows))


@pytest.mark.parametrize("header", ["height_m,force_N", "piezo_m,force_N"])
def test_metres_and_newtons_columns_are_converted(tmp_path: Path, header: str) -> None:
    piezo, force = _cone_curve()
    _assert_recovered(_csv(tmp_path / "si.csv", header, piezo * 1e-6, force * 1e-9))


@pytest.mark.parametrize(
    ("first_line", "rows_from"),
    [("0.0,0.0", 1), ("z,F", 0), ("height;force", 0)],
)
def test_a_table_without_a_unit_named_header_is_refused_showing_its_first_line(
    tmp_path: Path, first_line: str, rows_from: int
) -> None:
    piezo, force = _cone_curve()
    rows = [f"{u!r},{v!r}" for u, v in zip(piezo.tolist(), force.tolist(), strict=True)]
    path = _table(tmp_path / "h.csv", first_line, rows[rows_from:])
    with pytest.raises(InputError) as info:
        read_curve(path)
    message = str(info.value)
    assert message.startswith(f"{path}: header: expected a header row of unit-named columns")
    assert "piezo_um|" in message and "force_nN|" in message and repr(first_line) in message
    assert "afmformats" not in message


# --- 5. the viscoelastic route reads tables the same way (one reader for both) ---


def test_a_ramp_table_with_a_decreasing_height_is_the_same_ramp(tmp_path: Path) -> None:
    """A ramp in time (approach, then retract along the same path) written with a height
    that decreases towards the sample reads as the ramp with the piezo increasing: the same
    travel towards the sample to 1e-12 um, the turn at the farthest travel; metres under
    ``height_um`` are refused there too."""
    from afm.ramp_io import read_ramps

    piezo, force = _cone_curve(400)
    time = np.linspace(0.0, 2.0, 2 * piezo.size - 1)
    travel, load = np.r_[piezo, piezo[-2::-1]], np.r_[force, force[-2::-1]]

    def write(name: str, header: str, column: np.ndarray) -> Path:
        cells = zip(time.tolist(), column.tolist(), load.tolist(), strict=True)
        rows = [f"{t!r},{u!r},{v!r}" for t, u, v in cells]
        return _table(tmp_path / name, header, rows)

    [up] = read_ramps(write("up.csv", "time_s,piezo_um,force_nN", travel))
    [down] = read_ramps(write("down.csv", "time_s,height_um,force_nN", 10.0 - travel))
    assert down.n_approach == up.n_approach == piezo.size
    np.testing.assert_allclose(down.piezo_um - down.piezo_um[0], travel - travel[0], atol=1e-12)
    np.testing.assert_array_equal(down.force_nN, up.force_nN)
    metres = write("m.csv", "time_s,height_um,force_nN", (10.0 - travel) * 1e-6)
    with pytest.raises(InputError, match="height_um: expected an approach travel .* looks like"):
        read_ramps(metres)


# --- 6. a creep table's unit mistakes are refused the same way ---


def _creep_table(path: Path, force_nN: float, indentation_um: np.ndarray) -> Path:
    time = np.linspace(0.0, 5.0, 200)
    rows = [
        f"{t!r},{force_nN!r},{d!r}"
        for t, d in zip(time.tolist(), indentation_um.tolist(), strict=True)
    ]
    return _table(path, "time_s,force_nN,indentation_um", rows)


def test_a_creep_table_in_metres_or_newtons_is_refused(tmp_path: Path) -> None:
    """A clamp of 5 nN holding a cone at 2-3 um reads; the same hold written in metres under
    ``indentation_um`` (2e-6 um) or in newtons under ``force_nN`` (5e-9 nN) is refused, naming
    the column and the unit the values look like."""
    from afm.curve_io import read_creep

    depth = 2.0 + 1.0 * (1.0 - np.exp(-np.linspace(0.0, 5.0, 200)))
    assert read_creep(_creep_table(tmp_path / "ok.csv", 5.0, depth)).clamp_force_nN == 5.0
    with pytest.raises(
        InputError, match=r"indentation_um: expected an indentation .* looks like metres"
    ):
        read_creep(_creep_table(tmp_path / "m.csv", 5.0, depth * 1e-6))
    with pytest.raises(InputError, match=r"force_nN: expected a mean clamp force .* looks like"):
        read_creep(_creep_table(tmp_path / "n.csv", 5e-9, depth))


# --- swapped columns are named as such (outside tester 4) ---------------------------------


@pytest.mark.parametrize("noise_nN", [0.0, 0.05])
def test_swapped_columns_are_refused_saying_so(tmp_path: Path, noise_nN: float) -> None:
    """A travel in even steps (an instrument's piezo) written under force_nN and the force
    (with or without baseline noise) under piezo_um: refused naming both columns and
    'swapped' (before: "no contact" or a step back of the piezo); the same rows in their
    own columns are fitted (E within 0.5 %)."""
    z = np.linspace(0.0, TRAVEL_UM, 800)
    c = 2 / math.pi * E_KPA / (1 - NU**2) * math.tan(math.radians(HALF_ANGLE_DEG))
    k = 1e3 * K_N_PER_M  # nN/um
    travel = np.clip(z - CONTACT_UM, 0.0, None)
    delta = (-k + np.sqrt(k**2 + 4 * c * k * travel)) / (2 * c)  # d = z - z0 - F / k
    force = c * delta**2 + np.random.default_rng(3).normal(0.0, noise_nN, z.size)
    swapped = _csv(tmp_path / "swapped.csv", "piezo_um,force_nN", force, z)
    with pytest.raises(InputError) as err:
        read_curve(swapped)
    assert err.value.field == "piezo_um, force_nN"
    assert "columns that look swapped" in str(err.value)
    right = _fit(_csv(tmp_path / "right.csv", "piezo_um,force_nN", z, force))
    assert right.E_kPa == pytest.approx(E_KPA, rel=E_REL)
