"""Batch solver: many collisions at once, compiled, in lanes, on every core.

Same equations as the reference solver (the regularised sigma-time system of
:mod:`viscontact.kernels`: x = s^m, dt = m s^(m-1) dsigma, polynomial in s for m p
integral) and the same end criteria, but no histories and no Python per collision:

- each thread takes a chunk of the batch and advances ``LANES`` collisions in lockstep
  with an adaptive explicit Runge-Kutta pair (Dormand-Prince 8(5,3), the coefficients of
  scipy's DOP853), each lane with its own step size; a finished lane is refilled with the
  next collision of the chunk, so the cost is linear in the batch size;
- the end of contact is an event g(y) = min(s, F/s^q (k-th root, zero-force end only),
  T_MAX - t) crossing zero from above; a step that crosses is not taken but shortened
  to the crossing by a safeguarded secant iteration (Illinois) on its length, each trial
  a full Runge-Kutta step from the step's start, so the end state carries the full order
  of the method (no interpolation error);
- the force arithmetic is :func:`viscontact.kernels.rhs_sigma` and
  :func:`viscontact.kernels.end_force_event`, the same expressions the reference uses.

Accuracy (measured against the references of ``tests/``, alpha, beta in [0, 10], every law,
both ends): at the default ``rtol`` = :data:`BATCH_RTOL` |e - exact| <= 1e-9 and
|tc - exact| <= 1e-8; at ``rtol = 1e-13`` about 1e-12 in e.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
from numba import prange
from numpy.typing import ArrayLike
# The published Dormand-Prince 8(5,3) tableau, as shipped by scipy (not copied here).
from scipy.integrate._ivp import dop853_coefficients as _dop853

from ..kernels import end_force_event, rhs_sigma
from ..laws import LawParams
from .base import END_CRITERIA, T_MAX, Contact

__all__ = ["BatchResult", "solve_batch", "solve_batch_one", "BATCH_RTOL", "LANES"]

#: Default relative tolerance of the batch solver: meets |e - exact| <= 1e-9 (contract 1e-8).
BATCH_RTOL: float = 1e-10
#: Collisions advanced in lockstep by one thread.
LANES: int = 8
#: Collisions per parallel work item (threads take chunks; lanes refill within a chunk).
_CHUNK: int = 512
#: Steps (accepted, rejected or event trials) after which one collision is declared failed.
_MAX_STEPS: int = 200_000

_NS = _dop853.N_STAGES  # 12 stages; the 13th evaluation is the first of the next step
_A = np.ascontiguousarray(_dop853.A[:_NS, :_NS])
_B = np.ascontiguousarray(_dop853.B)
_E3 = np.ascontiguousarray(_dop853.E3)
_E5 = np.ascontiguousarray(_dop853.E5)
_NV = 4  # state: s, v, t, W (dissipated work)

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0


@dataclass
class BatchResult:
    """Outcome of a batch of non-dimensional collisions (arrays of the batch shape).

    e: restitution -x'(t_c) (0 when not separated); tc: contact time t_c / T (inf when not
    separated); residual: overlap x(t_c) (at T_MAX when not separated); dissipated: damping
    work in m* v_i^2; separated: False when the contact still lasted at t = T_MAX.
    """

    e: np.ndarray
    tc: np.ndarray
    residual: np.ndarray
    dissipated: np.ndarray
    separated: np.ndarray


_jit = numba.njit(cache=True, nogil=True)


@_jit
def _event(s, v, t, alpha, beta, p, m, q, root, force_end, t_max):
    """min of the end events, each positive during the contact (see module docstring)."""
    g = min(s, t_max - t)
    if force_end and alpha > 0.0:  # undamped: F = 0 only where x = 0
        g = min(g, end_force_event(s, v, t, alpha, beta, p, m, q, root))
    return g


@_jit
def _first_step(beta, m):
    """Initial step: Jian with small beta switches damping on at t ~ beta (sigma ~ beta^(1/m))."""
    return 1e-2 if beta <= 0.0 else min(1e-2, 0.1 * beta ** (1.0 / m))


@_jit
def _solve_range(alpha, beta, lo, hi, p, m, q, root, force_end, rtol, atol, t_max,
                 e_out, tc_out, res_out, w_out, sep_out, steps_out):
    """Solve collisions lo..hi-1 in LANES lanes, writing the outputs (see module docstring)."""
    L = LANES
    y0 = np.zeros((_NV, L))  # state at the start of the current step
    y1 = np.zeros((_NV, L))  # trial state at its end
    ys = np.zeros((_NV, L))  # stage state
    K = np.zeros((_NS + 1, _NV, L))
    h = np.zeros(L)
    sig = np.zeros(L)
    a = np.zeros(L)
    b = np.zeros(L)
    ev0 = np.zeros(L)  # event value at y0
    idx = np.full(L, -1)  # collision in each lane (-1: idle)
    rejected = np.zeros(L, dtype=np.bool_)
    locating = np.zeros(L, dtype=np.bool_)
    h_lo = np.zeros(L)  # event bracket on the step length: g(h_lo) > 0 > g(h_hi)
    h_hi = np.zeros(L)
    g_lo = np.zeros(L)
    g_hi = np.zeros(L)
    side = np.zeros(L, dtype=np.int64)  # Illinois: which end moved last
    nsteps = np.zeros(L, dtype=np.int64)

    nxt = lo
    active = 0
    for l in range(L):
        if nxt < hi:
            idx[l] = nxt
            nxt += 1
            active += 1
        # idle lanes keep a harmless state (s = 0, v = 1, alpha = 0) and h = 0
    for l in range(L):
        _load(l, idx[l], alpha, beta, a, b, y0, K, h, sig, ev0, rejected, locating, nsteps,
              p, m)

    while active > 0:
        # --- one Runge-Kutta step in every lane (straight-line over lanes) ---
        for i in range(1, _NS):
            for c in range(_NV):
                for l in range(L):
                    ys[c, l] = 0.0
                for j in range(i):
                    aij = _A[i, j]
                    for l in range(L):
                        ys[c, l] += aij * K[j, c, l]
                for l in range(L):
                    ys[c, l] = y0[c, l] + h[l] * ys[c, l]
            for l in range(L):
                K[i, 0, l], K[i, 1, l], K[i, 2, l], K[i, 3, l] = rhs_sigma(
                    ys[0, l], ys[1, l], ys[2, l], a[l], b[l], p, m)
        for c in range(_NV):
            for l in range(L):
                y1[c, l] = 0.0
            for j in range(_NS):
                bj = _B[j]
                for l in range(L):
                    y1[c, l] += bj * K[j, c, l]
            for l in range(L):
                y1[c, l] = y0[c, l] + h[l] * y1[c, l]
        for l in range(L):
            K[_NS, 0, l], K[_NS, 1, l], K[_NS, 2, l], K[_NS, 3, l] = rhs_sigma(
                y1[0, l], y1[1, l], y1[2, l], a[l], b[l], p, m)

        # --- per-lane control: accept / reject / locate the end / refill ---
        for l in range(L):
            if idx[l] < 0:
                continue
            nsteps[l] += 1
            g1 = _event(y1[0, l], y1[1, l], y1[2, l], a[l], b[l], p, m, q, root, force_end, t_max)
            if locating[l]:
                done = False
                if g1 > 0.0:
                    h_lo[l], g_lo[l] = h[l], g1
                    if side[l] == 1:
                        g_hi[l] *= 0.5
                    side[l] = 1
                elif g1 < 0.0:
                    h_hi[l], g_hi[l] = h[l], g1
                    if side[l] == -1:
                        g_lo[l] *= 0.5
                    side[l] = -1
                else:
                    done = True
                width = h_hi[l] - h_lo[l]
                if width <= 4e-16 * (sig[l] + h_hi[l]) or nsteps[l] > _MAX_STEPS:
                    done = True
                if not done:
                    hn = h_lo[l] - g_lo[l] * width / (g_hi[l] - g_lo[l])
                    if not (h_lo[l] < hn < h_hi[l]):
                        hn = 0.5 * (h_lo[l] + h_hi[l])
                    h[l] = hn
                    continue
                k = idx[l]
                sep = y1[2, l] < t_max * (1.0 - 1e-12) and nsteps[l] <= _MAX_STEPS
                sep_out[k] = sep
                e_out[k] = max(-y1[1, l], 0.0) if sep else 0.0
                tc_out[k] = y1[2, l] if sep else math.inf
                res_out[k] = max(y1[0, l], 0.0) ** m
                w_out[k] = y1[3, l]
                steps_out[k] = nsteps[l]
                if nxt < hi:
                    idx[l] = nxt
                    nxt += 1
                else:
                    idx[l] = -1
                    active -= 1
                _load(l, idx[l], alpha, beta, a, b, y0, K, h, sig, ev0, rejected, locating,
                      nsteps, p, m)
                continue

            # error estimate of the 8(5,3) pair (as scipy's DOP853)
            e5 = 0.0
            e3 = 0.0
            for c in range(_NV):
                sc = atol + rtol * max(abs(y0[c, l]), abs(y1[c, l]))
                d5 = 0.0
                d3 = 0.0
                for j in range(_NS + 1):
                    d5 += _E5[j] * K[j, c, l]
                    d3 += _E3[j] * K[j, c, l]
                e5 += (d5 / sc) ** 2
                e3 += (d3 / sc) ** 2
            den = e5 + 0.01 * e3
            err = abs(h[l]) * e5 / math.sqrt(den * _NV) if den > 0.0 else 0.0
            if err > 1.0 or not math.isfinite(err):
                factor = _SAFETY * err ** (-1.0 / 8.0) if math.isfinite(err) else _MIN_FACTOR
                h[l] *= max(_MIN_FACTOR, factor)
                rejected[l] = True
                continue
            if g1 < 0.0:  # the contact ends inside this step: bracket the crossing
                locating[l] = True
                h_lo[l], g_lo[l] = 0.0, ev0[l]
                h_hi[l], g_hi[l] = h[l], g1
                side[l] = 0
                hn = -g_lo[l] * h[l] / (g1 - g_lo[l])
                h[l] = hn if 0.0 < hn < h_hi[l] else 0.5 * h_hi[l]
                continue
            # accept
            for c in range(_NV):
                y0[c, l] = y1[c, l]
                K[0, c, l] = K[_NS, c, l]
            sig[l] += h[l]
            ev0[l] = g1
            factor = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR, _SAFETY * err ** (-1.0 / 8.0))
            if rejected[l]:
                factor = min(1.0, factor)
            rejected[l] = False
            h[l] *= factor
            if nsteps[l] > _MAX_STEPS:  # give up on this collision: make it end now
                locating[l] = True
                h_lo[l], h_hi[l], g_lo[l], g_hi[l] = 0.0, 0.0, 1.0, -1.0
                h[l] = 0.0


@_jit
def _load(l, k, alpha, beta, a, b, y0, K, h, sig, ev0, rejected, locating, nsteps, p, m):
    """Put collision k (or an idle placeholder when k < 0) into lane l at x = 0, x' = 1."""
    if k >= 0:
        a[l] = alpha[k]
        b[l] = beta[k]
        h[l] = _first_step(b[l], m)
    else:
        a[l] = 0.0
        b[l] = 0.0
        h[l] = 0.0
    y0[0, l], y0[1, l], y0[2, l], y0[3, l] = 0.0, 1.0, 0.0, 0.0
    K[0, 0, l], K[0, 1, l], K[0, 2, l], K[0, 3, l] = rhs_sigma(0.0, 1.0, 0.0, a[l], b[l], p, m)
    sig[l] = 0.0
    ev0[l] = 0.0
    rejected[l] = False
    locating[l] = False
    nsteps[l] = 0


