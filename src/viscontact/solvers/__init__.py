"""Collision solvers behind one contract.

A solver is a function ``solve(lp, alpha, end, *, rtol, detail) -> Contact`` (see
:mod:`viscontact.solvers.base`).  Solvers know nothing about law names: they receive
the resolved numbers (p, beta, m) and call the kernels.  ``SOLVERS`` lists them; the
public API picks one by name, so a faster solver drops in without touching callers.

The batch solver (numba) and the reference solver (scipy) are imported on first use, so
that a caller of one does not pay for loading the other.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from .._lazy import lazy_exports
from ..laws import LawParams
from .base import Contact, SolveFn, END_CRITERIA, T_MAX, DEFAULT_RTOL

if TYPE_CHECKING:
    from .batch import BATCH_RTOL, BatchResult, solve_batch, solve_batch_one
    from .reference import solve_reference

#: module -> the names it provides, imported on first access
_LAZY = {
    "batch": ("BATCH_RTOL", "BatchResult", "solve_batch", "solve_batch_one"),
    "reference": ("solve_reference",),
}


def _solver(module: str, name: str) -> SolveFn:
    """``module.name`` behind the solver contract, imported on its first call."""

    def solve(lp: LawParams, alpha: float, end: str, **options: Any) -> Contact:
        return getattr(importlib.import_module(f".{module}", __name__), name)(
            lp, alpha, end, **options)

    solve.__name__ = solve.__qualname__ = name
    solve.__doc__ = f"{name} from viscontact.solvers.{module}, imported on first call."
    return solve


#: ``reference``: scipy DOP853, histories, one collision per call.  ``batch``: compiled,
#: many collisions per call (:func:`solve_batch`), no histories.
SOLVERS: dict[str, SolveFn] = {
    "reference": _solver("reference", "solve_reference"),
    "batch": _solver("batch", "solve_batch_one"),
}

__all__ = [
    "Contact", "SolveFn", "SOLVERS", "END_CRITERIA", "T_MAX", "DEFAULT_RTOL", "BATCH_RTOL",
    "BatchResult", "solve_batch", "solve_batch_one", "solve_reference",
]

__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())
