"""Fitting the contact laws to measured impacts (force-plate recordings).

:mod:`.recording` reads a recording and what it says before any fit (e, t_c, F_max,
delta_max, k_Hertz); :mod:`.fitting` fits every law by least squares (one recording, or one set
of physical constants across several); :mod:`.plots` draws the results; :mod:`.synthetic`
makes recordings at known parameters and ships an example (:func:`example_recording`).
Imports the layers below it: physics, solvers, collision, calibration, paper, audit, _support.

    from viscontact.fit import example_recording, fit_laws, measure, read_recording
    m = measure(read_recording(example_recording()), mass=0.1547, v=1.7155)
    best = fit_laws(m)[0]          # LawFit: law, alpha +- alpha_err, c, tau, rms, ...
"""

from .fitting import FIT_LAWS, GlobalFit, LawFit, Weights, fit_global, fit_law, fit_laws
from .recording import Measured, Recording, RecordingError, measure, read_recording
from .synthetic import example_recording, synthetic_recording

__all__ = ["Measured", "Recording", "RecordingError", "measure", "read_recording",
           "example_recording", "synthetic_recording", "FIT_LAWS", "GlobalFit", "LawFit",
           "Weights", "fit_global", "fit_law", "fit_laws"]
