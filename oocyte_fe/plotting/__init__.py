"""Figures of FE results, rendered off-screen (no display needed)."""

from oocyte_fe.plotting.section import plot_section

__all__ = ["plot_section"]
