"""The force arithmetic: pure scalar functions, compiled, shared by every solver.

One expression of the force law lives here (:func:`force_s`); everything else (the
collision solver, the histories, calibration, a future many-particle engine) calls it.

Non-dimensional law (Jian et al., Powder Technol. 356 (2019) 735), with x = delta/(T v_i), t = t/T, v = x':

    F = x^(3/2) + alpha g(t) x^p v,     g(t) = 1 - exp(-t/beta)  (beta > 0),  g = 1 (beta = 0)

The solver works with x = s^m and a new time sigma, dt = m s^(m-1) d(sigma), which makes
the equations polynomial in s (for m p integer) and removes the singular points at x = 0:

    ds/dsigma = v
    dv/dsigma = -m s^(m-1) F,     F = s^(3m/2) + alpha g(t) s^(m p) v
    dt/dsigma = m s^(m-1)

Powers with integer exponents are evaluated as signed integer powers so that the
right-hand side continues smoothly through s = 0 (where the zero-overlap contact ends).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = [
    "relaxation", "ipow", "spow", "damping_term", "spring_s", "damping_s", "force_s", "force",
    "rhs_sigma", "rhs_sigma_int", "force_s_int", "end_force_event", "INT_POW_LIMIT",
]

_jit = numba.njit(cache=True, fastmath=False, nogil=True, error_model="numpy")
# Inlined at numba IR level into every caller, so that loops over lanes vectorise.
_inline = numba.njit(cache=True, fastmath=False, nogil=True, error_model="numpy", inline="always")


#: exp(-40) < 5e-18: beyond t = 40 beta the factor g is 1 to double precision
_RELAXED = 40.0
#: nodes of the relaxation table per unit of t / beta
_RELAX_NODES_PER_UNIT = 16
_RELAX_SPACING = 1.0 / _RELAX_NODES_PER_UNIT
_RELAX_JS = range(int(_RELAXED * _RELAX_NODES_PER_UNIT) + 1)
#: exp(-j/16) and 1 - exp(-j/16) at the nodes (libm: correctly rounded to within an ulp)
_RELAX_EXP = np.array([math.exp(-j * _RELAX_SPACING) for j in _RELAX_JS])
_RELAX_GAP = np.array([-math.expm1(-j * _RELAX_SPACING) for j in _RELAX_JS])
#: 1/(k+1)!, k = 0..8: expm1(u) = u sum_k u^k/(k+1)!, truncation (1/16)^9/10! < 5e-18
_INV_FACTORIALS = np.array([1.0 / math.factorial(k + 1) for k in range(9)])


@_inline
def relaxation(t: float, beta: float) -> float:
    """g(t) = 1 - exp(-t/beta), the Jian switch-on factor (Jian et al. 2019); 1 when beta = 0 (KK).

    Without library calls, so that it vectorises across lanes: with y = t/beta = j/16 + r,
    0 <= r < 1/16 (y capped at 40, where g = 1 to double precision),

        g = (1 - exp(-j/16)) - exp(-j/16) expm1(-r),

    a sum of two non-negative terms (no cancellation), the first two from a table, expm1(-r)
    from nine terms of its Taylor series (Horner): within a few ulp of g.

    A branch, not a select: scalar callers (the end-of-contact events) skip all this when
    beta = 0, and loops over lanes still vectorise (the compiler turns it into a select);
    it never divides by 0, which plain Python (:mod:`viscontact.physics.kernels_py`) would raise on.
    """
    if beta > 0.0:
        y = t * (1.0 / beta)  # 1/beta: one division per lane for all of a step's stages
        y = y if y < _RELAXED else _RELAXED  # also NaN
        j = max(int(y * _RELAX_NODES_PER_UNIT), 0)
        u = j * _RELAX_SPACING - y  # -r, exact (Sterbenz)
        w = _INV_FACTORIALS[8]
        for k in range(7, -1, -1):
            w = _INV_FACTORIALS[k] + u * w
        return _RELAX_GAP[j] - _RELAX_EXP[j] * (u * w)
    return 1.0


#: :func:`ipow` handles exponents below this in straight-line code
INT_POW_LIMIT = 64


@_inline
def ipow(s: float, n: int) -> float:
    """s^n for an integer 0 <= n < INT_POW_LIMIT: binary powering without branches or loops
    of variable length, so that it vectorises across lanes."""
    r = 1.0
    b = s
    for bit in range(6):
        r *= b if (n >> bit) & 1 else 1.0
        b *= b
    return r


@_jit
def spow(s: float, k: float) -> float:
    """s^k: a signed integer power when k is integral (smooth through 0), else |s|^k."""
    ki = int(k)
    if ki == k and 0 <= ki < INT_POW_LIMIT:
        return ipow(s, ki)
    if ki == k and ki > 0:
        r = 1.0
        for _ in range(ki):
            r *= s
        return r
    return abs(s) ** k


@_inline
def damping_term(x_pow_p: float, v: float, t: float, alpha: float, beta: float) -> float:
    """The damping force alpha g(t) x^p x', given x^p (or s^(m p - q) for the scaled form)."""
    return alpha * relaxation(t, beta) * x_pow_p * v


