"""Collision solvers behind one contract (imports physics and
_support only).

A solver is a function ``solve(lp, alpha, end, *, rtol, detail) -> Contact`` (see
:mod:`viscontact.solvers.base`).  Solvers know nothing about law names: they receive the
resolved numbers (p, beta, m) and call the kernels of :mod:`viscontact.physics.kernels`.
``SOLVERS`` lists them; the public API picks one by name, so a faster solver drops in without
touching callers.  ``reference`` (:mod:`.reference`): scipy DOP853 with histories, one
collision per call.  ``batch`` (:mod:`.batch`): compiled, many collisions per call, no
histories.  Each entry imports its module on its first call, so a caller of one solver does not
load the other's scipy or numba.
"""

from __future__ import annotations

from typing import Any

from ..physics.laws import LawParams
from .base import DEFAULT_RTOL, END_CRITERIA, T_MAX, Contact, SolveFn


def _reference(lp: LawParams, alpha: float, end: str, **options: Any) -> Contact:
    """:func:`viscontact.solvers.reference.solve_reference` (scipy, loaded on first call)."""
    from .reference import solve_reference

    return solve_reference(lp, alpha, end, **options)


def _batch(lp: LawParams, alpha: float, end: str, **options: Any) -> Contact:
    """:func:`viscontact.solvers.batch.solve_batch_one` (numba, loaded on first call)."""
    from .batch import solve_batch_one

    return solve_batch_one(lp, alpha, end, **options)


SOLVERS: dict[str, SolveFn] = {"reference": _reference, "batch": _batch}

__all__ = ["Contact", "SolveFn", "SOLVERS", "END_CRITERIA", "T_MAX", "DEFAULT_RTOL"]
