"""Batch solver: many collisions at once, compiled, on every core.

Same equations as the reference solver (the regularised sigma-time system of
:mod:`viscontact.physics.kernels`: x = s^m, dt = m s^(m-1) dsigma, polynomial in s for m p
integral) and the same end criteria, but no histories and no Python per collision:

- the batch is cut into chunks that a pool of threads shares (``numba.get_num_threads()``
  of them; the compiled solver releases the GIL); a thread advances up to ``SLOTS`` (128)
  collisions of its chunk in lockstep ("lanes"), their states the rows of one flat array;
  each lane has its own step size (Dormand-Prince 8(5,3), the tableau shipped with scipy's
  DOP853, and scipy's error norm and step control); a finished lane takes the next
  collision of the chunk, or the last live lane, so the cost is linear in the batch size
  and the memory a few arrays of it;
- one step of every lane is :func:`._dop853_lanes.dop853_lanes`, generated straight-line
  code (:mod:`._codegen`: twelve stages as scalar locals, no inner loops, no library
  calls), which the compiler vectorises across lanes (8 doubles per instruction with
  AVX-512), with fused multiply-adds; accept/reject and the next step size follow in a
  second vectorised loop (:func:`_accept_lanes`); only lanes whose step crosses an end of
  contact are handled one by one;
- with m p an integer (every named law, and ``power`` with p a multiple of 1/8) the
  right-hand side is :func:`viscontact.physics.kernels.rhs_sigma_int`: straight-line code, no
  library calls (the relaxation factor of Jian from a table and a short series);
  otherwise the general :func:`viscontact.physics.kernels.rhs_sigma` (|s|^k by pow), slower;
- each shape of the equations (m, m p, whether some beta > 0, whether W is wanted) is
  compiled once with these as constants (:func:`_make_solver`): the integer powers fold
  to a few multiplications and an unused W (``dissipated=False``, as ``restitution``
  asks) costs nothing;
- the end of contact is an event g(y) = min(s, zero-force gap
  (:func:`viscontact.physics.kernels.end_force_event`, zero-force end only), T_MAX - t)
  crossing zero from above; a step that crosses is not taken but shortened to the
  crossing by safeguarded Newton iterations on its length (first guess: the root of the
  cubic Hermite interpolant of the ending event over the step; slope of g along the
  solution exact for the overlap and time events, by a difference for the zero-force one;
  Illinois secant or bisection when Newton leaves the bracket), each trial a full Runge-Kutta step from the step's start, so the end state
  carries the full order of the method; once the Newton correction d is below
  1e-2 sqrt(rtol) of the step, the end is the last trial extrapolated by d along the
  solution (error O(d^2), far below rtol) instead of one more trial.

Accuracy, measured against the reference solver at rtol 1e-13 and the independent
references of ``tests/`` (alpha, beta in {0} U [1e-9, 10], every law, both ends):
at the default ``rtol`` = :data:`BATCH_RTOL` (1e-9), |e - exact| <= 4e-10 and
|tc - exact| <= 2e-8 (without W, ``dissipated=False``, W no longer tightens the error norm:
|e - exact| <= 6e-10, Jian with beta ~ 0.01 the worst); at ``rtol = 1e-13``, |e - exact| <~ 2e-12 and |tc - exact| <~ 3e-11.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numba
import numpy as np
from numpy.typing import ArrayLike

from .._support.locks import compile_once
from ..physics.kernels import INT_POW_LIMIT, end_force_event, rhs_sigma
from ..physics.laws import LawParams
from . import _dop853_lanes as L
from ._dop853_lanes import SLOTS as _SLOTS
from ._dop853_lanes import dop853_lanes
from .base import END_CRITERIA, T_MAX, Contact, force_end_is_overlap_end

__all__ = ["BatchResult", "solve_batch", "solve_batch_one", "BATCH_RTOL"]

#: Default relative tolerance of the batch solver: meets |e - exact| <= 1e-9 (contract 1e-8).
BATCH_RTOL: float = 1e-9
#: Lanes stepped are padded to a multiple of this (above any vector width x interleave)
_VECTOR_PAD: int = 16
#: Fewest collisions per parallel work item (threads take chunks; slots refill within one).
_CHUNK: int = 2048
#: First step in sigma (the solution is a power series in sigma at the start).
_H0: float = 0.1
#: Steps (accepted, rejected or event trials) after which one collision is given up: damping
#: so strong that the explicit method needs ~ alpha steps (LH, zero-overlap end, alpha = 1e4
#: takes ~3e5; a few seconds at this limit).
_MAX_STEPS: int = 5_000_000

# safety 0.8 (scipy: 0.9): a quarter fewer rejected steps, a few per cent fewer steps in all
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.8, 0.2, 10.0


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


_jit = numba.njit(cache=True, nogil=True, error_model="numpy")


@_jit
def _event_min(S, y_row, l, alpha, beta, p, m, q, force_end, t_max):
    """The end events at lane l of the state at row y_row of S, each positive during the
    contact (see module docstring): (g, part, g_force) with g the smallest, part which one
    (0: overlap s, 1: time limit T_MAX - t, 2: zero force) and g_force the zero-force event
    (+inf when it is off)."""
    s, v, t = S[y_row + l], S[y_row + _SLOTS + l], S[y_row + 2 * _SLOTS + l]
    g, part, g_force = s, 0, math.inf
    if t_max - t < g:
        g, part = t_max - t, 1
    if force_end and alpha > 0.0:  # undamped: F = 0 only where x = 0
        g_force = end_force_event(s, v, t, alpha, beta, p, m, q)
        if g_force < g:
            g, part = g_force, 2
    return g, part, g_force


@_jit
def _event_part(S, y_row, l, part, g_force, t_max):
    """Event ``part`` (as :func:`_event_min`) at lane l of the state at row y_row."""
    if part == 0:
        return S[y_row + l]
    if part == 1:
        return t_max - S[y_row + 2 * _SLOTS + l]
    return g_force


@_jit
def _event_slope(S, y_row, f_row, l, part, g, alpha, beta, p, m, q, h, central):
    """d(event ``part``)/dsigma at lane l of the state at row y_row of S, where the event is g.

    Exact for the overlap and time-limit events (ds/dsigma, -dt/dsigma: the right-hand side
    at row f_row, FS1 at a step's end, FS0 at its start, which every step computes anyway);
    for the zero-force event a difference along the solution: central (error O(d^2), for
    the Hermite guess), or one-sided from g (one evaluation; error O(d), which only slows
    the last Newton correction by a factor ~1e-6, far below the tolerance)."""
    if part == 0:
        return S[f_row + l]
    if part == 1:
        return -S[f_row + 2 * _SLOTS + l]
    d = 1e-6 * h
    if not d > 0.0:
        return 0.0
    y0, y1, y2 = S[y_row + l], S[y_row + _SLOTS + l], S[y_row + 2 * _SLOTS + l]
    f0, f1, f2 = S[f_row + l], S[f_row + _SLOTS + l], S[f_row + 2 * _SLOTS + l]
    up = end_force_event(y0 + d * f0, y1 + d * f1, y2 + d * f2, alpha, beta, p, m, q)
    if not central:
        return (up - g) / d
    dn = end_force_event(y0 - d * f0, y1 - d * f1, y2 - d * f2, alpha, beta, p, m, q)
    return (up - dn) / (2.0 * d)


@_jit
def _hermite_root(g0, d0, g1, d1, h):
    """Root in (0, h) of the cubic Hermite interpolant of an event with values g0 > 0 > g1
    and slopes d0, d1 at the ends of a step of length h (Newton on the cubic, kept in its
    bracket by bisection): a first guess of the end within O(h^4) of it; -1 if none."""
    t_lo, t_hi = 0.0, 1.0
    t = g0 / (g0 - g1)
    for _ in range(30):
        t2 = t * t
        t3 = t2 * t
        val = ((2.0 * t3 - 3.0 * t2 + 1.0) * g0 + (t3 - 2.0 * t2 + t) * h * d0
               + (3.0 * t2 - 2.0 * t3) * g1 + (t3 - t2) * h * d1)
        der = ((6.0 * t2 - 6.0 * t) * (g0 - g1) + (3.0 * t2 - 4.0 * t + 1.0) * h * d0
               + (3.0 * t2 - 2.0 * t) * h * d1)
        if val > 0.0:
            t_lo = t
        else:
            t_hi = t
        tn = t - val / der if der != 0.0 else -1.0
        if not t_lo < tn < t_hi:
            tn = 0.5 * (t_lo + t_hi)
        if abs(tn - t) <= 1e-12:
            return tn * h
        t = tn
    return t * h if 0.0 < t < 1.0 else -1.0


@_jit
def _first_step(beta, m):
    """Initial step: Jian with small beta switches damping on at t ~ beta (sigma ~ beta^(1/m))."""
    return _H0 if beta <= 0.0 else min(_H0, 0.1 * beta ** (1.0 / m))


_inline = numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")


@_inline
def _accept_lanes(S, lo, hi, nv, t_max):
    """After :func:`dop853_lanes`: accept or reject the step in lanes lo..hi-1 and choose the
    next step (scipy's DOP853 control), all as selects so that the loop vectorises.  A lane
    whose accepted step crosses an end event, or that is locating one, is marked SPECIAL and
    left as it is for the one-by-one event handling.  Returns the number of such lanes plus
    those past the step limit."""
    pending = 0
    for l in range(lo, hi):
        en = S[L.ERR + l]
        ok = en <= 1.0  # False for NaN
        cross = ((S[L.S1 + l] < 0.0) | (S[L.T1 + l] > t_max)
                 | ((S[L.ACTIVE_FORCE + l] != 0.0) & (S[L.FEND + l] < 0.0)))
        special = (S[L.LOCATING + l] != 0.0) | (ok & cross)
        # err^(-1/8) by three square roots (vectorises; no pow)
        grow = _SAFETY / math.sqrt(math.sqrt(math.sqrt(en))) if en > 0.0 else _MAX_FACTOR
        grow = min(_MAX_FACTOR, grow)
        rejected = S[L.REJECTED + l] != 0.0
        grow = min(1.0, grow) if rejected else grow
        shrink = max(_MIN_FACTOR, grow) if en == en else _MIN_FACTOR
        take = ok & ~special
        for c in range(nv):
            r = c * _SLOTS + l
            S[L.S0 + r] = S[L.S1 + r] if take else S[L.S0 + r]
            S[L.FS0 + r] = S[L.FS1 + r] if take else S[L.FS0 + r]
        h = S[L.H + l]
        S[L.SIG + l] = S[L.SIG + l] + h if take else S[L.SIG + l]
        S[L.H + l] = h if special else h * (grow if ok else shrink)
        S[L.REJECTED + l] = S[L.REJECTED + l] if special else (0.0 if ok else 1.0)
        S[L.SPECIAL + l] = 1.0 if special else 0.0
        S[L.NSTEPS + l] += 1.0
        pending += 1 if special | (S[L.NSTEPS + l] > _MAX_STEPS) else 0
    return pending


def _make_solver(m: int, n_damp: int, nv: int, relax: bool):
    """The compiled solver of one shape of the equations, with the exponents m and
    n_damp = m p (-1: not an integer, the general pow path), the state size nv (3: s, v, t;
    4: also the dissipated work W) and ``relax`` (False: every beta is 0, g = 1) as
    compile-time constants, so that the integer powers fold to a few multiplications and
    unused components cost nothing.  Built once per shape; numba caches each closure by
    its constants."""
    k_spring = (3 * m) // 2 - min(n_damp, (3 * m) // 2)  # F / s^q exponents (integer path)
    k_damp = n_damp - min(n_damp, (3 * m) // 2)

    # only numbers in the closures: numba caches them under their hash
    # contract: a * b + c as one fused multiply-add (one rounding instead of two; the
    # stage sums become chains of them), no other fast-math licence
    @numba.njit(cache=True, nogil=True, error_model="numpy", fastmath={"contract"})
    def solve_range(alpha, beta, lo, hi, p, q, force_end, rtol, atol, t_max,
                    e_out, tc_out, res_out, w_out, sep_out, steps_out):
        """Solve collisions lo..hi-1 in up to SLOTS lanes advanced in lockstep.

        The lanes' state is one flat array (field k of lane l at S[k * SLOTS + l], fields in
        :mod:`._dop853_lanes`): one base pointer at constant distances lets the compiler
        vectorise the loops over lanes without run-time alias checks.  Lanes 0..n-1 are
        live; a finished lane takes the next collision, or, when none is left, the state of
        the last live lane (so the live lanes stay contiguous).
        """
        C = min(_SLOTS, hi - lo)
        ext = 1e-2 * math.sqrt(rtol)  # relative Newton step that ends the event search
        S = np.zeros(L.N_FIELDS * _SLOTS)
        # event search (one by one, not vectorised): bracket [h_lo, h_hi] of the step length
        h_lo, h_hi, g_lo, g_hi = np.zeros(C), np.zeros(C), np.zeros(C), np.zeros(C)
        side = np.zeros(C, dtype=np.int64)  # Illinois: which end of the bracket moved last
        idx = np.zeros(C, dtype=np.int64)

        nxt = lo
        n = C
        for l in range(n):
            _load(S, l, nxt, alpha, beta, idx, force_end, p, m, nv)
            nxt += 1

        while n > 0:
            # steps in every live lane until one needs the one-by-one handling below; the
            # loop over lanes vectorises only inside such a loop (measured: 8-12x faster)
            # every live lane takes the vector loop's body, never its scalar remainder (whose
            # fused multiply-adds may differ by an ulp): a result must not depend on how many
            # collisions share its block; lanes past n hold stale states, harmless to step
            n_pad = min(-(-n // _VECTOR_PAD) * _VECTOR_PAD, _SLOTS)
            while True:
                dop853_lanes(S, 0, n_pad, rtol, atol, p, q, m, n_damp, k_spring, k_damp, nv,
                             relax)
                if _accept_lanes(S, 0, n, nv, t_max):
                    break
            # --- one by one: bracket and locate the end, finish, refill or compact ---
            for l in range(n - 1, -1, -1):
                a, b, h = S[L.ALPHA + l], S[L.BETA + l], S[L.H + l]
                nsteps = S[L.NSTEPS + l]
                if S[L.SPECIAL + l] == 0.0:
                    if nsteps <= _MAX_STEPS:
                        continue
                    S[L.LOCATING + l] = 1.0  # give up on this collision: end it here
                    h_lo[l], h_hi[l], g_lo[l], g_hi[l] = 0.0, 0.0, 1.0, -1.0
                    S[L.H + l] = 0.0
                    continue
                g1, part, g1_force = _event_min(S, L.S1, l, a, b, p, m, q, force_end, t_max)
                slope = math.nan
                guess = -1.0
                if S[L.LOCATING + l] == 0.0:  # a crossing inside this step: bracket it
                    g0, _, g0_force = _event_min(S, L.S0, l, a, b, p, m, q, force_end, t_max)
                    S[L.LOCATING + l] = 1.0
                    h_lo[l], g_lo[l] = 0.0, max(g0, 0.0)
                    h_hi[l], g_hi[l] = h, min(g1, 0.0)
                    side[l] = 0
                    # first guess: the Hermite cubic of the event that ends the step (the
                    # min of several is not smooth where another one was smallest)
                    gp0 = _event_part(S, L.S0, l, part, g0_force, t_max)
                    gp1 = _event_part(S, L.S1, l, part, g1_force, t_max)
                    if gp0 > 0.0 and gp1 < 0.0:
                        slope0 = _event_slope(S, L.S0, L.FS0, l, part, gp0, a, b, p, m, q, h,
                                              True)
                        slope = _event_slope(S, L.S1, L.FS1, l, part, gp1, a, b, p, m, q, h,
                                             True)
                        guess = _hermite_root(gp0, slope0, gp1, slope, h)
                elif g1 > 0.0:
                    h_lo[l], g_lo[l] = h, g1
                    if side[l] == 1:
                        g_hi[l] *= 0.5
                    side[l] = 1
                elif g1 < 0.0:
                    h_hi[l], g_hi[l] = h, g1
                    if side[l] == -1:
                        g_lo[l] *= 0.5
                    side[l] = -1
                # Newton on the step length (slope of the event along the solution), kept inside
                # the bracket; else the Illinois secant; else bisection
                if slope != slope:
                    slope = _event_slope(S, L.S1, L.FS1, l, part, g1, a, b, p, m, q, h, True)
                width = h_hi[l] - h_lo[l]
                hn = h - g1 / slope if slope != 0.0 else -1.0
                # a Newton step this short ends the search: the first-order extrapolation
                # along the solution to it errs by O(step^2), far below the tolerance
                newton_step = hn - h
                tol = 4e-16 * (S[L.SIG + l] + h_hi[l])
                # (the bracket widened by tol: a Newton step below rounding may land on its end)
                close = (h_lo[l] - tol <= hn <= h_hi[l] + tol and abs(newton_step) <= ext * h
                         and nsteps <= _MAX_STEPS)
                if h_lo[l] < guess < h_hi[l]:
                    hn = guess
                if not h_lo[l] < hn < h_hi[l]:
                    hn = h_lo[l] - g_lo[l] * width / (g_hi[l] - g_lo[l])
                if not h_lo[l] < hn < h_hi[l]:
                    hn = 0.5 * (h_lo[l] + h_hi[l])
                if not (g1 == 0.0 or close or abs(hn - h) <= tol or width <= tol
                        or nsteps > _MAX_STEPS):
                    S[L.H + l] = hn
                    continue
                if close and g1 != 0.0:
                    for c in range(nv):
                        S[L.S1 + c * _SLOTS + l] += newton_step * S[L.FS1 + c * _SLOTS + l]
                k = idx[l]
                s1, v1, t1 = S[L.S1 + l], S[L.V1 + l], S[L.T1 + l]
                sep = t1 < t_max * (1.0 - 1e-12) and nsteps <= _MAX_STEPS
                sep_out[k] = sep
                e_out[k] = min(max(-v1, 0.0), 1.0) if sep else 0.0  # e <= 1: energy
                tc_out[k] = t1 if sep else math.inf
                res_out[k] = max(s1, 0.0) ** m
                w_out[k] = S[L.W1 + l] if nv == 4 else math.nan
                steps_out[k] = int(nsteps)
                if nxt < hi:
                    _load(S, l, nxt, alpha, beta, idx, force_end, p, m, nv)
                    nxt += 1
                    continue
                n -= 1  # move the last live lane here (it was handled already)
                if l < n:
                    for f in range(L.N_FIELDS):
                        S[f * _SLOTS + l] = S[f * _SLOTS + n]
                    h_lo[l], h_hi[l], g_lo[l], g_hi[l] = h_lo[n], h_hi[n], g_lo[n], g_hi[n]
                    side[l], idx[l] = side[n], idx[n]

    return solve_range


_SOLVERS: dict[tuple[int, int, int, bool], object] = {}


def _solver(m: int, n_damp: int, nv: int, relax: bool):
    """The compiled solver for these constants (built on first use)."""
    key = (m, n_damp, nv, relax)
    if key not in _SOLVERS:
        _SOLVERS[key] = _make_solver(*key)
    return _SOLVERS[key]


@_jit
def _load(S, l, k, alpha, beta, idx, force_end, p, m, nv):
    """Put collision k into lane l at x = 0, x' = 1 (nv components: s, v, t and maybe W)."""
    a = alpha[k]
    b = beta[k]
    S[L.ALPHA + l] = a
    S[L.BETA + l] = b
    S[L.H + l] = _first_step(b, m)
    y = (0.0, 1.0, 0.0, 0.0)
    f = rhs_sigma(0.0, 1.0, 0.0, a, b, p, m)
    for c in range(nv):
        S[L.S0 + c * _SLOTS + l] = y[c]
        S[L.FS0 + c * _SLOTS + l] = f[c]
    S[L.SIG + l] = 0.0
    S[L.REJECTED + l] = 0.0
    S[L.LOCATING + l] = 0.0
    S[L.SPECIAL + l] = 0.0
    S[L.NSTEPS + l] = 0.0
    S[L.ACTIVE_FORCE + l] = 1.0 if force_end and a > 0.0 else 0.0
    idx[l] = k


def solve_batch(
    lp: LawParams, alpha: ArrayLike, end: str = "force", *, beta: ArrayLike | None = None,
    rtol: float = BATCH_RTOL, dissipated: bool = True,
) -> BatchResult:
    """Solve every collision of a batch (contract of :class:`~viscontact.solvers.base.SolveFn`).

    Args:
        lp: the resolved law (p, m; its beta unless ``beta`` is given).
        alpha: damping constants, any shape, validated finite and >= 0 by the caller.
        end: ``"force"`` (first zero of the force) or ``"overlap"`` (x back to 0).
        beta: relaxation times tau / T, broadcast against ``alpha`` (default ``lp.beta``).
        rtol: relative tolerance of the step-size control (absolute: rtol / 100).
        dissipated: False: the damping work is not integrated (``dissipated`` is NaN), which
            saves a quarter of the arithmetic when only e, t_c are wanted.

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
    force_end = end == "force" and not force_end_is_overlap_end(lp)
    n_damp = int(m * p) if m * p == int(m * p) and 1.5 * m < INT_POW_LIMIT else -1
    if not 0 <= n_damp < INT_POW_LIMIT:
        n_damp = -1
    if n:
        # a few chunks per thread: balanced, and few half-empty tails of slots
        threads = numba.get_num_threads()
        chunk = max(_CHUNK, -(-n // (4 * threads)))
        key = (m, n_damp, 4 if dissipated else 3, bool(np.any(b > 0.0)))
        solve_range = _solver(*key)

        def args(lo: int) -> tuple:
            return (a, b, lo, min(n, lo + chunk), p, q, force_end, rtol, rtol * 1e-2, T_MAX, e,
                    tc, res, w, sep, steps)

        # compiled before the threads start, once for the processes that start together
        compile_once(solve_range, args(0), tag=str(key))

        def run(lo: int) -> None:
            solve_range(*args(lo))

        starts = range(0, n, chunk)
        if threads == 1 or len(starts) == 1:
            for lo in starts:
                run(lo)
        else:  # the compiled solver releases the GIL: chunks run in parallel
            with ThreadPoolExecutor(threads) as pool:
                list(pool.map(run, starts))
        over = np.flatnonzero(steps > _MAX_STEPS)
        if over.size:
            raise ValueError(
                f"alpha = {a[over[0]]:g} (beta = {b[over[0]]:g}) damps so strongly that the "
                f"solver gave up after {_MAX_STEPS} steps; alpha in [0, 1000] is supported "
                "(viscontact.physics.domain)")
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