@_jit
def spring_s(s: float, m: int, q: float = 0.0) -> float:
    """Hertz spring force x^(3/2) at x = s^m (non-dimensional), divided by s^q."""
    return spow(s, 1.5 * m - q)


@_jit
def damping_s(
    s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int, q: float = 0.0
) -> float:
    """Damping force alpha g(t) x^p x' at x = s^m (non-dimensional), divided by s^q."""
    return damping_term(spow(s, m * p - q), v, t, alpha, beta)


@_jit
def force_s(
    s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int, q: float = 0.0
) -> float:
    """Non-dimensional contact force F^ = x^(3/2) + alpha g(t) x^p x' at x = s^m, over s^q.

    With q = min(m p, 3m/2) the common factor s^q is removed: the result has the sign of
    F for s > 0 and a simple zero where the force vanishes inside the contact, which makes
    it a well-conditioned end-of-contact event function.
    """
    return spring_s(s, m, q) + damping_s(s, v, t, alpha, beta, p, m, q)


@_inline
def force_s_int(s: float, v: float, t: float, alpha: float, beta: float, k_spring: int,
                k_damp: int) -> float:
    """:func:`force_s` for integer exponents k_spring = 3m/2 - q, k_damp = m p - q (< 64):
    straight-line code that vectorises across lanes."""
    return ipow(s, k_spring) + damping_term(ipow(s, k_damp), v, t, alpha, beta)


@_jit
def force(x: float, v: float, t: float, alpha: float, beta: float, p: float) -> float:
    """F^ at overlap x >= 0, velocity v = x', time t since contact start (all non-dimensional)."""
    return force_s(max(x, 0.0), v, t, alpha, beta, p, 1)


@_inline
def _rhs_from_powers(s_m1: float, s_spring: float, s_damp: float, v: float, t: float,
                     alpha: float, beta: float, m: int):
    """(ds, dv, dt, dW) from s^(m-1), s^(3m/2) = x^(3/2) and s^(m p) = x^p."""
    jac = m * s_m1  # dt/dsigma
    damp = damping_term(s_damp, v, t, alpha, beta)
    return v, -jac * (s_spring + damp), jac, jac * damp * v


@_jit
def rhs_sigma(s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int):
    """Right-hand side in sigma-time: (ds, dv, dt, dW), W the dissipated work (units m* v_i^2)."""
    return _rhs_from_powers(spow(s, m - 1.0), spring_s(s, m), spow(s, m * p), v, t, alpha, beta, m)


@_inline
def rhs_sigma_int(s: float, v: float, t: float, alpha: float, beta: float, n_damp: int, m: int):
    """:func:`rhs_sigma` for an integer n_damp = m p < INT_POW_LIMIT: straight-line code
    (no branches on the exponents, no library calls), which vectorises across lanes."""
    return _rhs_from_powers(ipow(s, m - 1), ipow(s, (3 * m) // 2), ipow(s, n_damp), v, t,
                            alpha, beta, m)


@_jit
def end_force_event(
    s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int, q: float
) -> float:
    """Zero-force end event, positive during the contact, with a simple zero at F = 0.

    With q = min(m p, 3m/2) and k = 3m/2 - q, F / s^q = s^k + A, where A is the scaled
    damping term (free of s when k > 0).  For k > 0 the event is the gap s - (-A)^(1/k)
    (just s while A >= 0): its zero is simple, with slope ds/dsigma = v, even as alpha -> 0
    where F / s^q itself tends to the k-fold zero of s^k.  For k = 0 it is F / s^q = 1 + A.
    Only |s| enters A, so the function continues smoothly when a step jumps past x = 0.
    """
    k = 1.5 * m - q
    damp = damping_s(abs(s), v, t, alpha, beta, p, m, q)
    if k == 0.0:
        return spring_s(abs(s), m, q) + damp
    if damp >= 0.0:
        return s
    return s - (math.sqrt(-damp) if k == 2.0 else (-damp) ** (1.0 / k))  # sqrt: KK, Jian
