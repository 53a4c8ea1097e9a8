"""The rules every case kind's inputs share (oocyte_fe.runner.schema) and the case-file checks."""

from __future__ import annotations

import json
import logging
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from pydantic import BaseModel, ConfigDict, Field

from oocyte_fe.errors import InputError
from oocyte_fe.kinds.afm_zp_cytoplasm import MAX_REDRAW_ROUNDS
from oocyte_fe.runner.casefile import load_case
from oocyte_fe.runner.registry import CaseContext, case_kind, kinds
from oocyte_fe.runner.schema import CaseInputs, unit_of
from oocyte_fe.runner.strict_json import strict_dumps

CASES = Path(__file__).resolve().parents[1] / "cases"


def _fields(model: type[BaseModel], prefix: str = ""):
    for name, info in model.model_fields.items():
        annotation = info.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            yield from _fields(annotation, f"{prefix}{name}.")
        yield f"{prefix}{name}", info


def test_every_input_has_a_description_and_numbers_a_unit() -> None:
    missing = []
    for kind in kinds().values():
        if not kind.module.startswith("oocyte_fe.kinds"):
            continue
        for name, info in _fields(kind.inputs):
            if not info.description:
                missing.append(f"{kind.name}: {name}: no description")
            text = str(info.annotation)
            numeric = ("float" in text or "int" in text) and "Literal" not in text
            if numeric and unit_of(info) is None and "BaseModel" not in text:
                missing.append(f"{kind.name}: {name}: no unit")
    assert not missing, "\n".join(missing)


def test_a_kind_must_use_the_strict_base() -> None:
    class Loose(BaseModel):
        model_config = ConfigDict(extra="forbid")
        x: float = Field(1.0, description="x", json_schema_extra={"unit": "1"})

    with pytest.raises(TypeError, match="CaseInputs"):
        case_kind("loose_for_test", inputs=Loose, metrics={})


def _copy(tmp_path: Path, name: str) -> Path:
    shutil.copytree(CASES / name, tmp_path / name)
    return tmp_path / name


def _edit(case: Path, old: str, new: str) -> None:
    text = (case / "case.toml").read_text()
    assert old in text, old
    (case / "case.toml").write_text(text.replace(old, new, 1))


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        ("timeout_s = 120", "timeout_s = true", "timeout_s"),
        ("timeout_s = 120", "timeout_s = inf", "timeout_s"),
        ("E0_kPa = 7.01", "E0_kPa = 1e400", "inputs.E0_kPa"),
        ("E0_kPa = 7.01", "E0_kPa = 1e308", "inputs.E0_kPa"),
        ("E0_kPa = 7.01", 'E0_kPa = "7.01"', "inputs.E0_kPa"),
        ("E0_kPa = 7.01", "E0_kPa = true", "inputs.E0_kPa"),
        ("per_decade = 4", "per_decade = 4.5", "inputs.per_decade"),
        ("prony_g = [0.3, 0.2]", "prony_g = [0.7, 0.6]", "inputs"),
        ("prony_g = [0.3, 0.2]", "prony_g = [0.3, nan]", "inputs.prony_g.1"),
        ("prony_tau_s = [0.2, 1.5]", "prony_tau_s = [0.2, -1.5]", "inputs.prony_tau_s.1"),
        ("seed = 7", "seed = -1", "inputs.seed"),
    ],
)
def test_strict_and_finite_inputs(tmp_path: Path, old: str, new: str, field: str) -> None:
    case = _copy(tmp_path, "afm_creep_prony")
    _edit(case, old, new)
    with pytest.raises(InputError) as info:
        load_case(case)
    assert info.value.file.endswith("case.toml")
    assert info.value.field == field, str(info.value)


@pytest.mark.parametrize(
    ("table", "text", "field"),
    [
        ("tolerances", "min = 2.0\nmax = 1.0", "tolerances.E0_kPa"),
        ("tolerances", "max = nan", "tolerances.E0_kPa.max"),
        ("tolerances", "rel = true", "tolerances.E0_kPa.rel"),
    ],
)
def test_impossible_tolerances(tmp_path: Path, table: str, text: str, field: str) -> None:
    case = _copy(tmp_path, "afm_creep_prony")
    raw = (case / "case.toml").read_text()
    start = raw.index("[tolerances.E0_kPa]")
    end = raw.index("\n[", start + 1) if "\n[" in raw[start + 1 :] else len(raw)
    raw = raw[:start] + f"[tolerances.E0_kPa]\n{text}\n" + raw[end:]
    (case / "case.toml").write_text(raw)
    with pytest.raises(InputError) as info:
        load_case(case)
    assert info.value.field.startswith(field), str(info.value)


