"""``python -m oocyte_fe`` is the ``oocyte-fe`` command."""

from oocyte_fe.cli import main

main()
