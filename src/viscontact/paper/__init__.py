"""The seed study: Jian et al., Powder Technol. 356 (2019) 735, recomputed (imports physics,
solvers, collision, calibration and _support).

:mod:`.experiment`: the drop tests of lacrosse balls (the published measurements, calibrated
to each law); :mod:`.study`: every number behind the paper's tables and figures, computed once;
:mod:`.tables`, :mod:`.figures` and :mod:`.html` read those results; :mod:`.report`
(:func:`~viscontact.paper.report.reproduce`) writes them as one report directory.
"""
