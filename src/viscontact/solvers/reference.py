"""Reference solver: scipy's DOP853 on the regularised sigma-time equations.

The substitution x = s^m, dt = m s^(m-1) dsigma (see :mod:`viscontact.physics.kernels`) makes the
right-hand side polynomial, so an 8th-order Runge-Kutta method keeps its order through
the start (x = 0) and the end of contact; the end is an event located on the dense
output by a bracketing root finder (scipy), which stays exact where the force returns
to zero tangentially (alpha = 0): there the zero of s is a simple root in sigma.
"""

from __future__ import annotations

import importlib
import itertools
import math
import sys
import types

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from ..physics.kernels_py import python_kernels
from ..physics.laws import LawParams
from .base import DEFAULT_RTOL, T_MAX, Contact, force_end_is_overlap_end

_HISTORY_POINTS = 801  # samples in each history, uniform in t
_KERNELS = __package__.rpartition(".")[0] + ".physics.kernels"  # the compiled kernels
#: solves in plain Python before this process loads the compiled kernels: numba's start-up
#: (about 0.5 s) is what 20 to 50 solves lose in plain Python (10 to 25 ms each)
PLAIN_SOLVES = 8
_solve_count = itertools.count()
#: alpha t^ up to which this solver integrates (an explicit method takes ~alpha t^ / 3 steps on
#: a contact damped at rate ~alpha): a few thousand steps, well under a second.  A contact still
#: going at t^ = min(T_MAX, REF_WORK / alpha) (heavily damped, zero-overlap end, creeping
#: back) is finished by the compiled batch solver at the same tolerance: its scalars come
#: from there, its histories cover [0, that time].
REF_WORK = 1.0e4


def _event(fn, terminal: bool, direction: float):
    fn.terminal = terminal
    fn.direction = direction
    return fn


def kernels() -> types.ModuleType:
    """The kernels for the next solve: :mod:`viscontact.physics.kernels` (compiled) once this process
    has loaded it or has solved :data:`PLAIN_SOLVES` collisions, else the same functions as
    plain Python (:mod:`viscontact.physics.kernels_py`).

    A process that solves a few collisions (``viscontact collide``) then skips numba's
    start-up; the numbers are the same either way (tested).
    """
    compiled = sys.modules.get(_KERNELS)
    if compiled is not None:
        return compiled
    if next(_solve_count) < PLAIN_SOLVES:
        return python_kernels()
    return importlib.import_module(_KERNELS)


