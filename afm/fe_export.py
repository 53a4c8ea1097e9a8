"""A material's Prony series as input for other FE codes: ANSYS ``TB,PRONY`` and FEBio.

Both use the normalised relaxation of the material file, G(t)/G0 = a_inf + sum a_i exp(-t/tau_i)
with a_i = g_i and a_inf = 1 - sum g_i, on top of an elastic law with the instantaneous modulus
E0. Units are passed through: kPa and s here, so the FE model must use um (or any length) with
stress in kPa and time in s.

* ANSYS (APDL): ``MP,EX`` / ``MP,PRXY`` give E0 and nu; ``TB,PRONY,mat,,n,SHEAR`` with
  ``TBDATA,1,a1,tau1,a2,tau2,...`` the shear relaxation. No bulk relaxation is written (the bulk
  modulus stays elastic). nu = 0.5 needs a mixed u-P element formulation.
* FEBio: a ``viscoelastic`` material wrapping a ``neo-Hookean`` elastic part with E0 and nu;
  its relaxation function is G(t) = g0 + sum g_i exp(-t/t_i) with g0 = 1 - sum g_i and at most
  six terms. FEBio's viscoelastic model relaxes the whole elastic stress (deviatoric and
  volumetric alike); a compressible neo-Hookean needs nu < 0.5, so lower nu (e.g. 0.49) or
  swap in an uncoupled material before running with nu = 0.5.
"""

from __future__ import annotations

from afm.errors import AfmInputError
from afm.material_file import MaterialFile

FEBIO_MAX_TERMS = 6


def ansys_prony_block(material: MaterialFile, mat_id: int = 1) -> str:
    """APDL commands defining ``material`` as material ``mat_id`` (E0, nu, shear Prony)."""
    lines = [
        f"! {material.name}: {material.source}",
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


def febio_material(material: MaterialFile, mat_id: int = 1) -> str:
    """A FEBio ``<material>`` element (viscoelastic around neo-Hookean) for ``material``."""
    n = len(material.g)
    if n > FEBIO_MAX_TERMS:
        raise AfmInputError(
            material.file, "prony.g", f"at most {FEBIO_MAX_TERMS} terms for FEBio", n
        )
    lines = [
        f'<material id="{mat_id}" name="{material.name}" type="viscoelastic">',
        f"\t<!-- {material.source}; units kPa, s -->",
        f"\t<g0>{1.0 - sum(material.g)!r}</g0>",
    ]
    for i, (g, tau) in enumerate(zip(material.g, material.tau_s, strict=True), start=1):
        lines.append(f"\t<g{i}>{g!r}</g{i}>")
        lines.append(f"\t<t{i}>{tau!r}</t{i}>")
    lines += [
        '\t<elastic type="neo-Hookean">',
        f"\t\t<E>{material.E_kPa!r}</E>",
        f"\t\t<v>{material.nu!r}</v>",
        "\t</elastic>",
        "</material>",
    ]
    return "\n".join(lines) + "\n"
