"""A kind's inputs as text: ``oocyte-fe kinds KIND`` and the case folder of ``oocyte-fe new``.

Every input is read from the kind's pydantic model: its default (``required`` when it has
none), its description and its unit (``json_schema_extra={"unit": ...}``). A data-file input
(a ``Path``) gets a template file that the kind's reader accepts: ``json_schema_extra`` gives
its ``columns`` (the header), ``example_rows`` (one or two rows under it) and
``example_source`` (where the rows come from, or that they are synthetic), or, for a file that
is not a table, its ``suffix`` (e.g. ``".toml"``) and whole ``example_text``.
The new case has no ``[reference]``/``[tolerances]``: a user's case is judged only against
what its author declares.
"""

from __future__ import annotations

import json
import types
import typing
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from pathlib import Path
from typing import Any

import tomli_w
from pydantic import BaseModel
from pydantic.fields import FieldInfo

from oocyte_fe.errors import InputError
from oocyte_fe.runner.casefile import CASE_FILE, DEFAULT_TIMEOUT_S
from oocyte_fe.runner.registry import CaseKind


@dataclass(frozen=True)
class InputDoc:
    """One input as the user sees it."""

    name: str
    required: bool
    default: Any
    description: str
    unit: str
    is_file: bool
    columns: tuple[str, ...]
    template: str  # text of the data-file template ("" when the kind gives none)
    suffix: str  # of the data-file template
    source: str  # where the template's example comes from
    model: type[BaseModel] | None  # a nested table of inputs
    folder_files: dict[str, str] = dataclass_field(default_factory=dict)  # a folder's examples


def _extra(field: FieldInfo) -> dict[str, Any]:
    extra = field.json_schema_extra
    return extra if isinstance(extra, dict) else {}