def test_reference_must_be_finite(tmp_path: Path) -> None:
    case = _copy(tmp_path, "afm_creep_prony")
    raw = (case / "case.toml").read_text()
    start = raw.index("[reference.E0_kPa]")
    at = raw.index("value = ", start)
    end = raw.index("\n", at)
    (case / "case.toml").write_text(raw[:at] + "value = inf" + raw[end:])
    with pytest.raises(InputError, match=r"reference\.E0_kPa\.value: expected a finite"):
        load_case(case)


def test_zp_draws_that_cannot_pass_the_floor_are_refused_at_validation(tmp_path: Path) -> None:
    case = _copy(tmp_path, "afm_zp_cytoplasm")
    raw = (case / "case.toml").read_text()
    for key, value in (("min_E_kPa", "50.0"), ("E_zp_sd_kPa", "0.0")):
        at = raw.index(f"\n{key} = ") + 1
        raw = raw[:at] + f"{key} = {value}" + raw[raw.index("\n", at) :]
    (case / "case.toml").write_text(raw)
    with pytest.raises(InputError, match="min_E_kPa"):
        load_case(case)


def test_redraw_loop_is_bounded(tmp_path: Path) -> None:
    """A floor 2.99 SD above the mean passes validation (the 3 SD rule) but almost every draw
    falls below it: the run gives up after MAX_REDRAW_ROUNDS rounds (the message counts them; a
    time limit here would be a timed test), naming the floor and how many draws stayed below
    it."""
    case = _copy(tmp_path, "afm_zp_cytoplasm")
    raw = (case / "case.toml").read_text()
    for key, value in (
        ("E_zp_mean_kPa", "1.0"),
        ("E_zp_sd_kPa", "1.0"),
        ("E_cytoplasm_mean_kPa", "1.0"),
        ("E_cytoplasm_sd_kPa", "1.0"),
        ("min_E_kPa", "3.99"),
    ):
        at = raw.index(f"\n{key} = ") + 1
        raw = raw[:at] + f"{key} = {value}" + raw[raw.index("\n", at) :]
    (case / "case.toml").write_text(raw)
    loaded = load_case(case)
    ctx = CaseContext(
        loaded.name, loaded.directory, tmp_path / "out", loaded.inputs, False, logging.getLogger()
    )
    with pytest.raises(InputError) as err:
        loaded.kind.run(ctx)
    assert str(err.value) == (
        f"{case / 'case.toml'}: inputs.min_E_kPa: expected a floor most draws of N(1, 1) kPa "
        f"pass; {MAX_REDRAW_ROUNDS} redraw rounds left 13 of 60 below 3.99 kPa"
    )


def test_fit_pressures_must_be_in_the_table(tmp_path: Path) -> None:
    case = _copy(tmp_path, "microchannel_deformation")
    raw = (case / "case.toml").read_text()
    at = raw.index("fit_pressures_hPa = ")
    raw = raw[:at] + "fit_pressures_hPa = [1.2345, 2.0]" + raw[raw.index("\n", at) :]
    (case / "case.toml").write_text(raw)
    with pytest.raises(InputError, match="among the pressures of table4_deformation.csv"):
        load_case(case)


def test_a_copied_neck_case_fails_validation_and_material_files_work(tmp_path: Path) -> None:
    case = _copy(tmp_path, "fe_neck_aspiration")  # its ../afm_creep_prony is not there
    with pytest.raises(InputError, match=r"inputs\.material_case: .*zona_material_file"):
        load_case(case)
    for name in ("zp", "cytoplasm"):
        (case / f"material_{name}.toml").write_text(
            f'[material]\nname = "{name}"\nsource = "test"\nE_kPa = 7.0\nnu = 0.5\n'
        )
    _edit(
        case,
        'material_case = "../afm_creep_prony"',
        'zona_material_file = "material_zp.toml"\n'
        'cytoplasm_material_file = "material_cytoplasm.toml"',
    )
    loaded = load_case(case)
    assert loaded.inputs.zona_material_file.name == "material_zp.toml"
    (case / "material_zp.toml").write_text("[material]\nname = 1\n")
    with pytest.raises(InputError, match="material_zp.toml"):
        load_case(case)


def test_metrics_json_has_no_bare_nan() -> None:
    text = strict_dumps({"metrics": {"a": math.nan, "b": [1.0, math.inf]}, "n": np.float64(2)})
    data = json.loads(text, parse_constant=lambda c: pytest.fail(f"bare {c} in JSON"))
    assert data["metrics"] == {"a": None, "b": [1.0, None]}
    assert set(data["non_finite"]) == {"metrics.a", "metrics.b.1"}
    assert data["n"] == 2.0


def test_strict_base_reads_arrays_as_tuples() -> None:
    class Pair(CaseInputs):
        p: tuple[float, float] = Field(
            (0.0, 0.0), description="p", json_schema_extra={"unit": "um"}
        )

    assert Pair.model_validate({"p": [1, 2]}).p == (1.0, 2.0)


