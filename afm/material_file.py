"""The oocyte-fe material file (TOML): Young's modulus, Poisson ratio, normalised Prony series.

Format (units kPa, s; read by the FE core)::

    # oocyte-fe material file; units: kPa, s
    [material]
    name = "zona_pellucida"
    source = "..."          # where it came from
    E_kPa = 7.01            # instantaneous Young's modulus E0 = 2 (1 + nu) G0
    nu = 0.5
    [prony]                 # normalised relaxation: G(t)/G0 = 1 - sum g_i (1 - exp(-t/tau_i))
    g = [0.2, 0.1]
    tau_s = [0.1, 1.0]

``[prony]`` may be left out (or hold empty lists) for an elastic material. Validation
(:func:`material_constants`, the one check of a layer's constants: the FE description's inline
materials use it too): E in [1e-6, 1e9] kPa, 0 <= nu <= 0.5, every g_i in [0, 1) with sum g < 1
(a solid: G_inf > 0), tau_i in [1e-9, 1e9] s, as many g as tau, no unknown keys. Errors name
the file and the field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import tomli_w

from oocyte_fe import checks
from oocyte_fe.errors import InputError

HEADER = (
    "# oocyte-fe material file; units: kPa, s\n"
    "# E_kPa: instantaneous Young's modulus E0 = 2 (1 + nu) G0\n"
    "# [prony]: normalised relaxation G(t)/G0 = 1 - sum g_i (1 - exp(-t/tau_i))\n"
)
MAX_FILE_BYTES = 1_000_000
_MATERIAL_KEYS = {"name", "source", "E_kPa", "nu"}
_PRONY_KEYS = {"g", "tau_s"}
E_KPA_RANGE = checks.QUANTITIES["modulus_kPa"][:2]
"""Young's modulus of a layer [kPa]: the physical bounds of a modulus (1 mPa to 1 TPa)."""
NU_RANGE = (0.0, 0.5)
"""Poisson's ratio of a layer: 0 to 0.5 (incompressible); no auxetic cell."""
TAU_S_RANGE = checks.QUANTITIES["time_s"][:2]
"""Relaxation time of a Prony term [s]: the physical bounds of a time (1 ns to 30 years)."""


def material_constants(
    file: str | Path,
    E_kPa: object,
    nu: object,
    g: tuple[object, ...] | list[object] = (),
    tau_s: tuple[object, ...] | list[object] = (),
) -> tuple[float, float, tuple[float, ...], tuple[float, ...]]:
    """The constants of a layer checked (the one check of a material file and of an inline
    material in ``case.toml``): ``(E_kPa, nu, g, tau_s)`` as floats, or :class:`InputError`
    naming ``file`` and the field (``material.E_kPa``, ``material.nu``, ``prony.g``,
    ``prony.tau_s``)."""
    (e_lo, e_hi), (nu_lo, nu_hi), (t_lo, t_hi) = E_KPA_RANGE, NU_RANGE, TAU_S_RANGE
    e = _number(file, "material.E_kPa", E_kPa)
    if not e_lo <= e <= e_hi:
        raise InputError(
            file, "material.E_kPa", f"a value in [{e_lo:g}, {e_hi:g}] kPa (Young's modulus)", e
        )
    n = _number(file, "material.nu", nu)
    if not nu_lo <= n <= nu_hi:
        raise InputError(
            file, "material.nu", f"a value in [{nu_lo:g}, {nu_hi:g}] (Poisson's ratio)", n
        )
    gs = tuple(_number(file, "prony.g", v) for v in g)
    taus = tuple(_number(file, "prony.tau_s", v) for v in tau_s)
    if len(gs) != len(taus):
        raise InputError(file, "prony.tau_s", f"one tau per g ({len(gs)})", len(taus))
    if any(not 0 <= v < 1 for v in gs):
        raise InputError(file, "prony.g", "terms g_i in [0, 1)", list(gs))
    if not sum(gs) < 1.0:
        raise InputError(file, "prony.g", "terms summing to less than 1", sum(gs))
    if any(not t_lo <= v <= t_hi for v in taus):
        raise InputError(
            file, "prony.tau_s", f"relaxation times in [{t_lo:g}, {t_hi:g}] s", list(taus)
        )
    return e, n, gs, taus


@dataclass(frozen=True)
class MaterialFile:
    """A validated material record; ``file`` names where it came from (for errors)."""

    name: str
    source: str
    E_kPa: float
    nu: float
    g: tuple[float, ...] = ()
    tau_s: tuple[float, ...] = ()
    file: str = "<input>"

    def __post_init__(self) -> None:
        f = self.file
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f, "material.name", "a non-empty string", self.name)
        if not isinstance(self.source, str):
            raise InputError(f, "material.source", "a string", self.source)
        e, nu, g, tau = material_constants(f, self.E_kPa, self.nu, self.g, self.tau_s)
        object.__setattr__(self, "E_kPa", e)
        object.__setattr__(self, "nu", nu)
        object.__setattr__(self, "g", g)
        object.__setattr__(self, "tau_s", tau)

    @property
    def G0_kPa(self) -> float:
        """Instantaneous shear modulus E / (2 (1 + nu)), kPa."""
        return self.E_kPa / (2.0 * (1.0 + self.nu))

    def relaxation(self, t_s: float) -> float:
        """Normalised relaxation G(t)/G0 = 1 - sum g_i (1 - exp(-t/tau_i))."""
        pairs = zip(self.g, self.tau_s, strict=True)
        return 1.0 - sum(g * (1.0 - math.exp(-t_s / tau)) for g, tau in pairs)


def _number(file: str | Path, field: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(file, field, "a number", value)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(file, field, "a finite number", value)
    return value


def read_material(path: str | Path) -> MaterialFile:
    """Read and validate a material file; errors name the file and the field."""
    file = str(path)
    if checks.regular_file(path).stat().st_size > MAX_FILE_BYTES:  # no FIFO, no folder
        raise InputError(file, "", f"a material file under {MAX_FILE_BYTES} bytes")
    data = checks.read_toml(path)  # UTF-8 text, valid TOML: every fault one line
    unknown = sorted(set(data) - {"material", "prony"})
    if unknown:
        raise InputError(file, unknown[0], "only the tables [material] and [prony]")
    material = checks.toml_table(file, data, "material", _MATERIAL_KEYS)
    prony = checks.toml_table(file, data, "prony", _PRONY_KEYS, required=False)
    for key in ("name", "E_kPa", "nu"):
        if key not in material:
            raise InputError(file, f"material.{key}", "this key (it is required)")
    for key in ("g", "tau_s"):
        if not isinstance(prony.get(key, []), list):
            raise InputError(file, f"prony.{key}", "a list of numbers", prony[key])
    return MaterialFile(
        name=material["name"],
        source=material.get("source", ""),
        E_kPa=material["E_kPa"],
        nu=material["nu"],
        g=tuple(prony.get("g", [])),
        tau_s=tuple(prony.get("tau_s", [])),
        file=file,
    )


def material_toml(material: MaterialFile) -> str:
    """The material file's text (floats written at full precision, so reading is exact)."""
    body = {
        "material": {
            "name": material.name,
            "source": material.source,
            "E_kPa": material.E_kPa,
            "nu": material.nu,
        }
    }
    if material.g:
        body["prony"] = {"g": list(material.g), "tau_s": list(material.tau_s)}
    return HEADER + tomli_w.dumps(body)


def write_material(material: MaterialFile, path: str | Path) -> Path:
    """Write ``material`` to ``path`` (TOML, format in the module docstring)."""
    path = Path(path)
    path.write_text(material_toml(material))
    return path
