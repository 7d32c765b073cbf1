"""Restitution coefficient e(alpha) and its inverse alpha(e), broadcasting over arrays."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from .collision import check_end, collide_params
from .laws import LawParams, check_finite_nonneg, resolve

__all__ = ["restitution", "alpha_from_e", "ALPHA_MAX"]

#: alpha_from_e searches alpha in [0, ALPHA_MAX]; a smaller e is reported unreachable.
ALPHA_MAX = 1000.0
_E_TOL = 1e-12  # |e(alpha) - target| at which the inversion stops (the contract is 1e-9)


def _as_checked_array(name: str, value: ArrayLike) -> np.ndarray:
    arr = np.asarray(value, dtype=object)
    flat = [check_finite_nonneg(name, v) for v in arr.ravel()]
    return np.array(flat, dtype=float).reshape(arr.shape)


def _law_grid(model: str, alpha: ArrayLike, beta: ArrayLike | None, p: float | None):
    """Validated (law for each element, alpha array) broadcast together."""
    base = resolve(model, beta=None if beta is None else 0.0, p=p)
    a = _as_checked_array("alpha", alpha)
    if beta is None:
        return np.full(a.shape, base, dtype=object), a
    b = _as_checked_array("beta", beta)
    a, b = np.broadcast_arrays(a, b)
    laws = np.empty(a.shape, dtype=object)
    for idx in np.ndindex(a.shape):
        laws[idx] = LawParams(base.law, base.p, float(b[idx]), base.m)
    return laws, a


def _e_of(lp: LawParams, alpha: float, end: str) -> float:
    return collide_params(lp, alpha, end, history=False).e


def restitution(
    model: str, alpha: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force",
) -> np.ndarray | float:
    """Coefficient of restitution e = -x'(t_c) for each alpha (and beta, Jian).

    Broadcasts ``alpha`` against ``beta``; returns a float for scalar input, else an
    array of the broadcast shape.  Accuracy |e - exact| <= 1e-8 (SPEC sections 2-5).
    A zero-overlap contact that never separates gives e = 0.
    """
    check_end(end)
    laws, a = _law_grid(model, alpha, beta, p)
    out = np.empty(a.shape)
    for idx in np.ndindex(a.shape):
        out[idx] = _e_of(laws[idx], float(a[idx]), end)
    return float(out) if out.ndim == 0 else out


def _invert(lp: LawParams, target: float, end: str) -> float:
    if target == 1.0:
        return 0.0
    hi = 1.0
    e_hi = _e_of(lp, hi, end)
    while e_hi > target:
        if hi >= ALPHA_MAX:
            raise ValueError(
                f"e = {target!r} is below what {lp.name} reaches with alpha <= {ALPHA_MAX:g} under "
                f"the zero-{end} criterion; allowed range is [{e_hi:.6g}, 1]"
            )
        hi = min(4.0 * hi, ALPHA_MAX)
        e_hi = _e_of(lp, hi, end)
    return brentq(
        lambda a: _e_of(lp, a, end) - target, 0.0, hi, xtol=1e-15, rtol=1e-14, maxiter=200
    )


def alpha_from_e(
    model: str, e: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force",
) -> np.ndarray | float:
    """The damping constant alpha >= 0 that gives restitution ``e`` (inverse of :func:`restitution`).

    Broadcasts ``e`` against ``beta``.  |restitution(alpha_from_e(e)) - e| <= 1e-9; e = 1
    gives 0.  Raises ValueError for e outside (0, 1], NaN, or an e the law cannot reach.
    """
    check_end(end)
    e_arr = np.asarray(e, dtype=object)
    for v in e_arr.ravel():
        try:
            ok = 0.0 < float(v) <= 1.0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"e must be a number in (0, 1]; got {v!r}")
    laws, e_f = _law_grid(model, e_arr, beta, p)
    out = np.empty(e_f.shape)
    for idx in np.ndindex(e_f.shape):
        out[idx] = _invert(laws[idx], float(e_f[idx]), end)
    return float(out) if out.ndim == 0 else out