@pytest.mark.slow
def test_neck_case_runs_on_its_own_material_files(tmp_path: Path) -> None:
    case = _copy(tmp_path, "fe_neck_aspiration")
    for name, modulus in (("zp", 7.01), ("cytoplasm", 1.55)):
        (case / f"material_{name}.toml").write_text(
            f'[material]\nname = "{name}"\nsource = "test"\nE_kPa = {modulus}\nnu = 0.5\n'
        )
    _edit(
        case,
        'material_case = "../afm_creep_prony"',
        'zona_material_file = "material_zp.toml"\n'
        'cytoplasm_material_file = "material_cytoplasm.toml"',
    )
    loaded = load_case(case, quick=True)
    cheap = {"steps": 8, "size_um": 16.0, "mesh_study_sizes_um": [], "sensitivity": False}
    inputs = loaded.inputs.model_copy(update=cheap)
    out = tmp_path / "out"
    out.mkdir()
    ctx = CaseContext(loaded.name, case, out, inputs, True, logging.getLogger("neck"))
    outcome = loaded.kind.run(ctx)
    metrics = outcome.metrics
    assert not (out / "material").exists()  # no AFM case was re-run
    assert 0 < metrics["deformation_min_um"] <= metrics["deformation_max_um"] < 100
    # the report names the files the materials came from, not an AFM re-run
    [materials] = [text for title, text in outcome.sections if title == "Materials"]
    assert "`material_zp.toml` and `material_cytoplasm.toml`" in materials
    assert "regenerated" not in materials


def test_tolerance_given_as_text_is_refused(tmp_path: Path) -> None:
    case = _copy(tmp_path, "afm_creep_prony")
    _edit(case, "[tolerances.E0_kPa]\nrel = 0.02", '[tolerances.E0_kPa]\nrel = "0.02"')
    with pytest.raises(InputError, match=r"tolerances\.E0_kPa\.rel: expected a number"):
        load_case(case)


def test_library_argument_errors_inside_a_run_name_the_case_file(tmp_path: Path) -> None:
    """An input that passes validation but that a library refuses at run time (a cone half
    angle of 1e-4 deg: the test kind's schema asks > 0, afm's tip model (1e-3, 90) deg) is
    reported against ``case.toml: inputs``, never under the library's ``<input>`` placeholder."""
    import tests.kinds_for_tests  # noqa: F401  (registers test_echo)

    case = tmp_path / "echo"
    case.mkdir()
    (case / "case.toml").write_text(
        'kind = "test_echo"\ndescription = "d"\n[inputs]\nx_um = 1.0\ncone_half_angle_deg = 1e-4\n'
    )
    loaded = load_case(case)
    ctx = CaseContext(
        loaded.name, loaded.directory, tmp_path / "out", loaded.inputs, False, logging.getLogger()
    )
    with pytest.raises(InputError) as err:
        loaded.kind.run(ctx)
    assert str(err.value) == (
        f"{case / 'case.toml'}: inputs (passed on as argument 'half_angle_deg'): expected a "
        "value in (0.001, 90) deg, got 0.0001"
    )


def test_full_table_overrides_inputs_and_quick_overrides_both(tmp_path: Path) -> None:
    case = _copy(tmp_path, "fe_verification")
    assert load_case(case).inputs.hertz_fractions == [1.0, 0.5, 0.25]
    assert load_case(case, full=True).inputs.hertz_fractions == [0.5, 0.25, 0.125]
    both = load_case(case, quick=True, full=True)
    assert both.inputs.shell_size_um == 4.0  # [quick] over [full] over [inputs]
    assert both.full and both.quick
    assert both.raw_inputs["hertz_fractions"] == [1.0, 0.5, 0.25]


def test_bad_full_override_is_named_in_its_table_even_without_full(tmp_path: Path) -> None:
    case = _copy(tmp_path, "fe_verification")
    _edit(case, "hertz_fractions = [0.5, 0.25, 0.125]", "hertz_fractions = [0.5, -1.0]")
    with pytest.raises(InputError, match=r"full\.hertz_fractions"):
        load_case(case)
    _edit(case, "hertz_fractions = [0.5, -1.0]", "hertz_fraction = [0.5]")
    with pytest.raises(InputError, match=r"full\.hertz_fraction: .*did you mean 'hertz_fractions'"):
        load_case(case)


def test_old_full_flag_points_to_heavy(tmp_path: Path) -> None:
    case = _copy(tmp_path, "sweep_spindle_offset")
    _edit(case, "heavy = true", "full = true")
    with pytest.raises(InputError, match=r"full: .*heavy = true"):
        load_case(case)
