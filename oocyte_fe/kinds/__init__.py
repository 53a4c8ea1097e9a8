"""Built-in case kinds, one module each (``afm_*``, ``nmsd_*``, ``fe_*``, ``microchannel_*``).

Importing this package imports every module in it, and each module registers its kinds with
:func:`oocyte_fe.runner.registry.case_kind`. A kind module only validates inputs and calls the
plain library functions of ``afm``, ``nmsd`` or ``oocyte_fe``; physics lives there, report
writing in a report module (``nmsd_report`` here for the NMSD kinds). ``data_templates`` holds
what the data files look like, for ``oocyte-fe new``.
"""

import importlib
import pkgutil

for _module in pkgutil.iter_modules(__path__):
    importlib.import_module(f"{__name__}.{_module.name}")
