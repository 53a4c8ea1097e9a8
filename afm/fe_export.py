"""A material's Prony series as input for other FE codes: ANSYS ``TB,PRONY`` and FEBio.

Both use the normalised relaxation of the material file, G(t)/G0 = a_inf + sum a_i exp(-t/tau_i)
with a_i = g_i and a_inf = 1 - sum g_i, on top of an elastic law with the instantaneous modulus
E0. Units are passed through: kPa and s here, so the FE model must use um (or any length) with
stress in kPa and time in s.

* ANSYS (APDL): ``MP,EX`` / ``MP,PRXY`` give E0 and nu; ``TB,PRONY,mat,,n,SHEAR`` with
  ``TBDATA,1,a1,tau1,a2,tau2,...`` the shear relaxation. No bulk relaxation is written (the bulk
  modulus stays elastic). nu = 0.5 needs a mixed u-P element formulation. The name and source
  go into ``!`` comment lines only; line breaks, other control characters, ``$`` (APDL's command
  separator) and non-ASCII characters in them are replaced by a space or ``?``, so they can
  never start a command.
* FEBio, nu < 0.5: a ``viscoelastic`` material wrapping a compressible ``neo-Hookean`` with E0
  and nu (FEBio's neo-Hookean needs nu < 0.5). Its relaxation G(t) = g0 + sum g_i exp(-t/t_i),
  g0 = 1 - sum g_i, at most six terms, acts on the whole elastic stress.
* FEBio, nu = 0.5: an ``uncoupled viscoelastic`` material wrapping an uncoupled
  ``Mooney-Rivlin`` with c1 = G0/2, c2 = 0 (small-strain shear modulus 2 (c1 + c2) = G0) and a
  bulk modulus ``k = bulk_ratio * G0`` (default 1000 G0, the volume stiffness of nu = 0.4995
  in small strain). The relaxation acts on the deviatoric stress only; the volumetric response
  stays elastic with k, as in the ANSYS block.

XML escaping: the name is an attribute value (``&``, ``<``, ``"`` and line breaks as character
references, so it parses back exactly); the source is a comment in which ``&`` and every ``-``
that would form ``--`` or end the comment, and carriage returns, are written as character
references (``&amp;``, ``&#45;``, ``&#13;``; comments hold
no entities, so ``html.unescape`` of the comment text gives the source back). Characters XML 1.0
cannot hold (control characters other than tab and line breaks) become U+FFFD.
"""

from __future__ import annotations

import math
import re
from xml.sax.saxutils import quoteattr

from afm.material_file import MaterialFile
from oocyte_fe.errors import InputError

FEBIO_MAX_TERMS = 6
INCOMPRESSIBLE_NU = 0.5
DEFAULT_BULK_RATIO = 1000.0
"""k / G0 written for an incompressible material (nu = 0.5) in FEBio."""

_XML_INVALID = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _apdl_comment(text: str) -> str:
    """``text`` safe inside one APDL ``!`` comment line (see the module docstring)."""
    ascii_text = text.encode("ascii", "replace").decode("ascii")
    return "".join(" " if (not ch.isprintable() or ch == "$") else ch for ch in ascii_text)


def _check_mat_id(mat_id: int) -> int:
    if isinstance(mat_id, bool) or not isinstance(mat_id, int) or mat_id < 1:
        raise InputError("<input>", "mat_id", "a positive integer material number", mat_id)
    return mat_id


def ansys_prony_block(material: MaterialFile, mat_id: int = 1) -> str:
    """APDL commands defining ``material`` as material ``mat_id`` (E0, nu, shear Prony)."""
    mat_id = _check_mat_id(mat_id)
    lines = [
        f"! {_apdl_comment(material.name)}: {_apdl_comment(material.source)}",
        "! units: kPa, s (E0 is the instantaneous modulus)",
        f"MP,EX,{mat_id},{material.E_kPa!r}",
        f"MP,PRXY,{mat_id},{material.nu!r}",
    ]
    if material.g:
        lines.append(f"TB,PRONY,{mat_id},,{len(material.g)},SHEAR")
        values = [v for pair in zip(material.g, material.tau_s, strict=True) for v in pair]
        # TBDATA takes at most six values per command
        for start in range(0, len(values), 6):
            chunk = ",".join(repr(v) for v in values[start : start + 6])
            lines.append(f"TBDATA,{start + 1},{chunk}")
    return "\n".join(lines) + "\n"


def xml_comment_text(text: str) -> str:
    """``text`` as the body of an XML comment, reversible by :func:`html.unescape`."""
    text = _XML_INVALID.sub("\ufffd", text).replace("&", "&amp;").replace("\r", "&#13;")
    return re.sub(r"-(?=-|$)", "&#45;", text)


def febio_material(
    material: MaterialFile, mat_id: int = 1, bulk_ratio: float = DEFAULT_BULK_RATIO
) -> str:
    """A FEBio ``<material>`` element for ``material`` (formulation by nu: module docstring)."""
    mat_id = _check_mat_id(mat_id)
    n = len(material.g)
    if n > FEBIO_MAX_TERMS:
        raise InputError(material.file, "prony.g", f"at most {FEBIO_MAX_TERMS} terms for FEBio", n)
    if not (isinstance(bulk_ratio, (int, float)) and math.isfinite(bulk_ratio) and bulk_ratio > 1):
        raise InputError("<input>", "bulk_ratio", "a finite bulk/shear ratio k/G0 > 1", bulk_ratio)
    incompressible = material.nu >= INCOMPRESSIBLE_NU
    kind = "uncoupled viscoelastic" if incompressible else "viscoelastic"
    name = quoteattr(_XML_INVALID.sub("\ufffd", material.name))
    lines = [
        f'<material id="{mat_id}" name={name} type="{kind}">',
        f"\t<!-- {xml_comment_text(material.source)}; units kPa, s -->",
        f"\t<g0>{1.0 - sum(material.g)!r}</g0>",
    ]
    for i, (g, tau) in enumerate(zip(material.g, material.tau_s, strict=True), start=1):
        lines.append(f"\t<g{i}>{g!r}</g{i}>")
        lines.append(f"\t<t{i}>{tau!r}</t{i}>")
    if incompressible:
        lines += [
            '\t<elastic type="Mooney-Rivlin">',
            f"\t\t<c1>{0.5 * material.G0_kPa!r}</c1>",
            "\t\t<c2>0.0</c2>",
            f"\t\t<k>{bulk_ratio * material.G0_kPa!r}</k>",
            "\t</elastic>",
        ]
    else:
        lines += [
            '\t<elastic type="neo-Hookean">',
            f"\t\t<E>{material.E_kPa!r}</E>",
            f"\t\t<v>{material.nu!r}</v>",
            "\t</elastic>",
        ]
    lines.append("</material>")
    return "\n".join(lines) + "\n"
