"""Collision solvers behind one contract.

A solver is a function ``solve(lp, alpha, end, *, rtol, detail) -> Contact`` (see
:mod:`viscontact.solvers.base`).  Solvers know nothing about law names: they receive
the resolved numbers (p, beta, m) and call the kernels.  ``SOLVERS`` lists them; the
public API picks one by name, so a faster solver drops in without touching callers.
"""

from __future__ import annotations

from .base import Contact, SolveFn, END_CRITERIA, T_MAX, DEFAULT_RTOL
from .batch import BATCH_RTOL, BatchResult, solve_batch, solve_batch_one
from .reference import solve_reference

#: ``reference``: scipy DOP853, histories, one collision per call.  ``batch``: compiled,
#: many collisions per call (:func:`solve_batch`), no histories.
SOLVERS: dict[str, SolveFn] = {"reference": solve_reference, "batch": solve_batch_one}

__all__ = [
    "Contact", "SolveFn", "SOLVERS", "END_CRITERIA", "T_MAX", "DEFAULT_RTOL", "BATCH_RTOL",
    "BatchResult", "solve_batch",
]
