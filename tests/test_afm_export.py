"""FE exports of a material (afm/fe_export.py): FEBio XML that parses and FEBio accepts,
ANSYS blocks that hold only the intended commands whatever the name and source contain."""

from __future__ import annotations

import html
import os
import xml.etree.ElementTree as ET

import pytest

from afm.fe_export import ansys_prony_block, febio_material
from afm.material_file import MaterialFile, read_material
from oocyte_fe.errors import InputError

HOSTILE = [
    'zp & "cyto" <b>',
    "a -- b --> c -",
    "line one\nline two\r\n/EXIT",
    "x $ /CLEAR ! y",
    "tab\tand ünïcode",
]


def _parse(xml: str) -> tuple[ET.Element, str]:
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    root = ET.fromstring(xml, parser=parser)
    comments = [c.text for c in root if c.tag is ET.Comment]
    assert len(comments) == 1
    return root, comments[0]


@pytest.mark.parametrize("text", HOSTILE)
def test_febio_xml_parses_and_round_trips_name_and_source(text):
    material = MaterialFile(text, text + " source", 7.01, 0.45, (0.3,), (0.2,))
    root, comment = _parse(febio_material(material))
    assert root.get("name") == text
    assert html.unescape(comment.strip().removesuffix("; units kPa, s")) == text + " source"


def test_febio_incompressible_is_uncoupled_with_bulk_modulus():
    # nu = 0.5: FEBio's neo-Hookean rejects it, so the uncoupled Mooney-Rivlin is written
    material = MaterialFile("zp", "test", 7.5, 0.5, (0.3, 0.2), (0.2, 1.5))
    root, _ = _parse(febio_material(material, bulk_ratio=1000.0))
    assert root.get("type") == "uncoupled viscoelastic"
    elastic = root.find("elastic")
    assert elastic.get("type") == "Mooney-Rivlin"
    g0 = 7.5 / 3.0  # E / (2 (1 + nu))
    assert float(elastic.find("c1").text) == pytest.approx(g0 / 2, rel=1e-14)
    assert float(elastic.find("c2").text) == 0.0
    assert float(elastic.find("k").text) == pytest.approx(1000 * g0, rel=1e-14)
    assert root.find("elastic/v") is None
    assert float(root.find("g0").text) == pytest.approx(0.5, rel=1e-12)


def test_febio_compressible_keeps_neo_hookean_below_half():
    root, _ = _parse(febio_material(MaterialFile("zp", "", 7.0, 0.49)))
    assert root.get("type") == "viscoelastic"
    assert float(root.find("elastic/v").text) == 0.49 < 0.5


@pytest.mark.parametrize("text", HOSTILE)
def test_ansys_block_holds_only_the_intended_commands(text):
    material = MaterialFile(text, text, 7.01, 0.5, (0.3, 0.2), (0.2, 1.5))
    lines = ansys_prony_block(material, mat_id=3).splitlines()
    comments = [ln for ln in lines if ln.startswith("!")]
    commands = [ln for ln in lines if not ln.startswith("!")]
    assert len(comments) == 2
    assert all("$" not in ln and ln.isascii() and ln.isprintable() for ln in lines)
    assert commands == [
        "MP,EX,3,7.01",
        "MP,PRXY,3,0.5",
        "TB,PRONY,3,,2,SHEAR",
        "TBDATA,1,0.3,0.2,0.2,1.5",
    ]


@pytest.mark.parametrize("mat_id", [0, -1, 1.5, True])
def test_exports_refuse_a_bad_material_number(mat_id):
    material = MaterialFile("zp", "", 7.0, 0.45)
    for export in (ansys_prony_block, febio_material):
        with pytest.raises(InputError, match="mat_id"):
            export(material, mat_id=mat_id)


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        ("a = " + "[" * 2000 + "]" * 2000 + "\n", "nested less deeply"),
        ('[material]\nname = "z\xe9"\n'.encode("latin-1"), "UTF-8"),
        (None, "regular file"),
        ("fifo", "regular file"),
    ],
)
def test_read_material_refuses_hostile_files(tmp_path, content, expected):
    # issue 18: RecursionError, UnicodeDecodeError, IsADirectoryError, a hang on a FIFO
    path = tmp_path / "material.toml"
    if content is None:
        path.mkdir()
    elif content == "fifo":
        os.mkfifo(path)
    elif isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    with pytest.raises(InputError, match=expected) as info:
        read_material(path)
    assert str(path) in str(info.value)
