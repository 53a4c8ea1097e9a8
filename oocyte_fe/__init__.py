"""oocyte-fe: layered finite-element models of oocytes, the case runner and its CLI.

Internal units everywhere in the code: micrometre (um), nanonewton (nN), kilopascal (kPa),
second (s). See ``docs/units.md``; files state their own units and are converted on reading.
"""

__version__ = "0.1.0"
