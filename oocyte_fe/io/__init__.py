"""Result files: VTU/PVD field series for ParaView and CSV time histories."""

from oocyte_fe.io.history_csv import write_history_csv
from oocyte_fe.io.vtu import FieldSeriesWriter

__all__ = ["FieldSeriesWriter", "write_history_csv"]
