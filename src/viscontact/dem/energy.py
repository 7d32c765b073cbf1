"""The energy of a DEM run read back: ``compute ID GROUP viscontact/energy`` and the balance.

The compute sums ``pair_style viscontact`` and every ``fix viscontact/wall`` over the group's
atoms and gives a global vector of 12 (and a per-atom array of the same 12 columns), in the
run's energy unit:

====  ==============================  ===========================================================
 col  name                            meaning
====  ==============================  ===========================================================
  1   ``dissipated``                  all energy dissipated so far (sum of 2-7), cumulative
  2   ``normal_damping``              work of the law's normal damping F_d = -eta_n v_n
  3   ``tangential_damping``          work of eta_t = XGAMMA eta_n on the slip velocity
  4   ``sliding_friction``            tangential spring energy removed by the Coulomb cap
  5   ``rolling``                     rolling sds: dashpot work + spring energy capped off
  6   ``twisting``                    twisting sds/marshall: dashpot + spring energy capped off
  7   ``adhesion_hysteresis``         JKR: the jump of the elastic energy at snap-in (delta = 0)
                                      and at pull-off (delta = -delta_c)
  8   ``elastic``                     elastic energy stored now (sum of 9-12)
  9   ``elastic_normal``              Hertz, DMT or JKR potential of the normal force
 10   ``elastic_tangential``          tangential spring (k_t |xi|^2 / 2; mindlin: the path
                                      integral of the spring force)
 11   ``elastic_rolling``             rolling spring KR |xi_R|^2 / 2
 12   ``elastic_twisting``            twisting spring k_tw xi_tw^2 / 2
====  ==============================  ===========================================================

A pair contact gives half its dissipation to each partner, a wall contact all to the atom, so
the global sum over all atoms is the total.  With these, kinetic + rotational + elastic +
dissipated + gravitational energy is constant up to the integrator's error (first order in dt
for the spring-dashpot-slider updates).  Plain ``tangential mindlin`` is not conservative:
k_t = 8 G* a grows with the contact radius at fixed displacement xi, so loading and unloading
at different overlaps do work that no spring energy stores; use ``mindlin_rescale`` (or
``linear_history``) for a closing balance.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from .io import Frame, read_log

__all__ = ["ENERGY_COLUMNS", "DISSIPATION_COLUMNS", "ELASTIC_COLUMNS", "energy_compute",
           "energy_thermo", "read_energy"]

#: the dissipation mechanisms (columns 2-7) and the elastic parts (columns 9-12)
DISSIPATION_COLUMNS = ("normal_damping", "tangential_damping", "sliding_friction", "rolling",
                       "twisting", "adhesion_hysteresis")
ELASTIC_COLUMNS = ("elastic_normal", "elastic_tangential", "elastic_rolling", "elastic_twisting")
#: the 12 columns of ``compute viscontact/energy``, in order
ENERGY_COLUMNS = ("dissipated", *DISSIPATION_COLUMNS, "elastic", *ELASTIC_COLUMNS)


def _check_id(compute_id: str) -> str:
    if not isinstance(compute_id, str) or not compute_id.replace("_", "").isalnum():
        raise ValueError(f"compute ID must be letters, digits and _, got {compute_id!r}")
    return compute_id


def energy_compute(compute_id: str = "vcenergy", group: str = "all") -> str:
    """The LAMMPS line ``compute ID GROUP viscontact/energy``."""
    return f"compute {_check_id(compute_id)} {_check_id(group)} viscontact/energy"


def energy_thermo(compute_id: str = "vcenergy") -> str:
    """The thermo_style words of the 12 columns: ``c_ID[1] ... c_ID[12]``."""
    cid = _check_id(compute_id)
    return " ".join(f"c_{cid}[{k}]" for k in range(1, len(ENERGY_COLUMNS) + 1))


def read_energy(source: "str | os.PathLike | Mapping[str, np.ndarray] | Frame",
                compute_id: str = "vcenergy") -> dict[str, np.ndarray]:
    """The 12 columns (:data:`ENERGY_COLUMNS` -> array) from a LAMMPS log (its last run;
    ``thermo_style custom ... c_ID[1] ... c_ID[12]``, :func:`energy_thermo`: one value per
    thermo row), from thermo columns already read (:func:`viscontact.dem.read_log`,
    ``RunResult.thermo``), or from a dump frame (:func:`viscontact.dem.read_dump`; ``dump ID G
    custom N FILE id ... c_ID[1] ... c_ID[12]``: the per-atom array, one value per atom).
    ValueError names the first column missing."""
    cid = _check_id(compute_id)
    if isinstance(source, Frame):
        thermo: Mapping[str, np.ndarray] = source.columns
    elif isinstance(source, Mapping):
        thermo = source
    else:
        thermo = read_log(source)
    out = {}
    for k, name in enumerate(ENERGY_COLUMNS, start=1):
        key = f"c_{cid}[{k}]"
        if key not in thermo:
            raise ValueError(f"no column {key} ({name}): add '{energy_compute(cid)}' and "
                             f"'{energy_thermo(cid)}' to thermo_style custom (or a custom dump)")
        out[name] = np.asarray(thermo[key], dtype=float)
    return out
