"""The layered cell's materials at run time: one type for every experiment and scenario.

``zona`` and ``cytoplasm`` are FE materials (:class:`~oocyte_fe.fe.material.Material`: E0
[kPa], nu, Prony terms); each names where it came from in its ``source`` (a material file of
the AFM route, a creep record, inline constants).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from oocyte_fe.fe.material import Material, Prony


@dataclass(frozen=True)
class LayerMaterials:
    """The ZP and the cytoplasm of a layered cell."""

    zona: Material
    cytoplasm: Material

    def stiffness_ratio(self, relaxed: bool) -> float:
        """``E_zp / E_cyto`` [-]: instantaneous (``E0`` of each layer) or relaxed
        (``E0 g_inf``, ``g_inf = 1 - sum g_i``, the modulus left after every Prony term has
        relaxed). The relaxed ratio is the one a Kelvin-Voigt lattice link reads: its spring
        carries the equilibrium stress and its dashpot the rate-dependent excess."""
        zona, cyto = self.zona, self.cytoplasm
        if relaxed:
            return zona.E_kPa * zona.prony.g_inf / (cyto.E_kPa * cyto.prony.g_inf)
        return zona.E_kPa / cyto.E_kPa

    def with_moduli(
        self, zona_E_kPa: float | None = None, cytoplasm_E_kPa: float | None = None
    ) -> LayerMaterials:
        """The same materials with the instantaneous moduli replaced where given (a sweep or a
        sensitivity over the AFM scatter); the Prony terms are kept."""
        zona = self.zona if zona_E_kPa is None else replace(self.zona, E_kPa=zona_E_kPa)
        cyto = self.cytoplasm
        if cytoplasm_E_kPa is not None:
            cyto = replace(cyto, E_kPa=cytoplasm_E_kPa)
        return LayerMaterials(zona, cyto)

    def regions(self, viscoelastic: bool = True, zona_E_kPa: float | None = None) -> dict:
        """``{"zona": ..., "cytoplasm": ...}``; ``viscoelastic=False`` drops the Prony terms
        (instantaneous moduli kept), ``zona_E_kPa`` replaces the ZP's instantaneous modulus."""
        zona, cyto = self.with_moduli(zona_E_kPa).zona, self.cytoplasm
        if not viscoelastic:
            zona, cyto = replace(zona, prony=Prony()), replace(cyto, prony=Prony())
        return {"zona": zona, "cytoplasm": cyto}
