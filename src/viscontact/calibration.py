"""Restitution coefficient e(alpha) and its inverse alpha(e), broadcasting over arrays."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .collision import check_end
from .laws import LawParams, check_finite_nonneg, resolve

# The tables and the batch solver (numba) are imported where they are used, so that importing
# this module (the command line does) does not load the compiler.

__all__ = ["restitution", "alpha_from_e", "ALPHA_MAX"]

#: alpha_from_e searches alpha in [0, ALPHA_MAX]; a smaller e is reported unreachable.
ALPHA_MAX = 1000.0
_E_TOL = 1e-12  # |e(alpha) - target| at which the inversion stops (the contract is 1e-9)
_MAX_ITER = 200


def _as_checked_array(name: str, value: ArrayLike) -> np.ndarray:
    """``value`` as a float array, or ValueError naming the first bad element (vectorised)."""
    raw = np.asarray(value)
    if raw.dtype.kind not in "biuf":  # strings, objects, complex: check one by one
        arr = np.asarray(value, dtype=object)
        flat = [check_finite_nonneg(name, v) for v in arr.ravel()]
        return np.array(flat, dtype=float).reshape(arr.shape)
    a = raw.astype(float, copy=False)  # read only below: no copy of a float array
    if a.size and not (a.min() >= 0.0 and a.max() < np.inf):  # NaN fails too; no temporaries
        bad = ~(np.isfinite(a) & (a >= 0))
        first = np.asarray(value, dtype=object).ravel()[int(np.argmax(bad.ravel()))]
        check_finite_nonneg(name, first)  # raises with the usual message
    return a


def _law_grid(model: str, alpha: ArrayLike, beta: ArrayLike | None, p: float | None):
    """Validated law, alpha array and beta array (or None) broadcast together."""
    base = resolve(model, beta=None if beta is None else 0.0, p=p)
    a = _as_checked_array("alpha", alpha)
    if beta is None:
        return base, a, None
    a, b = np.broadcast_arrays(a, _as_checked_array("beta", beta))
    return base, a, b


def _e_of(lp: LawParams, alpha: np.ndarray, beta: np.ndarray | None, end: str) -> np.ndarray:
    from .solvers.batch import solve_batch

    return solve_batch(lp, alpha, end, beta=beta, dissipated=False).e


def restitution(
    model: str, alpha: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force", exact: bool = False,
) -> np.ndarray | float:
    """Coefficient of restitution e = -x'(t_c) for each alpha (and beta, Jian).

    Broadcasts ``alpha`` against ``beta``; returns a float for scalar input, else an
    array of the broadcast shape.  Accuracy |e - exact| <= 1e-8 (SPEC sections 2-5);
    solved by the compiled batch solver (:func:`viscontact.solvers.solve_batch`).
    A zero-overlap contact that never separates gives e = 0.

    Inside alpha, beta in [0, 10] every law but ``power`` answers from a precomputed table
    (:mod:`viscontact.tables`, |e - exact| <= 1e-10); ``exact=True`` always solves.
    """
    from . import tables

    check_end(end)
    lp, a, b = _law_grid(model, alpha, beta, p)
    out = _e_of(lp, a, b, end) if exact else tables.through_tables("e", lp, a, b, end, _e_of)
    return float(out) if out.ndim == 0 else out


def _invert(lp: LawParams, target: np.ndarray, beta: np.ndarray | None, end: str) -> np.ndarray:
    """alpha with e(alpha) = target for every element (flat arrays): vectorised bracketing,
    then a safeguarded secant iteration (Illinois) on all unconverged elements at once."""
    n = target.size
    alpha = np.zeros(n)
    todo = np.flatnonzero(target < 1.0)  # e = 1 -> alpha = 0
    if todo.size == 0:
        return alpha
    tgt = target[todo]
    bet = None if beta is None else beta[todo]
    lo, f_lo = np.zeros(todo.size), 1.0 - tgt  # e(0) = 1
    hi = np.ones(todo.size)
    f_hi = _e_of(lp, hi, bet, end) - tgt
    while True:  # grow the bracket where e(hi) is still above the target
        grow = np.flatnonzero(f_hi > 0)
        if grow.size == 0:
            break
        capped = grow[hi[grow] >= ALPHA_MAX]
        if capped.size:
            i = capped[0]
            raise ValueError(
                f"e = {float(tgt[i])!r} is below what {lp.name} reaches with alpha <= {ALPHA_MAX:g} under "
                f"the zero-{end} criterion; allowed range is [{f_hi[i] + tgt[i]:.6g}, 1]"
            )
        lo[grow], f_lo[grow] = hi[grow], f_hi[grow]
        hi[grow] = np.minimum(4.0 * hi[grow], ALPHA_MAX)
        f_hi[grow] = _e_of(lp, hi[grow], None if bet is None else bet[grow], end) - tgt[grow]
    side = np.zeros(todo.size, dtype=int)
    best = hi.copy()
    live = np.arange(todo.size)
    for _ in range(_MAX_ITER):
        x = lo[live] - f_lo[live] * (hi[live] - lo[live]) / (f_hi[live] - f_lo[live])
        bad = ~((x > lo[live]) & (x < hi[live]))
        x[bad] = 0.5 * (lo[live][bad] + hi[live][bad])
        f = _e_of(lp, x, None if bet is None else bet[live], end) - tgt[live]
        best[live] = x
        up = f > 0  # e too high: alpha above x
        i_up, i_dn = live[up], live[~up]
        lo[i_up], f_lo[i_up] = x[up], f[up]
        f_hi[i_up[side[i_up] == 1]] *= 0.5  # Illinois: halve the stale end
        side[i_up] = 1
        hi[i_dn], f_hi[i_dn] = x[~up], f[~up]
        f_lo[i_dn[side[i_dn] == -1]] *= 0.5
        side[i_dn] = -1
        done = (np.abs(f) <= _E_TOL) | (hi[live] - lo[live] <= 4e-16 * hi[live])
        live = live[~done]
        if live.size == 0:
            break
    alpha[todo] = best
    return alpha


def alpha_from_e(
    model: str, e: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force", exact: bool = False,
) -> np.ndarray | float:
    """The damping constant alpha >= 0 that gives restitution ``e`` (inverse of :func:`restitution`).

    Broadcasts ``e`` against ``beta``.  |restitution(alpha_from_e(e)) - e| <= 1e-9; e = 1
    gives 0.  Raises ValueError for e outside (0, 1], NaN, or an e the law cannot reach.
    Every element is solved at once: batch solves of the whole array per iteration.
    Where the law's table (:mod:`viscontact.tables`) reaches, it answers instead (Newton on
    the interpolant); ``exact=True`` always solves.
    """
    check_end(end)
    raw = np.asarray(e)
    if raw.dtype.kind in "biuf":
        e_arr = raw.astype(float, copy=False)  # read only below
        if e_arr.size and not (e_arr.min() > 0.0 and e_arr.max() <= 1.0):  # NaN fails too
            ok = (e_arr > 0.0) & (e_arr <= 1.0)
            bad = np.asarray(e, dtype=object).ravel()[int(np.argmin(ok.ravel()))]
            raise ValueError(f"e must be a number in (0, 1]; got {bad!r}")
    else:
        for v in np.asarray(e, dtype=object).ravel():
            try:
                good = 0.0 < float(v) <= 1.0
            except (TypeError, ValueError):
                good = False
            if not good:
                raise ValueError(f"e must be a number in (0, 1]; got {v!r}")
        e_arr = np.asarray(e, dtype=object).astype(float)
    lp, e_f, b = _law_grid(model, e_arr, beta, p)
    if exact:
        out = _invert(lp, np.ascontiguousarray(e_f).ravel(), None if b is None else
                      np.ascontiguousarray(b).ravel(), end).reshape(e_f.shape)
    else:
        from . import tables

        out = tables.through_tables("alpha", lp, e_f, b, end, _invert)
    return float(out) if out.ndim == 0 else out
