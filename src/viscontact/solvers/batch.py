"""Batch solver: many collisions at once, compiled, on every core.

Same equations as the reference solver (the regularised sigma-time system of
:mod:`viscontact.kernels`: x = s^m, dt = m s^(m-1) dsigma, polynomial in s for m p
integral) and the same end criteria, but no histories and no Python per collision:

- the batch is cut into chunks that a pool of threads shares (``numba.get_num_threads()``
  of them; the compiled solver releases the GIL); a thread
  advances up to ``_SLOTS`` collisions of its chunk in lockstep, their states stored as
  structure-of-arrays so that every stage is a plain loop over slots that the compiler
  vectorises; each slot has its own step size (Dormand-Prince 8(5,3), the tableau
  shipped with scipy's DOP853, and scipy's error norm and step control); a finished slot
  takes the next collision of the chunk, or the last live slot, so the cost is linear
  in the batch size and the memory a few arrays of it;
- with m p an integer (every named law, and ``power`` with p a multiple of 1/8) the
  right-hand side is :func:`viscontact.kernels.rhs_sigma_int`: straight-line code, no
  library calls (the relaxation factor of Jian uses an inline expm1); otherwise the
  general :func:`viscontact.kernels.rhs_sigma` (|s|^k by pow), slower;
- each shape of the equations (m, m p, whether some beta > 0, whether W is wanted) is
  compiled once with these as constants (:func:`_make_solver`): the integer powers fold
  to a few multiplications and an unused W (``dissipated=False``, as ``restitution``
  asks) costs nothing;
- the end of contact is an event g(y) = min(s, zero-force gap
  (:func:`viscontact.kernels.end_force_event`, zero-force end only), T_MAX - t)
  crossing zero from above; a step that crosses is not taken but shortened to the
  crossing by safeguarded Newton iterations on its length (first guess: the root of the
  cubic Hermite interpolant of the ending event over the step; slope of g along the
  solution by a central difference; Illinois secant or bisection when Newton leaves the
  bracket), each trial a full Runge-Kutta step from the step's start, so the end state
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
# The published Dormand-Prince 8(5,3) tableau, as shipped by scipy (not copied here).
from scipy.integrate._ivp import dop853_coefficients as _dop853

from ..kernels import (INT_POW_LIMIT, end_force_event, force_s, force_s_int, rhs_sigma,
                       rhs_sigma_int)
from ..laws import LawParams
from .base import END_CRITERIA, T_MAX, Contact

__all__ = ["BatchResult", "solve_batch", "solve_batch_one", "BATCH_RTOL"]

#: Default relative tolerance of the batch solver: meets |e - exact| <= 1e-9 (contract 1e-8).
BATCH_RTOL: float = 1e-9
#: Collisions advanced in lockstep by one thread (slots of structure-of-arrays state).
_SLOTS: int = 128
#: Fewest collisions per parallel work item (threads take chunks; slots refill within one).
_CHUNK: int = 2048
#: First step in sigma (the solution is a power series in sigma at the start).
_H0: float = 0.1
#: Steps (accepted, rejected or event trials) after which one collision is given up: damping
#: so strong that the explicit method needs ~ alpha steps (LH, zero-overlap end, alpha = 1e4
#: takes ~3e5; a few seconds at this limit).
_MAX_STEPS: int = 5_000_000

_NS = _dop853.N_STAGES  # 12 stages; the 13th evaluation is the first of the next step
_A = np.ascontiguousarray(_dop853.A[:_NS, :_NS])
_B = np.ascontiguousarray(_dop853.B)
_E3 = np.ascontiguousarray(_dop853.E3)
_E5 = np.ascontiguousarray(_dop853.E5)
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
def _event(s, v, t, alpha, beta, p, m, q, force_end, t_max, part=-1):
    """min of the end events, each positive during the contact (see module docstring);
    only event ``part`` (0: overlap, 1: time limit, 2: zero force) when it is >= 0."""
    if part == 0:
        return s
    if part == 1:
        return t_max - t
    if part == 2:
        return end_force_event(s, v, t, alpha, beta, p, m, q)
    g = min(s, t_max - t)
    if force_end and alpha > 0.0:  # undamped: F = 0 only where x = 0
        g = min(g, end_force_event(s, v, t, alpha, beta, p, m, q))
    return g


@_jit
def _event_part(s, v, t, alpha, beta, p, m, q, force_end, t_max):
    """Which event (the ``part`` of :func:`_event`) is the smallest."""
    part = 0 if s <= t_max - t else 1
    if force_end and alpha > 0.0:
        if end_force_event(s, v, t, alpha, beta, p, m, q) < min(s, t_max - t):
            part = 2
    return part


@_jit
def _event_slope(Y, K, row, l, alpha, beta, p, m, q, force_end, t_max, h, part=-1):
    """d(event)/dsigma at slot l of Y by a central difference along the solution, whose
    direction K[row] (the right-hand side at Y: K[_NS] at a step's end, K[0] at its start)
    every step computes anyway."""
    d = 1e-6 * h
    f = K[row, :, l]
    up = _event(Y[0, l] + d * f[0], Y[1, l] + d * f[1], Y[2, l] + d * f[2], alpha, beta, p, m,
                q, force_end, t_max, part)
    dn = _event(Y[0, l] - d * f[0], Y[1, l] - d * f[1], Y[2, l] - d * f[2], alpha, beta, p, m,
                q, force_end, t_max, part)
    return (up - dn) / (2.0 * d) if d > 0.0 else 0.0


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
def _rhs_slots(Y, K, i, n, a, b, p, m, n_damp, nv, relax):
    """K[i] = right-hand side at Y for slots 0..n-1 (straight-line over slots); inlined, so
    the constants of :func:`_make_solver` fold into it."""
    for l in range(n):
        bl = b[l] if relax else 0.0
        if n_damp >= 0:
            r = rhs_sigma_int(Y[0, l], Y[1, l], Y[2, l], a[l], bl, n_damp, m)
        else:
            r = rhs_sigma(Y[0, l], Y[1, l], Y[2, l], a[l], bl, p, m)
        K[i, 0, l] = r[0]
        K[i, 1, l] = r[1]
        K[i, 2, l] = r[2]
        if nv == 4:
            K[i, 3, l] = r[3]


@_inline
def _force_scaled_slots(Y, out, n, a, b, p, q, m, n_damp, k_spring, k_damp, relax):
    """out = F / s^q at Y for slots 0..n-1 (only its sign is used: end-of-contact test)."""
    for l in range(n):
        bl = b[l] if relax else 0.0
        if n_damp >= 0:
            out[l] = force_s_int(Y[0, l], Y[1, l], Y[2, l], a[l], bl, k_spring, k_damp)
        else:
            out[l] = force_s(Y[0, l], Y[1, l], Y[2, l], a[l], bl, p, m, q)


def _make_solver(m: int, n_damp: int, nv: int, relax: bool):
    """The compiled solver of one shape of the equations, with the exponents m and
    n_damp = m p (-1: not an integer, the general pow path), the state size nv (3: s, v, t;
    4: also the dissipated work W) and ``relax`` (False: every beta is 0, g = 1) as
    compile-time constants, so that the integer powers fold to a few multiplications and
    unused components cost nothing.  Built once per shape; numba caches each closure by
    its constants."""
    k_spring = (3 * m) // 2 - min(n_damp, (3 * m) // 2)  # F / s^q exponents (integer path)
    k_damp = n_damp - min(n_damp, (3 * m) // 2)

    # only numbers in the closure: numba caches it under their hash
    @numba.njit(cache=True, nogil=True, error_model="numpy")
    def solve_range(alpha, beta, lo, hi, p, q, force_end, rtol, atol, t_max,
                    e_out, tc_out, res_out, w_out, sep_out, steps_out):
        """Solve collisions lo..hi-1 in up to _SLOTS slots advanced in lockstep.

        Slots 0..n-1 are live; a finished slot takes the next collision, or, when none is left,
        the state of the last live slot (so the live slots stay contiguous and every loop over
        them is a plain vectorisable loop).
        """
        C = min(_SLOTS, hi - lo)
        ext = 1e-2 * math.sqrt(rtol)  # relative Newton step that ends the event search
        Y0 = np.zeros((nv, C))  # state at the start of the current step
        Y1 = np.zeros((nv, C))  # trial state at its end
        YS = np.zeros((nv, C))  # stage state
        E = np.zeros((nv, C))  # error estimate
        K = np.zeros((_NS + 1, nv, C))
        h, sig, a, b = np.zeros(C), np.zeros(C), np.zeros(C), np.zeros(C)
        err, fac, fend = np.zeros(C), np.zeros(C), np.zeros(C)
        active_force = np.zeros(C, dtype=np.bool_)  # zero-force event on (force end, alpha > 0)
        rejected = np.zeros(C, dtype=np.bool_)
        locating = np.zeros(C, dtype=np.bool_)
        special = np.zeros(C, dtype=np.bool_)  # crossing found or locating: handled one by one
        h_lo, h_hi, g_lo, g_hi = np.zeros(C), np.zeros(C), np.zeros(C), np.zeros(C)
        side = np.zeros(C, dtype=np.int64)  # Illinois: which end of the bracket moved last
        idx = np.zeros(C, dtype=np.int64)
        nsteps = np.zeros(C, dtype=np.int64)

        nxt = lo
        n = C
        for l in range(n):
            _load(l, nxt, alpha, beta, a, b, Y0, K, h, sig, rejected, locating, nsteps, idx,
                  active_force, force_end, p, m, nv)
            nxt += 1

        while n > 0:
            # --- one Runge-Kutta step in every live slot (plain loops over slots) ---
            for i in range(1, _NS + 1):
                last = i == _NS  # the solution; its right-hand side is the next step's first stage
                Yt = Y1 if last else YS
                u0, u1, u2, u3 = Yt[0], Yt[1], Yt[2], Yt[nv - 1]
                for j in range(i):
                    w = _B[j] if last else _A[i, j]
                    k0, k1, k2, k3 = K[j, 0], K[j, 1], K[j, 2], K[j, nv - 1]
                    if j == 0:
                        for l in range(n):
                            u0[l] = w * k0[l]
                            u1[l] = w * k1[l]
                            u2[l] = w * k2[l]
                            if nv == 4:
                                u3[l] = w * k3[l]
                    else:
                        for l in range(n):
                            u0[l] += w * k0[l]
                            u1[l] += w * k1[l]
                            u2[l] += w * k2[l]
                            if nv == 4:
                                u3[l] += w * k3[l]
                y0, y1, y2, y3 = Y0[0], Y0[1], Y0[2], Y0[nv - 1]
                for l in range(n):
                    hl = h[l]
                    u0[l] = y0[l] + hl * u0[l]
                    u1[l] = y1[l] + hl * u1[l]
                    u2[l] = y2[l] + hl * u2[l]
                    if nv == 4:
                        u3[l] = y3[l] + hl * u3[l]
                _rhs_slots(Yt, K, i, n, a, b, p, m, n_damp, nv, relax)
            # --- error estimate of the 8(5,3) pair (as scipy's DOP853): differences in YS
            # (5th order) and E (3rd order), then the norms over the components ---
            for j in range(_NS + 1):
                c5 = _E5[j]
                c3 = _E3[j]
                k0, k1, k2, k3 = K[j, 0], K[j, 1], K[j, 2], K[j, nv - 1]
                if j == 0:
                    for l in range(n):
                        YS[0, l] = c5 * k0[l]
                        YS[1, l] = c5 * k1[l]
                        YS[2, l] = c5 * k2[l]
                        if nv == 4:
                            YS[3, l] = c5 * k3[l]
                        E[0, l] = c3 * k0[l]
                        E[1, l] = c3 * k1[l]
                        E[2, l] = c3 * k2[l]
                        if nv == 4:
                            E[3, l] = c3 * k3[l]
                else:
                    for l in range(n):
                        YS[0, l] += c5 * k0[l]
                        YS[1, l] += c5 * k1[l]
                        YS[2, l] += c5 * k2[l]
                        if nv == 4:
                            YS[3, l] += c5 * k3[l]
                        E[0, l] += c3 * k0[l]
                        E[1, l] += c3 * k1[l]
                        E[2, l] += c3 * k2[l]
                        if nv == 4:
                            E[3, l] += c3 * k3[l]
            for l in range(n):
                e5 = 0.0
                e3 = 0.0
                for c in range(nv):
                    sc = atol + rtol * max(abs(Y0[c, l]), abs(Y1[c, l]))
                    e5 += (YS[c, l] / sc) ** 2
                    e3 += (E[c, l] / sc) ** 2
                err[l] = e5
                fac[l] = e3
            _force_scaled_slots(Y1, fend, n, a, b, p, q, m, n_damp, k_spring, k_damp, relax)
            # --- accept or reject (vectorised); crossings and locating slots are special ---
            for l in range(n):
                e5 = err[l]
                den = e5 + 0.01 * fac[l]
                en = abs(h[l]) * e5 / math.sqrt(den * nv) if den > 0.0 else 0.0
                ok = en <= 1.0  # False for NaN
                cross = (Y1[0, l] < 0.0) | (Y1[2, l] > t_max) | (active_force[l] & (fend[l] < 0.0))
                special[l] = locating[l] | (ok & cross)
                # err^(-1/8) by three square roots (vectorises; no pow)
                grow = _SAFETY / math.sqrt(math.sqrt(math.sqrt(en))) if en > 0.0 else _MAX_FACTOR
                grow = min(_MAX_FACTOR, grow)
                if rejected[l]:
                    grow = min(1.0, grow)
                shrink = max(_MIN_FACTOR, grow) if en == en else _MIN_FACTOR
                take = ok & ~special[l]
                for c in range(nv):
                    Y0[c, l] = Y1[c, l] if take else Y0[c, l]
                    K[0, c, l] = K[_NS, c, l] if take else K[0, c, l]
                sig[l] = sig[l] + h[l] if take else sig[l]
                hn = h[l] * (grow if ok else shrink)
                h[l] = h[l] if special[l] else hn
                rejected[l] = rejected[l] if special[l] else ~ok
                nsteps[l] += 1
            # --- one by one: bracket and locate the end, finish, refill or compact ---
            for l in range(n - 1, -1, -1):
                if not special[l]:
                    if nsteps[l] <= _MAX_STEPS:
                        continue
                    locating[l] = True  # give up on this collision: end it here
                    h_lo[l], h_hi[l], g_lo[l], g_hi[l] = 0.0, 0.0, 1.0, -1.0
                    h[l] = 0.0
                    continue
                g1 = _event(Y1[0, l], Y1[1, l], Y1[2, l], a[l], b[l], p, m, q, force_end, t_max)
                slope = _event_slope(Y1, K, _NS, l, a[l], b[l], p, m, q, force_end, t_max, h[l])
                guess = -1.0
                if not locating[l]:  # a crossing inside this step: bracket it on the step length
                    g0 = _event(Y0[0, l], Y0[1, l], Y0[2, l], a[l], b[l], p, m, q, force_end, t_max)
                    locating[l] = True
                    h_lo[l], g_lo[l] = 0.0, max(g0, 0.0)
                    h_hi[l], g_hi[l] = h[l], min(g1, 0.0)
                    side[l] = 0
                    # first guess: the Hermite cubic of the event that ends the step (the
                    # min of several is not smooth where another one was smallest)
                    part = _event_part(Y1[0, l], Y1[1, l], Y1[2, l], a[l], b[l], p, m, q,
                                       force_end, t_max)
                    gp0 = _event(Y0[0, l], Y0[1, l], Y0[2, l], a[l], b[l], p, m, q, force_end,
                                 t_max, part)
                    gp1 = _event(Y1[0, l], Y1[1, l], Y1[2, l], a[l], b[l], p, m, q, force_end,
                                 t_max, part)
                    if gp0 > 0.0 and gp1 < 0.0:
                        slope0 = _event_slope(Y0, K, 0, l, a[l], b[l], p, m, q, force_end, t_max,
                                              h[l], part)
                        slope1 = _event_slope(Y1, K, _NS, l, a[l], b[l], p, m, q, force_end,
                                              t_max, h[l], part)
                        guess = _hermite_root(gp0, slope0, gp1, slope1, h[l])
                elif g1 > 0.0:
                    h_lo[l], g_lo[l] = h[l], g1
                    if side[l] == 1:
                        g_hi[l] *= 0.5
                    side[l] = 1
                elif g1 < 0.0:
                    h_hi[l], g_hi[l] = h[l], g1
                    if side[l] == -1:
                        g_lo[l] *= 0.5
                    side[l] = -1
                # Newton on the step length (slope of the event along the solution), kept inside
                # the bracket; else the Illinois secant; else bisection
                width = h_hi[l] - h_lo[l]
                hn = h[l] - g1 / slope if slope != 0.0 else -1.0
                # a Newton step this short ends the search: the first-order extrapolation
                # along the solution to it errs by O(step^2), far below the tolerance
                newton_step = hn - h[l]
                close = (h_lo[l] < hn < h_hi[l] and abs(newton_step) <= ext * h[l]
                         and nsteps[l] <= _MAX_STEPS)
                if h_lo[l] < guess < h_hi[l]:
                    hn = guess
                if not h_lo[l] < hn < h_hi[l]:
                    hn = h_lo[l] - g_lo[l] * width / (g_hi[l] - g_lo[l])
                if not h_lo[l] < hn < h_hi[l]:
                    hn = 0.5 * (h_lo[l] + h_hi[l])
                tol = 4e-16 * (sig[l] + h_hi[l])
                if not (g1 == 0.0 or close or abs(hn - h[l]) <= tol or width <= tol
                        or nsteps[l] > _MAX_STEPS):
                    h[l] = hn
                    continue
                if close and g1 != 0.0:
                    for c in range(nv):
                        Y1[c, l] += newton_step * K[_NS, c, l]
                k = idx[l]
                sep = Y1[2, l] < t_max * (1.0 - 1e-12) and nsteps[l] <= _MAX_STEPS
                sep_out[k] = sep
                e_out[k] = max(-Y1[1, l], 0.0) if sep else 0.0
                tc_out[k] = Y1[2, l] if sep else math.inf
                res_out[k] = max(Y1[0, l], 0.0) ** m
                w_out[k] = Y1[nv - 1, l] if nv == 4 else math.nan
                steps_out[k] = nsteps[l]
                if nxt < hi:
                    _load(l, nxt, alpha, beta, a, b, Y0, K, h, sig, rejected, locating, nsteps, idx,
                          active_force, force_end, p, m, nv)
                    nxt += 1
                    continue
                n -= 1  # move the last live slot here (it was handled already)
                if l < n:
                    for c in range(nv):
                        Y0[c, l] = Y0[c, n]
                        Y1[c, l] = Y1[c, n]
                        K[0, c, l] = K[0, c, n]
                    h[l], sig[l], a[l], b[l] = h[n], sig[n], a[n], b[n]
                    active_force[l], rejected[l], locating[l] = active_force[n], rejected[n], locating[n]
                    h_lo[l], h_hi[l], g_lo[l], g_hi[l] = h_lo[n], h_hi[n], g_lo[n], g_hi[n]
                    side[l], idx[l], nsteps[l] = side[n], idx[n], nsteps[n]



    return solve_range


_SOLVERS: dict[tuple[int, int, int, bool], object] = {}


def _solver(m: int, n_damp: int, nv: int, relax: bool):
    """The compiled solver for these constants (built on first use)."""
    key = (m, n_damp, nv, relax)
    if key not in _SOLVERS:
        _SOLVERS[key] = _make_solver(*key)
    return _SOLVERS[key]

@_jit
def _load(l, k, alpha, beta, a, b, Y0, K, h, sig, rejected, locating, nsteps, idx, active_force,
          force_end, p, m, nv):
    """Put collision k into slot l at x = 0, x' = 1 (nv components: s, v, t and maybe W)."""
    a[l] = alpha[k]
    b[l] = beta[k]
    h[l] = _first_step(b[l], m)
    y = (0.0, 1.0, 0.0, 0.0)
    f = rhs_sigma(0.0, 1.0, 0.0, a[l], b[l], p, m)
    for c in range(nv):
        Y0[c, l] = y[c]
        K[0, c, l] = f[c]
    sig[l] = 0.0
    rejected[l] = False
    locating[l] = False
    nsteps[l] = 0
    idx[l] = k
    active_force[l] = force_end and a[l] > 0.0


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
    n_damp = int(m * p) if m * p == int(m * p) and 1.5 * m < INT_POW_LIMIT else -1
    if not 0 <= n_damp < INT_POW_LIMIT:
        n_damp = -1
    if n:
        # a few chunks per thread: balanced, and few half-empty tails of slots
        threads = numba.get_num_threads()
        chunk = max(_CHUNK, -(-n // (4 * threads)))
        solve_range = _solver(m, n_damp, 4 if dissipated else 3, bool(np.any(b > 0.0)))

        def run(lo: int) -> None:
            solve_range(a, b, lo, min(n, lo + chunk), p, q, end == "force", rtol, rtol * 1e-2,
                        T_MAX, e, tc, res, w, sep, steps)

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
                f"solver gave up after {_MAX_STEPS} steps; alpha up to about 1e4 is supported")
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
