"""The study's report: tables, figures and one HTML page.

:mod:`viscontact.study` computes; the modules here only read its results
(:mod:`.tables`, :mod:`.figures`, :mod:`.html`); :func:`reproduce` (in :mod:`.build`) ties
them together and writes the report directory atomically.
"""

from .build import DEFAULT_OUT, MARKER, ReportError, report_files, reproduce

__all__ = ["reproduce", "ReportError", "MARKER", "DEFAULT_OUT", "report_files"]
