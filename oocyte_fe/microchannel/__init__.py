"""Microchannel flow of the culture medium and the oocyte (seed 001, Sections 2.4 and 3.3).

Modules, one idea each:

- :mod:`.viscosity` -- registry of generalized-Newtonian viscosity models, :class:`Rheology`
- :mod:`.rheology_fit` -- bounded log-space least-squares fits with uncertainty
- :mod:`.poiseuille` -- closed-form Newtonian and power-law pipe, slit and rectangular flow
- :mod:`.rabinowitsch` -- exact generalized-Newtonian pipe and slit flow (Rabinowitsch-Mooney)
- :mod:`.duct_fe` -- fully developed duct flow by finite elements (scikit-fem, P2, Newton)
- :mod:`.channel` -- Reynolds number, mean velocity and laminar check of the device
- :mod:`.junction_deformation` -- reduced model of the cell's deformation at the junction
- :mod:`.tables` -- reading the tables (units in column names); :mod:`.units` -- conversions
- :mod:`.plotting` -- figures (imported by the case kinds only)

Internal units: um, nN, kPa, s (viscosity kPa s, density nN s^2/um^4, velocity um/s).
"""
