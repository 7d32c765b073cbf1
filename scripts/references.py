"""Independent references: closed forms and a high-precision Taylor-series solve (mpmath).

Nothing here calls viscontact: the references must be able to disagree with it.
"""

from __future__ import annotations

import functools
import math

import mpmath as mp

#: Undamped contact time (4/5)^(3/5) sqrt(pi) Gamma(2/5) / Gamma(9/10) and peak overlap (5/4)^(2/5).
TC_HERTZ = float((mp.mpf(4) / 5) ** (mp.mpf(3) / 5) * mp.sqrt(mp.pi) * mp.gamma(mp.mpf(2) / 5)
                 / mp.gamma(mp.mpf(9) / 10))
XMAX_HERTZ = float((mp.mpf(5) / 4) ** (mp.mpf(2) / 5))


def hunt_e(alpha: float) -> float:
    """Hunt-Crossley exact relation (1 + e) alpha = ln((1 + alpha) / (1 - alpha e)), solved for e."""
    if alpha == 0:
        return 1.0
    with mp.workdps(40):
        a = mp.mpf(alpha)
        f = lambda e: (1 + e) * a - mp.log((1 + a) / (1 - a * e))  # noqa: E731
        hi = min(mp.mpf(1), 1 / a) * (1 - mp.mpf(10) ** -30)
        return float(mp.findroot(f, (mp.mpf(0), hi), solver="anderson"))


def tsuji_overlap_alpha(e: float) -> float:
    """Tsuji, zero-overlap end: alpha = -sqrt(5) ln e / sqrt(ln^2 e + pi^2)."""
    le = math.log(e)
    return -math.sqrt(5) * le / math.sqrt(le * le + math.pi**2)


def tsuji_force_e(alpha: float) -> float:
    """Tsuji, zero-force end (linear oscillator in x^(5/4)); three damping regimes."""
    z = alpha / math.sqrt(5)
    if z < 1 / math.sqrt(2):
        w = math.sqrt(1 - z * z)
        return math.exp(-(z / w) * (math.pi - math.atan(2 * z * w / (1 - 2 * z * z))))
    if z < 1:
        w = math.sqrt(1 - z * z)
        return math.exp(-(z / w) * math.atan(2 * z * w / (2 * z * z - 1)))
    big_w = math.sqrt(z * z - 1)
    return ((z - big_w) / (z + big_w)) ** (z / big_w)


def taylor_reference(p: float, alpha: float, beta: float, end: str, t_stop: float = 100.0,
                     dps: int = 22) -> tuple[float, float] | None:
    """(e, t_c) by mpmath's Taylor-series ODE solver at ``dps`` digits; None if no end by t_stop.

    Solves x'' = -(x^(3/2) + alpha g(t) x^p x') in the regular variables x = s^2
    (s^4 when 2p is not an integer), dt = m s^(m-1) dsigma, and finds the end of contact with
    mpmath's root finder on the series solution.  Both ends of one collision read the same
    solution (:func:`_taylor_solution`): the second end continues where the first stopped.
    """
    with mp.workdps(dps):
        sol, force = _taylor_solution(p, alpha, beta, dps)
        if end == "overlap":
            fn = lambda z: sol(z)[0]  # noqa: E731
        else:
            fn = lambda z: force(*sol(z))  # noqa: E731
        h = mp.mpf("0.02")
        sig = h
        while fn(sig) >= 0:
            h = mp.mpf("0.02") * (1 + sig)  # sigma runs fast once the contact creeps
            sig += h
            if sol(sig)[2] > t_stop:
                return None
        try:
            root = mp.findroot(fn, (sig - h, sig), solver="anderson")
        except ValueError:  # a very flat zero (tiny alpha) defeats findroot: bisect instead
            lo, hi = sig - h, sig
            while hi - lo > mp.mpf(10) ** (2 - dps):
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if fn(mid) >= 0 else (lo, mid)
            root = hi
        s, v, t = sol(root)
        return float(-v), float(t)


# The last few solutions, kept for the other end of the same collision (its tests run one
# after the other).  Exactly the numbers of a fresh solve: mpmath's odefun computes its series
# segments one after the other from the start, each from the last one's end, whichever point
# is asked first, and evaluates a point on the segment that holds it.  A few, not all: a
# solution to t = 20 holds megabytes of series at the series' working precision.
@functools.lru_cache(maxsize=4)
def _taylor_solution(p: float, alpha: float, beta: float, dps: int):
    """(sol, force): mpmath's series solution sigma -> (s, v, t) of :func:`taylor_reference`'s
    system and the contact force F(s, v, t); call both inside ``mp.workdps(dps)``."""
    m = 2 if float(2 * p).is_integer() else 4
    with mp.workdps(dps):
        a, b = mp.mpf(alpha), mp.mpf(beta)

        def force(s, v, t):
            g = 1 if b == 0 else -mp.expm1(-t / b)
            return s ** (3 * m // 2) + a * g * s ** int(round(m * p)) * v

        def rhs(_sig, y):
            s, v, t = y
            j = m * s ** (m - 1)
            return [v, -j * force(s, v, t), j]

        return mp.odefun(rhs, 0, [mp.mpf(0), mp.mpf(1), mp.mpf(0)]), force
