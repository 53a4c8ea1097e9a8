"""Three-phase VOF flow of the oocyte at the junction (seed 001, Model II) on OpenFOAM.

Modules, one idea each:

- :mod:`.rheology` -- the project's viscosity models as OpenFOAM kinematic coefficients, the cap
- :mod:`.geometry` -- planar block layouts (the Fig. 6 junction, a slit), disk sampling
- :mod:`.foamfile` -- writing OpenFOAM dictionaries and fields, reading fields
- :mod:`.casewriter` -- a complete ``multiphaseInterFoam`` case from Python
- :mod:`.monitor` -- progress and the silent failure modes from the solver log
- :mod:`.runner` -- finding OpenFOAM, meshing, running serial or with MPI
- :mod:`.post` -- axis ratio, centroid path and speed, phase volumes, snapshots
- :mod:`.junction` -- the oocyte at the junction: set up, run and measure one pressure
- :mod:`.verification` -- single-phase slit flow against the closed forms
- :mod:`.drop` -- a two-phase drop in simple shear against the 2-D small-deformation result
- :mod:`.extrude` -- a planar layout extruded into a 3-D duct (timing runs)
- :mod:`.extrapolation` -- the step -> 0 limit and observed order from three solutions

Internal units: um, nN, kPa, s; SI only in the files OpenFOAM reads and writes.
"""
