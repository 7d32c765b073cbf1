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

__all__ = [
    "relaxation", "ipow", "spow", "spring_s", "damping_s", "force_s", "force", "rhs_sigma",
    "end_force_event",
]

_jit = numba.njit(cache=True, fastmath=False, nogil=True)


#: exp(-40) < 5e-18: beyond t = 40 beta the factor g is 1 to double precision
_RELAXED = 40.0


@_jit
def _expm1_neg(y: float) -> float:
    """exp(-y) - 1 for 0 <= y <= 40 without library calls (so it vectorises across lanes).

    Taylor series of expm1 at z = -y/128 (|z| <= 0.32, truncation < 1e-19), then seven
    doublings expm1(2z) = w (2 + w), which carry no cancellation.
    """
    z = -y * (1.0 / 128.0)
    w = 1.0
    for n in range(15, 1, -1):  # Horner: z (1 + z/2 (1 + z/3 (... (1 + z/15))))
        w = 1.0 + z * w / n
    w = z * w
    for _ in range(7):
        w = w * (2.0 + w)
    return w


@_jit
def relaxation(t: float, beta: float) -> float:
    """g(t) = 1 - exp(-t/beta), the Jian switch-on factor; 1 when beta = 0 (KK)."""
    if beta <= 0.0:
        return 1.0
    return -_expm1_neg(min(t / beta, _RELAXED))


@_jit
def ipow(s: float, n: int) -> float:
    """s^n for an integer n >= 0 by binary powering: straight-line code for n < 32."""
    r = 1.0
    b = s
    for bit in range(5):
        r *= b if (n >> bit) & 1 else 1.0
        b *= b
    for _ in range(n >> 5):  # b = s^32 here
        r *= b
    return r


@_jit
def spow(s: float, k: float) -> float:
    """s^k: a signed integer power when k is integral (smooth through 0), else |s|^k."""
    ki = int(k)
    if ki == k and ki >= 0:
        return ipow(s, ki)
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


@_jit
def end_force_event(
    s: float, v: float, t: float, alpha: float, beta: float, p: float, m: int, q: float, root: float
) -> float:
    """Zero-force end event: (F / s^q)^(1/k) (signed), k = 3m/2 - q, ``root`` = 1/k (or 1).

    The spring term is continued oddly through s = 0, so the function changes sign exactly
    once near the end even when a step jumps past x = 0; the k-th root keeps the zero simple
    when alpha -> 0 (where F / s^q tends to s^k).
    """
    a_s = abs(s)
    h = math.copysign(spring_s(a_s, m, q), s) + damping_s(a_s, v, t, alpha, beta, p, m, q)
    if root == 1.0:
        return h
    return math.copysign(abs(h) ** root, h)
