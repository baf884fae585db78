"""The HTML report of a run: one self-contained file with the run's facts, tables and figures.

A run directory (``run.json`` plus figures, :mod:`rlff.report.run`) is written by ``rlff demo``
or by a script; :func:`build_report` turns it into HTML.
"""

from rlff.report.html import build_report, render_report
from rlff.report.run import FigureEntry, Run, Section, Table, read_run, write_run

__all__ = [
    "FigureEntry",
    "Run",
    "Section",
    "Table",
    "build_report",
    "read_run",
    "render_report",
    "write_run",
]
