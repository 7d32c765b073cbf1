"""Fitting the contact laws to measured impacts (force-plate recordings).

:mod:`.recording` reads a recording and what it says before any fit (e, t_c, F_max,
delta_max, k_Hertz); :mod:`.fitting` fits every law by least squares (one recording, or one set
of physical parameters across several); :mod:`.plots` draws the results; :mod:`.synthetic`
makes recordings at known parameters and ships an example (:func:`example_recording`).
"""

from .recording import Measured, Recording, RecordingError, measure, read_recording
from .synthetic import example_recording, synthetic_recording

__all__ = ["Measured", "Recording", "RecordingError", "measure", "read_recording",
           "example_recording", "synthetic_recording"]