def _types(annotation: Any) -> list[Any]:
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _types(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        return [t for a in typing.get_args(annotation) for t in _types(a)]
    return [annotation]


def _tables_by_name(model: type[BaseModel], name: str) -> bool:
    """Whether the input ``name`` of ``model`` maps names to tables (``dict[str, Model]``,
    a union of models too), not to values."""
    for kind in _types(model.model_fields[name].annotation):
        if typing.get_origin(kind) is dict:
            values = _types(typing.get_args(kind)[1])
            return any(isinstance(t, type) and issubclass(t, BaseModel) for t in values)
    return False


def _template_text(extra: dict[str, Any]) -> str:
    """A data-file template: ``example_text``, or the header and ``example_rows`` as CSV."""
    if "example_text" in extra:
        return str(extra["example_text"])
    columns = list(extra.get("columns", ()))
    if not columns:
        return ""
    rows = [",".join(columns)]
    rows += [",".join(str(v) for v in row) for row in extra.get("example_rows", ())]  # as given
    return "\n".join(rows) + "\n"


def input_docs(model: type[BaseModel]) -> list[InputDoc]:
    """The inputs of ``model`` in declaration order."""
    docs = []
    for name, field in model.model_fields.items():
        kinds = _types(field.annotation)
        nested = next((t for t in kinds if isinstance(t, type) and issubclass(t, BaseModel)), None)
        required = field.is_required()
        default = None if required else field.get_default(call_default_factory=True)
        extra = _extra(field)
        docs.append(
            InputDoc(
                name,
                required,
                default,
                field.description or "",
                str(extra.get("unit", "")),
                Path in kinds,
                tuple(extra.get("columns", ())),
                _template_text(extra),
                str(extra.get("suffix", ".csv")),
                str(extra.get("example_source", "")),
                nested,
                dict(extra.get("example_folder", {})),
            )
        )
    return docs


def _value_text(doc: InputDoc) -> str:
    if doc.required:
        return "required"
    if isinstance(doc.default, BaseModel):
        return "default: see below"
    return f"default {json.dumps(doc.default, default=str)}"


UNIT_SUFFIXES = {"um": "um", "s": "s", "deg": "deg", "Pa": "Pa", "kPa": "kPa", "nN": "nN"}
"""The unit of an input named ``..._<suffix>`` (the project's naming) where it gives none."""


def _named_tables(annotation: Any) -> list[tuple[type[BaseModel], str]]:
    """For tables by name whose members are chosen by ``type`` (``tools``, ``loads``): each
    member model and its ``type``; else nothing."""
    if typing.get_origin(annotation) is not dict:
        return []
    members = [
        t
        for t in _types(typing.get_args(annotation)[1])
        if isinstance(t, type) and issubclass(t, BaseModel)
    ]
    out = []
    for member in members:
        field = member.model_fields.get("type")
        tags = typing.get_args(field.annotation) if field is not None else ()
        if typing.get_origin(field.annotation if field else None) is typing.Literal and tags:
            out.append((member, str(tags[0])))
    return out if len(out) == len(members) else []


def describe_kind(kind: CaseKind) -> list[str]:
    """Lines for ``oocyte-fe kinds KIND``: every input and metric."""
    lines = [f"{kind.name}: {kind.description}", "", "inputs:"]

    def add(model: type[BaseModel], prefix: str, tag: str = "") -> None:
        for doc in input_docs(model):
            if tag and doc.name == "type":
                continue  # said in the member's heading
            named = doc.unit or UNIT_SUFFIXES.get(doc.name.rsplit("_", 1)[-1], "")
            unit = f" [{named}]" if named else ""
            text = f"  {prefix}{doc.name}{unit}: {doc.description or '(no description)'}"
            lines.append(f"{text} ({_value_text(doc)})")
            if doc.model is not None:
                add(doc.model, f"{prefix}{doc.name}.")
            for member, kind_of in _named_tables(model.model_fields[doc.name].annotation):
                lines.append(f"  {prefix}{doc.name}.NAME with type = {kind_of!r}:")
                add(member, f"{prefix}{doc.name}.NAME.", kind_of)

    add(kind.inputs, "")
    lines += ["", "metrics:"]
    lines += [f"  {name}: {desc}" for name, desc in kind.metrics.items()]
    return lines


def _toml_value(value: Any) -> str:
    """A value as inline TOML (tables inline, so one input stays on one line)."""
    if isinstance(value, BaseModel):
        value = value.model_dump(mode="json")
    if isinstance(value, dict):
        items = ", ".join(f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in value.items())
        return "{ " + items + " }" if items else "{}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int | float):
        return tomli_w.dumps({"x": value}).split("=", 1)[1].strip()
    return json.dumps(str(value))


def _comment(doc: InputDoc) -> str:
    unit = f" [{doc.unit}]" if doc.unit else ""
    return f"# {doc.description or doc.name}{unit}"


def _table(
    model: type[BaseModel], title: str, files: dict[str, InputDoc], values: dict | None = None
) -> list[str]:
    """``[title]`` with every input of ``model``; ``values`` (a default instance) fills in."""
    lines = [f"[{title}]"]
    nested = []
    for doc in input_docs(model):
        given = values is not None and doc.name in values
        default = values[doc.name] if given else doc.default
        if doc.model is not None and (doc.required or isinstance(default, BaseModel | dict)):
            nested.append((doc, default))
            continue
        if doc.description or doc.unit:
            lines.append(_comment(doc))
        if doc.folder_files:  # a folder input: example files written into it
            files[doc.name] = doc
            lines.append(f"# examples written in {doc.name}/: {doc.source}")
            lines.append(f'{doc.name} = "{doc.name}"   # replace with your folder')
        elif doc.is_file:
            files[doc.name] = doc
            if doc.source:
                lines.append(f"# template written beside this file; its rows: {doc.source}")
            entry = f'{doc.name} = "{doc.name}{doc.suffix}"'
            if not doc.required and default is None and not given:  # optional: off until set
                lines.append(f"# {entry}   # optional: uncomment to use (template beside)")
            else:
                lines.append(f"{entry}   # replace with your data")
        elif doc.required and not given:
            lines.append(f"# {doc.name} =    # REQUIRED: set a value")
        elif default is None:
            lines.append(f"# {doc.name} =    # optional, no default")
        elif isinstance(default, dict) and not default and _tables_by_name(model, doc.name):
            lines.append(f"# none by default; add them as [{title}.{doc.name}.NAME] tables")
        elif isinstance(default, dict) and not default:  # values by name: NAME = value
            lines.append(
                f"# none by default; write them here: {doc.name} = {{ NAME = value, ... }}"
            )
        else:
            lines.append(f"{doc.name} = {_toml_value(default)}")
    for doc, default in nested:
        sub = default.model_dump(mode="json") if isinstance(default, BaseModel) else default
        assert doc.model is not None
        lines += ["", _comment(doc), *_table(doc.model, f"{title}.{doc.name}", files, sub)]
    return lines


def new_case(kind: CaseKind, folder: Path, template: str | None = None) -> list[Path]:
    """Write a case folder for ``kind``: ``case.toml`` and a template per data file.

    With ``template`` (one of ``kind.templates``) the ``[inputs]`` are that ready experiment.
    Refuses a folder that already has a ``case.toml``. Returns the files written.
    """
    if (folder / CASE_FILE).exists():
        raise InputError(folder / CASE_FILE, "", "a new folder (this case exists; not overwritten)")
    if template is not None:
        return _new_from_template(kind, folder, template)
    files: dict[str, InputDoc] = {}
    lines = [
        f"# A {kind.name} case written by `oocyte-fe new`: edit the inputs, then",
        f"#   oocyte-fe validate {folder}   and   oocyte-fe run {folder}",
        "# Add [reference.METRIC] and [tolerances.METRIC] tables to judge metrics",
        "# (docs/cases.md); the metrics of this kind:",
        *[f"#   {name}: {desc}" for name, desc in kind.metrics.items()],
        *(
            [
                f"# Ready cases: oocyte-fe new {kind.name} DIR --template NAME, NAME one of "
                f"{', '.join(sorted(kind.templates))}"
            ]
            if kind.templates
            else []
        ),
        "",
        f'kind = "{kind.name}"',
        f'description = "My {kind.name} case"',
        f"timeout_s = {DEFAULT_TIMEOUT_S:g}",
        "",
        *_table(kind.inputs, "inputs", files),
        "",
        "[quick]",
        "# overrides of [inputs] for --quick (coarse settings)",
        "",
        "[full]",
        "# overrides of [inputs] for --full (fine meshes, long records)",
        "",
    ]
    written = [folder / CASE_FILE]
    _write(folder, written[0], "\n".join(lines))
    for name, doc in files.items():
        for file, text in doc.folder_files.items():
            path = folder / name / file
            _write(path.parent, path, text)
            written.append(path)
        if doc.folder_files:
            continue
        path = folder / f"{name}{doc.suffix}"
        if path.exists():
            continue
        # no comment lines: not every reader skips them (what the rows are is in case.toml)
        _write(folder, path, doc.template)
        written.append(path)
    return written


def _write(folder: Path, path: Path, text: str) -> None:
    """Write ``text`` to ``path`` in ``folder`` (made if missing); one line if it cannot be."""
    if folder.exists() and not folder.is_dir():
        raise InputError(folder, "FOLDER", "a folder for the new case, not a file")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    except OSError as exc:
        raise InputError(
            path, "FOLDER", "a folder the case can be written to", exc.strerror
        ) from None


def _new_from_template(kind: CaseKind, folder: Path, template: str | None) -> list[Path]:
    """``case.toml`` whose ``[inputs]`` is the kind's template ``template``."""
    names = ", ".join(sorted(kind.templates)) or "none for this kind"
    if template not in kind.templates:
        raise InputError("--template", "", f"one of the kind's templates ({names})", template)
    inputs = dict(kind.templates[template])
    description = str(inputs.pop("description", f"My {kind.name} case"))
    head = [
        f"# A {kind.name} case from the template {template!r} (`oocyte-fe new`): edit it, then",
        f"#   oocyte-fe validate {folder}   and   oocyte-fe run {folder}",
        f"# Templates of this kind: {names}. Metrics:",
        *[f"#   {name}: {desc}" for name, desc in kind.metrics.items()],
        "",
    ]
    body = {"kind": kind.name, "description": description, "timeout_s": DEFAULT_TIMEOUT_S}
    text = "\n".join(head) + tomli_w.dumps(body) + "\n" + tomli_w.dumps({"inputs": inputs})
    quick = {"mesh_scale": 2.0} if "mesh_scale" in kind.inputs.model_fields else {}
    text += "\n" + tomli_w.dumps({"quick": quick}) if quick else "\n[quick]\n"
    text += "# overrides of [inputs] for --quick (above) and --full (below)\n\n[full]\n"
    path = folder / CASE_FILE
    _write(folder, path, text)
    return [path]
