"""The force arithmetic: pure scalar functions, compiled, shared by every solver.

One expression of the force law lives here (:func:`force_s`); everything else (the
collision solver, the histories, calibration, a future many-particle engine) calls it.

Non-dimensional law (SPEC section 2), with x = delta/(T v_i), t = t/T, v = x':

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

__all__ = ["relaxation", "spow", "spring_s", "damping_s", "force_s", "force", "rhs_sigma"]

_jit = numba.njit(cache=True, fastmath=False, nogil=True)


@_jit
def relaxation(t: float, beta: float) -> float:
    """g(t) = 1 - exp(-t/beta), the Jian switch-on factor; 1 when beta = 0 (KK)."""
    if beta <= 0.0:
        return 1.0
    return -math.expm1(-t / beta)


@_jit
def spow(s: float, k: float) -> float:
    """s^k: a signed integer power when k is integral (smooth through 0), else |s|^k."""
    ki = int(k)
    if ki == k:
        r = 1.0
        for _ in range(ki):
            r *= s
        return r
    return abs(s) ** k


@_jit
def spring_s(s: float, m: int, q: float = 0.0) -> float:
    """Hertz spring force x^(3/2) at x = s^m (non-dimensional), divided by s^q."""
    return spow(s, 1.5 * m - q)


@_jit
def damping_s(
    s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int, q: float = 0.0
) -> float:
    """Damping force alpha g(t) x^p x' at x = s^m (non-dimensional), divided by s^q."""
    return alpha * relaxation(t, beta) * spow(s, m * p - q) * v


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


@_jit
def force(x: float, v: float, t: float, alpha: float, beta: float, p: float) -> float:
    """F^ at overlap x >= 0, velocity v = x', time t since contact start (all non-dimensional)."""
    return force_s(max(x, 0.0), v, t, alpha, beta, p, 1)


@_jit
def rhs_sigma(s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int):
    """Right-hand side in sigma-time: (ds, dv, dt, dW), W the dissipated work (units m* v_i^2)."""
    jac = m * spow(s, m - 1.0)  # dt/dsigma
    damp = damping_s(s, v, t, alpha, beta, p, m)
    return v, -jac * (spring_s(s, m) + damp), jac, jac * damp * v
