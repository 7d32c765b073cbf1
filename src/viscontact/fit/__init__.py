"""Fitting the contact laws to measured impacts: force-plate recordings, and restitution
measured at several speeds (a table, bounce timings, a sound recording).

:mod:`.recording` reads a recording and what it says before any fit (e, t_c, F_max,
delta_max, k_Hertz); :mod:`.fitting` fits every law by least squares (one recording, or one set
of physical constants across several); :mod:`.plots` draws the results; :mod:`.synthetic`
makes recordings at known parameters and ships an example (:func:`example_recording`).
Imports the layers below it: physics, solvers, collision, calibration, paper, audit, _support.

    from viscontact.fit import example_recording, fit_laws, measure, read_recording
    m = measure(read_recording(example_recording()), mass=0.1547, v=1.7155)
    best = fit_laws(m)[0]          # LawFit: law, alpha +- alpha_err, c, tau, rms, ...

e(v): :mod:`.restitution` fits every law to (v, e) points and ranks them (AICc, leave-one-out);
:mod:`.bounces` reduces impact times to (v, e) (with air drag); :mod:`.audio` finds the impact
times in a recording; :mod:`.restitution_plots` draws them (docs/fit-restitution.md)::

    from viscontact.fit import fit_restitution, read_drops, reduce_bounces, drag_constant
    red = reduce_bounces(read_drops("drop.txt"), k_drag=drag_constant(2.7e-3, 0.02))
    fit = fit_restitution(red.data, rejected=red.rejected)
    print(fit.verdict, fit.ranking, fit.laws["KK"].alpha)
"""

from .fitting import FIT_LAWS, GlobalFit, LawFit, Weights, fit_global, fit_law, fit_laws
from .recording import Measured, Recording, RecordingError, measure, read_recording
from .synthetic import example_recording, synthetic_recording
from .audio import detect_impacts, read_audio
from .bounces import (drag_constant, flight_time, landing_speed, launch_speed, read_bounces,
                      read_drops, reduce_bounces)
from .restitution import (RES_LAWS, RestitutionData, RestitutionFit, RestitutionLawFit,
                          fit_restitution, fit_restitution_sets, model_e, read_restitution,
                          restitution_data)

__all__ = ["Measured", "Recording", "RecordingError", "measure", "read_recording",
           "example_recording", "synthetic_recording", "FIT_LAWS", "GlobalFit", "LawFit",
           "Weights", "fit_global", "fit_law", "fit_laws",
           "RES_LAWS", "RestitutionData", "RestitutionFit", "RestitutionLawFit",
           "fit_restitution", "fit_restitution_sets", "model_e", "read_restitution",
           "restitution_data", "read_bounces", "read_drops", "reduce_bounces", "drag_constant",
           "flight_time", "landing_speed", "launch_speed", "read_audio", "detect_impacts"]