def solve_reference(
    lp: LawParams, alpha: float, end: str, *, rtol: float = DEFAULT_RTOL, detail: bool = True
) -> Contact:
    """Solve one collision (contract in :class:`viscontact.solvers.base.SolveFn`)."""
    p, beta, m = lp.p, lp.beta, lp.m
    t_stop = T_MAX if alpha * T_MAX <= REF_WORK else REF_WORK / alpha
    k = kernels()
    rhs_sigma, force_s, end_force_event = k.rhs_sigma, k.force_s, k.end_force_event

    # Python floats, not numpy scalars: faster through the plain-Python kernels, and the
    # same numbers through the compiled ones
    def fun(_sig, y):
        s, v, t, _w = y.tolist()
        return rhs_sigma(s, v, t, alpha, beta, p, m)

    def f_of(y):
        s, v, t, _w = y.tolist()
        return force_s(s, v, t, alpha, beta, p, m)

    events = [
        _event(lambda _s, y: y[0], True, -1.0),  # x = 0
        _event(lambda _s, y: y[2] - t_stop, True, 1.0),  # give up: no separation (or hand over)
        _event(lambda _s, y: y[1], False, -1.0),  # x' = 0: maximum overlap
    ]
    if end == "force" and alpha > 0 and not force_end_is_overlap_end(lp):
        q = min(m * p, 1.5 * m)

        def zero_force(_s, y):
            s, v, t, _w = y.tolist()
            return end_force_event(s, v, t, alpha, beta, p, m, q)

        events.append(_event(zero_force, True, -1.0))
    # Jian with tiny beta switches damping on at t ~ beta: do not step over it.
    first = 1e-2 if beta <= 0 else min(1e-2, 0.1 * beta ** (1.0 / m))
    sol = solve_ivp(
        fun,
        (0.0, math.inf),
        np.array([0.0, 1.0, 0.0, 0.0]),
        method="DOP853",
        rtol=rtol,
        atol=rtol * 1e-2,
        events=events,
        dense_output=detail,
        first_step=first,
    )
    if sol.status == -1:  # pragma: no cover - integration failure is a bug, not user input
        raise RuntimeError(f"integration failed: {sol.message}")
    s_end, v_end, t_end, w_end = sol.y[:, -1]
    separated = sol.t_events[1].size == 0
    if not separated and t_stop < T_MAX:  # a long creep: the compiled solver finishes it
        from .batch import solve_batch

        r = solve_batch(lp, np.array([alpha]), end, rtol=rtol)
        contact = Contact(e=float(r.e[0]), tc=float(r.tc[0]), separated=bool(r.separated[0]),
                          residual=float(r.residual[0]), dissipated=float(r.dissipated[0]))
    else:
        contact = Contact(
            e=min(max(-v_end, 0.0), 1.0) if separated else 0.0,  # e <= 1: energy
            tc=t_end if separated else math.inf,
            separated=separated,
            residual=max(s_end, 0.0) ** m,
            dissipated=w_end,
        )
    if not detail:
        return contact
    if sol.t_events[2].size:
        y_max = sol.y_events[2][0]
        contact.xmax, contact.t_xmax = y_max[0] ** m, y_max[2]
    _fill_peak_force(contact, sol, f_of)
    _fill_history(contact, sol, m, f_of)
    return contact


def _dense_samples(sol, per_step: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """sigma points subdividing every accepted step, and the state there (4 x n)."""
    knots = sol.t
    frac = np.linspace(0.0, 1.0, per_step, endpoint=False)
    sig = (knots[:-1, None] + np.diff(knots)[:, None] * frac).ravel()
    sig = np.append(sig, knots[-1])
    ys = sol.sol(sig)
    ys[:, -1] = sol.y[:, -1]
    return sig, ys


def _fill_peak_force(contact: Contact, sol, f_of) -> None:
    """F_max over the contact: per-step sampling, then Brent refinement around the best sample."""
    sig, ys = _dense_samples(sol)
    fs = np.array([f_of(ys[:, i]) for i in range(sig.size)])
    i = int(np.argmax(fs))
    best_sig, best_f = sig[i], fs[i]
    if 0 < i < sig.size - 1:
        res = minimize_scalar(
            lambda z: -f_of(sol.sol(z)), bounds=(sig[i - 1], sig[i + 1]), method="bounded",
            options={"xatol": 1e-13 * max(1.0, abs(sig[i]))},
        )
        if -res.fun > best_f:
            best_sig, best_f = res.x, -res.fun
    contact.fmax = float(best_f)
    contact.t_fmax = float(sol.sol(best_sig)[2])


def _fill_history(contact: Contact, sol, m: int, f_of) -> None:
    """Histories on a grid uniform in t (sigma found by inverting the monotone t(sigma))."""
    sig_d, ys_d = _dense_samples(sol)
    t_grid = np.linspace(0.0, ys_d[2, -1], _HISTORY_POINTS)
    sig = np.interp(t_grid, ys_d[2], sig_d)
    ys = sol.sol(sig)
    ys[:, 0], ys[:, -1] = sol.sol(sol.t[0]), sol.y[:, -1]
    s, v, t = ys[0], ys[1], ys[2]
    contact.history = {
        "t": t,
        "x": np.where(s > 0, np.abs(s) ** m, 0.0),
        "v": v,
        "f": np.array([f_of(ys[:, i]) for i in range(sig.size)]),
    }
