"""Restitution coefficient e(alpha) and its inverse alpha(e), broadcasting over arrays."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..physics import domain
from ..collision.single import check_end
from ..physics.domain import ALPHA_MAX
from ..physics.laws import LawParams, resolve

# The tables and the batch solver (numba) are imported where they are used, so that importing
# this module (the command line does) does not load the compiler.

__all__ = ["restitution", "alpha_from_e", "ALPHA_MAX"]

# alpha_from_e searches alpha in [0, ALPHA_MAX] (the domain of alpha, :mod:`.domain`); a
# smaller e is reported unreachable.
_E_TOL = 1e-12  # |e(alpha) - target| at which the inversion stops (the contract is 1e-9)
_MAX_ITER = 200


def _law_grid(model: str, x: np.ndarray, beta: ArrayLike | None, p: float | None):
    """Validated law, the (validated) array ``x`` and beta array (or None) broadcast together."""
    base = resolve(model, beta=None if beta is None else 0.0, p=p)
    if beta is None:
        return base, x, None
    b = domain.check_array("beta", beta)
    try:
        # owned copies: broadcast views warn (numpy 2) where numba receives them
        a, b = (np.array(v) for v in np.broadcast_arrays(x, b))
    except ValueError:
        raise ValueError(f"beta of shape {np.shape(beta)} does not broadcast against shape "
                         f"{np.shape(x)}") from None
    return base, a, b


def _valid_e(e: np.ndarray) -> np.ndarray:
    """Restitution as solved, within [0, 1] (e <= 1 exactly by the energy balance; rounding
    or the tables' interpolation may leave it a few ulps above)."""
    return np.clip(e, 0.0, 1.0, out=e) if isinstance(e, np.ndarray) and e.flags.writeable \
        else np.clip(e, 0.0, 1.0)


def _e_of(lp: LawParams, alpha: np.ndarray, beta: np.ndarray | None, end: str) -> np.ndarray:
    from ..solvers.batch import solve_batch

    return solve_batch(lp, alpha, end, beta=beta, dissipated=False).e


def restitution(
    model: str, alpha: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force", exact: bool = False,
) -> np.ndarray | float:
    """Coefficient of restitution e = -x'(t_c) for each alpha (and beta, Jian).

    Broadcasts ``alpha`` against ``beta``; returns a float for scalar input, else an
    array of the broadcast shape.  Accuracy |e - exact| <= 1e-8 (against the exact solver);
    solved by the compiled batch solver (:func:`viscontact.solvers.batch.solve_batch`).
    A zero-overlap contact that never separates gives e = 0.  e lies in [0, 1]; alpha = 0
    gives exactly 1.

    Inside alpha, beta in [0, 10] every law but ``power`` answers from a precomputed table
    (:mod:`viscontact.tables`, |e - exact| <= 1e-10); ``exact=True`` always solves.
    alpha, beta and p must lie in their domain (:mod:`viscontact.physics.domain`: [0, 1000],
    [0, 1000], [0, 10]), else ValueError.
    """
    from . import tables

    check_end(end)
    exact = domain.check_bool("exact", exact)
    lp, a, b = _law_grid(model, domain.check_array("alpha", alpha), beta, p)
    out = _e_of(lp, a, b, end) if exact else tables.through_tables("e", lp, a, b, end, _e_of)
    out = _valid_e(out)
    if out.size and not a.all():  # undamped: e = 1 exactly (energy is conserved)
        out = np.where(a == 0.0, 1.0, out)
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
    f_best = f_hi.copy()
    live = np.arange(todo.size)
    for _ in range(_MAX_ITER):
        x = lo[live] - f_lo[live] * (hi[live] - lo[live]) / (f_hi[live] - f_lo[live])
        bad = ~((x > lo[live]) & (x < hi[live]))
        x[bad] = 0.5 * (lo[live][bad] + hi[live][bad])
        f = _e_of(lp, x, None if bet is None else bet[live], end) - tgt[live]
        best[live], f_best[live] = x, f
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
    # e(alpha) jumps where a zero-overlap contact stops separating before T_MAX: a bracket
    # that closed on that jump has no root; say so rather than return its end
    miss = np.flatnonzero(np.abs(f_best) > 1e-9 * (1.0 + tgt))
    if miss.size:
        i = miss[0]
        raise ValueError(
            f"e = {float(tgt[i])!r} is not reached by {lp.name} under the zero-{end} criterion "
            f"(e(alpha) jumps to 0 near alpha = {float(best[i]):.6g}, "
            f"where the contact stops separating before t = T_MAX); give a larger e")
    alpha[todo] = best
    return alpha


def alpha_from_e(
    model: str, e: ArrayLike, *, beta: ArrayLike | None = None, p: float | None = None,
    end: str = "force", exact: bool = False,
) -> np.ndarray | float:
    """The damping constant alpha >= 0 that gives restitution ``e`` (inverse of :func:`restitution`).

    Broadcasts ``e`` against ``beta``.  |restitution(alpha_from_e(e)) - e| <= 1e-9; e = 1
    gives 0.  Raises ValueError for e outside [1e-6, 1] (:data:`viscontact.physics.domain.E_MIN`:
    below it the zero-overlap end gives up at T_MAX before the contact separates), NaN, an e
    the law cannot reach with alpha <= 1000, or beta, p outside their domain.
    Every element is solved at once: batch solves of the whole array per iteration.
    Where the law's table (:mod:`viscontact.tables`) reaches, it answers instead (Newton on
    the interpolant); ``exact=True`` always solves.
    """
    check_end(end)
    exact = domain.check_bool("exact", exact)
    e_arr = domain.check_array("e", e)
    lp, e_f, b = _law_grid(model, e_arr, beta, p)
    if exact:
        out = _invert(lp, np.ascontiguousarray(e_f).ravel(), None if b is None else
                      np.ascontiguousarray(b).ravel(), end).reshape(e_f.shape)
    else:
        from . import tables

        out = tables.through_tables("alpha", lp, e_f, b, end, _invert)
    return float(out) if out.ndim == 0 else out
