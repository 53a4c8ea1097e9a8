"""Three-phase VOF flow of the oocyte at the junction (seed 001, Model II) on OpenFOAM.

Modules, one idea each:

- :mod:`.rheology` -- the project's viscosity models as OpenFOAM kinematic coefficients, the cap
- :mod:`.geometry` -- planar block layouts (the Fig. 6 junction, a slit), disk sampling
- :mod:`.foamfile` -- writing OpenFOAM dictionaries and fields, reading fields
- :mod:`.casewriter` -- a complete ``multiphaseInterFoam`` case from Python
- :mod:`.monitor` -- progress and the silent failure modes from the solver log
- :mod:`.runner` -- finding OpenFOAM, meshing, running serial or with MPI
- :mod:`.post` -- axis ratio, centroid path and speed, phase volumes, snapshots

Internal units: um, nN, kPa, s; SI only in the files OpenFOAM reads and writes.
"""
