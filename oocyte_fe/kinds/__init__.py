"""Built-in case kinds, one module each (``afm_*``, ``nmsd_*``, ``fe_*``, ``microchannel_*``).

Each module registers its kinds with :func:`oocyte_fe.runner.registry.case_kind` when it is
imported. The registry imports only the module named like a kind it is asked for (most kinds
have one module of their name), and every module (:func:`import_all`) when it needs the whole
list: a run of one case does not pay for importing the physics of all the others.

A kind module only validates inputs and calls the plain library functions of ``afm``,
``nmsd`` or ``oocyte_fe``; physics lives there, report writing in a report module
(``nmsd_report`` here for the NMSD kinds, ``afm_fit_files_report`` for ``afm_fit_files``), a
large inputs schema in its own ``*_inputs`` module. ``data_templates`` holds what the data
files look like, for ``oocyte-fe new``.
"""

import importlib
import pkgutil


def import_all() -> None:
    """Import every module of this package (each registers its kinds)."""
    for module in pkgutil.iter_modules(__path__):
        importlib.import_module(f"{__name__}.{module.name}")
