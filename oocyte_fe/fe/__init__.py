"""The finite-strain FE core: kinematics, materials, forms, contact, loads and the solver.

Total-Lagrangian, two-dimensional (plane strain or axisymmetric), mixed displacement-pressure
(Taylor-Hood P2/P1, pressure discontinuous across material regions). Units: um, nN, kPa, s.
"""