@numba.njit(cache=True, nogil=True, parallel=True)
def _solve_all(alpha, beta, p, m, q, root, force_end, rtol, atol, t_max,
               e_out, tc_out, res_out, w_out, sep_out, steps_out):
    n = alpha.size
    n_chunks = (n + _CHUNK - 1) // _CHUNK
    for c in prange(n_chunks):
        lo = c * _CHUNK
        hi = min(n, lo + _CHUNK)
        _solve_range(alpha, beta, lo, hi, p, m, q, root, force_end, rtol, atol, t_max,
                     e_out, tc_out, res_out, w_out, sep_out, steps_out)


def solve_batch(
    lp: LawParams, alpha: ArrayLike, end: str = "force", *, beta: ArrayLike | None = None,
    rtol: float = BATCH_RTOL,
) -> BatchResult:
    """Solve every collision of a batch (contract of :class:`~viscontact.solvers.base.SolveFn`).

    Args:
        lp: the resolved law (p, m; its beta unless ``beta`` is given).
        alpha: damping constants, any shape, validated finite and >= 0 by the caller.
        end: ``"force"`` (first zero of the force) or ``"overlap"`` (x back to 0).
        beta: relaxation times tau / T, broadcast against ``alpha`` (default ``lp.beta``).
        rtol: relative tolerance of the step-size control (absolute: rtol / 100).

    Returns a :class:`BatchResult` of arrays with the broadcast shape.  Memory is a few
    arrays of the batch size; the cost is linear in it; no histories are kept.
    """
    if end not in END_CRITERIA:
        raise ValueError(f"end must be one of {', '.join(END_CRITERIA)}; got {end!r}")
    a = np.asarray(alpha, dtype=float)
    b = np.asarray(lp.beta if beta is None else beta, dtype=float)
    shape = np.broadcast_shapes(a.shape, b.shape)
    a, b = (np.array(np.broadcast_to(x, shape), order="C").ravel() for x in (a, b))  # own, writeable
    n = a.size
    e, tc, res, w = (np.empty(n) for _ in range(4))
    sep = np.empty(n, dtype=np.bool_)
    steps = np.empty(n, dtype=np.int64)
    m, p = lp.m, lp.p
    q = min(m * p, 1.5 * m)
    k = 1.5 * m - q
    root = 1.0 / k if k > 1 else 1.0
    if n:
        _solve_all(a, b, p, m, q, root, end == "force", rtol, rtol * 1e-2, T_MAX,
                   e, tc, res, w, sep, steps)
        if steps.max() > _MAX_STEPS:  # pragma: no cover - a solver failure is a bug
            raise RuntimeError("batch solver: step limit reached (please report this input)")
    return BatchResult(*(x.reshape(shape) for x in (e, tc, res, w, sep)))


def solve_batch_one(
    lp: LawParams, alpha: float, end: str, *, rtol: float = BATCH_RTOL, detail: bool = False
) -> Contact:
    """One collision through the batch solver (the :data:`SOLVERS` contract); no histories."""
    if detail:
        raise ValueError("the batch solver computes no histories; use the reference solver")
    r = solve_batch(lp, np.array([alpha]), end, rtol=rtol)
    return Contact(e=float(r.e[0]), tc=float(r.tc[0]), separated=bool(r.separated[0]),
                   residual=float(r.residual[0]), dissipated=float(r.dissipated[0]))
