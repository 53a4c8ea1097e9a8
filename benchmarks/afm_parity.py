"""Parity with nanite on real instrument files: E and contact point, file by file.

Usage: python benchmarks/afm_parity.py [data_folder]

``data_folder`` defaults to afmformats 0.18.7's ``tests/data`` (downloaded once into
``~/.cache/oocyte-fe/``, see ``tests/instrument_data.py``). Every force-distance curve afmformats
reads there (all curves of force maps) is fitted by both tools from the same file, with
nanite's default preprocessing on its side (``compute_tip_position``, ``correct_force_offset``,
``correct_tip_offset``; ``correct_split_approach_retract`` added for files that store approach
and retract as one segment), its fit (lmfit, free baseline offset, contact-point weight
``weight_cp``) over the whole approach; on our side ``read_curves`` (height channel chosen as
nanite does) and ``fit_indentation`` (baseline line removed, contact point free) over the
whole approach. Models: Sneddon cone 30 deg, Hertz paraboloid R = 10 um, three-sided pyramid
25 deg (nanite's only pyramid, ``hertz_pyr3s``; ours ``pyramid_3s``); nu 0.5. The four-sided
pyramid (``pyramid``) is the same delta^2 law with another constant (0.7453 for 0.8887), so its E
is the three-sided one times 0.8887 / 0.7453 exactly: it is not a separate row of the table.

Files without the spring constant or sensitivity are read with the values afmformats' own
tests pass for them (:data:`METADATA`). Prints a table: file, curve, model, E ours, E nanite,
difference, contact point difference; then this package's default analysis
(``fit_indentation``, same model, whole approach) against nanite with and without its
contact-point weighting (``weight_cp = 0``), and the default fit's quality or error.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from afm.curve_io import read_curves
from afm.fit import fit_indentation
from afm.nanite_pipeline import fit_nanite_default
from oocyte_fe.errors import InputError

MODELS = {
    # ours: (nanite key, our geometry, nanite geometry parameter and value)
    "sneddon_cone": ("hertz_cone", {"half_angle_deg": 30.0}, ("alpha", 30.0)),
    "hertz_paraboloid": ("hertz_para", {"radius_um": 10.0}, ("R", 10e-6)),
    "pyramid_3s": ("hertz_pyr3s", {"face_angle_deg": 25.0}, ("alpha", 25.0)),
}

METADATA = {
    # file name prefix: (spring constant N/m, sensitivity nm/V) as in afmformats' tests
    "fmt-afm-workshop-fd": (20.0, 10.0),
    "fmt-ntmdt-txt-fd": (0.055, 61e9),
    "fmt-jpk-fd_single-modified": (12.0, None),
}

NANITE_WEIGHT_CP_M = 1e-6  # nanite's FP_DEFAULT weight_cp (m)


@dataclass(frozen=True)
class ParityRow:
    file: str
    curve: int
    model: str
    E_ours_kPa: float
    E_nanite_kPa: float
    contact_diff_nm: float
    E_default_kPa: float = np.nan
    note: str = ""
    E_nanite_unweighted_kPa: float = np.nan
    default_quality: str = ""

    @property
    def difference(self) -> float:
        return self.E_ours_kPa / self.E_nanite_kPa - 1.0

    @property
    def default_difference(self) -> float:
        """fit_indentation's E against nanite's (weighted, its default)."""
        return self.E_default_kPa / self.E_nanite_kPa - 1.0

    @property
    def default_unweighted_difference(self) -> float:
        """fit_indentation's E against nanite's without contact-point weighting."""
        return self.E_default_kPa / self.E_nanite_unweighted_kPa - 1.0


def metadata_for(path: Path) -> tuple[float | None, float | None]:
    for prefix, values in METADATA.items():
        if path.name.startswith(prefix):
            return values
    return None, None


def nanite_fit(
    idnt, model: str, weight_cp_m: float = NANITE_WEIGHT_CP_M
) -> tuple[float, float, float]:
    """nanite's E [kPa], contact point [um] and baseline [nN].

    ``weight_cp_m = 0`` switches nanite's contact-point weighting off.

    The contact point is in nanite's tip position, turned to our sign (increasing towards the
    sample).
    """
    key, _, (gname, gvalue) = MODELS[model]
    params = idnt.get_initial_fit_parameters(model_key=key)
    for param in params.values():  # float32 columns (HDF5) give float32 values nanite can't hash
        param.set(value=float(param.value))
    params[gname].set(gvalue)
    params["nu"].set(0.5)
    idnt.fit_model(
        model_key=key,
        params_initial=params,
        range_type="absolute",
        range_x=(0, 0),
        weight_cp=weight_cp_m,
    )
    fitted = idnt.fit_properties["params_fitted"]
    e = fitted["E"].value * 1e-3
    return e, -fitted["contact_point"].value * 1e6, fitted["baseline"].value * 1e9


def nanite_records(path: Path):
    import nanite

    k, s = metadata_for(path)
    override = {}
    if k is not None:
        override["spring constant"] = k
    if s is not None:
        override["sensitivity"] = s * 1e-9
    return nanite.load_group(path, meta_override=override)


def _reverses(idnt) -> bool:
    z = -np.asarray(idnt.appr["height (measured)"])
    return float((np.maximum.accumulate(z) - z).max()) > 0.02 * float(np.ptp(z))


def parity_rows(path: Path, models: tuple[str, ...] = tuple(MODELS)) -> list[ParityRow]:
    """Both tools on every force-distance curve of ``path`` (module docstring)."""
    k, s = metadata_for(path)
    try:
        curves = read_curves(path, spring_constant_N_per_m=k, sensitivity_nm_per_V=s)
    except InputError as exc:
        return [ParityRow(path.name, -1, "-", np.nan, np.nan, np.nan, np.nan, f"not read: {exc}")]
    group = nanite_records(path)
    rows = []
    for i, (curve, idnt) in enumerate(zip(curves, group, strict=True)):
        steps = ["compute_tip_position", "correct_force_offset", "correct_tip_offset"]
        if _reverses(idnt):
            steps.insert(1, "correct_split_approach_retract")
        idnt.apply_preprocessing(steps)
        # nanite: tip = piezo - F_raw/k - C (C its contact shift), force offset subtracted
        k_um = curve.spring_constant_nN_per_um
        f_raw0 = float(curve.force_nN[0])
        shift = float(curve.piezo_um[0]) - f_raw0 / k_um + float(idnt["tip position"][0]) * 1e6
        offset = f_raw0 - float(idnt["force"][0]) * 1e9
        # nanite clips the whole record (approach and retract) at its largest force
        n_max = int(np.argmax(idnt["force"]))
        for model in models:
            _, geometry, _ = MODELS[model]
            note = ""
            try:
                ours = fit_nanite_default(curve, model, geometry, 0.5, n_max=n_max)
                # piezo travel at contact: there the force is the fitted baseline
                e_ours, z_ours = ours.E_kPa, ours.contact_point_um + ours.offset_nN / k_um
            except InputError as exc:
                e_ours, z_ours, note = np.nan, np.nan, str(exc)
            try:
                default = fit_indentation(curve, model, geometry, 0.5)
                e_default, quality = default.E_kPa, default.quality
            except InputError as exc:
                e_default, quality = np.nan, f"error: {exc.field}: {exc.expected}"
            e_unweighted = nanite_fit(idnt, model, weight_cp_m=0.0)[0]
            e_nan, x0_nan, baseline = nanite_fit(idnt, model)
            z_nan = x0_nan + shift + (offset + baseline) / k_um
            rows.append(
                ParityRow(
                    path.name,
                    i,
                    model,
                    e_ours,
                    e_nan,
                    (z_ours - z_nan) * 1e3,
                    e_default,
                    note,
                    e_unweighted,
                    quality,
                )
            )
    return rows


def main(folder: str | None = None) -> None:
    if folder is None:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
        from tests.instrument_data import afmformats_data

        data = afmformats_data()
        if data is None:
            print("afmformats test data not available (no download possible)")
            return
    else:
        data = Path(folder)
    warnings.simplefilter("ignore")
    print(
        f"{'file':58s} {'curve':>5s} {'model':17s} {'E ours':>10s} {'E nanite':>10s} "
        f"{'diff':>8s} {'x0 diff nm':>10s} {'E default':>10s} {'vs nanite':>9s} "
        f"{'E nanite w=0':>12s} {'vs w=0':>8s}  default quality"
    )
    compared = []
    for path in sorted(data.iterdir()):
        if "-fd" not in path.name:
            continue
        for r in parity_rows(path):
            if np.isfinite(r.difference):
                compared.append(r)
            print(
                f"{r.file[:58]:58s} {r.curve:5d} {r.model:17s} {r.E_ours_kPa:10.4g} "
                f"{r.E_nanite_kPa:10.4g} {r.difference:8.2%} {r.contact_diff_nm:10.2f} "
                f"{r.E_default_kPa:10.4g} {r.default_difference:9.1%} "
                f"{r.E_nanite_unweighted_kPa:12.4g} {r.default_unweighted_difference:8.1%}  "
                f"{r.default_quality[:70]} {r.note[:60]}"
            )
    if compared:
        d_e = max(abs(r.difference) for r in compared)
        within = sum(abs(r.contact_diff_nm) < 10.0 for r in compared)
        d_x = max(abs(r.contact_diff_nm) for r in compared)
        print(
            f"\n{len(compared)} fits: max |dE| {d_e:.2%} (goal 1 %), contact point within 10 nm "
            f"on {within} of {len(compared)} (max {d_x:.2f} nm)"
        )


if __name__ == "__main__":
    main(*sys.argv[1:2])
