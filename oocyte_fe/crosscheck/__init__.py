"""NMSD reduced model against the layered plane-strain FE model: one pipette press (issue 9).

Modules: :mod:`~oocyte_fe.crosscheck.scenario` (geometry mapping, spindle, comparison grid),
:mod:`~oocyte_fe.crosscheck.zp_material` (AFM creep record -> FE materials),
:mod:`~oocyte_fe.crosscheck.fe_press` (the FE press), :mod:`~oocyte_fe.crosscheck.agreement`
(force and displacement agreement), :mod:`~oocyte_fe.crosscheck.plotting` (figures).
"""
