"""Theory the DEM study is checked against (SPEC section 9).

* Haff's law for a freely cooling gas of smooth spheres with a constant restitution e:
  T(t) = T0 / (1 + t / tau0)^2,
  1 / tau0 = (2 sqrt(pi) / 3) (1 - e^2) g2 n sigma^2 sqrt(T0 / m),
  g2 = (1 - phi / 2) / (1 - phi)^3 (Enskog / Carnahan-Starling), T = m <v^2> / 3.
  P.K. Haff, J. Fluid Mech. 134 (1983) 401; N.V. Brilliantov, T. Poschel, Kinetic Theory of
  Granular Gases (Oxford 2004), chapter 6.
* Speed-dependent restitution 1 - e ~ v^q, q = (4 p - 1) / 5 for damping exponent p (small
  dissipation): T ~ t^(-2 / (1 + q)) at late times, t^(-5/3) for Kuwabara-Kono
  (Brilliantov & Poschel, Phys. Rev. E 61 (2000) 5573).
* A ball bouncing on a rigid plate: the exact sequence of single collisions (each one solved
  by :func:`viscontact.impact` at that bounce's impact speed with the calibrated c and tau),
  flights in closed form (apex h = v^2 / (2 g), flight time 2 v / g), gravity during contact
  neglected.

SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..dimensional import STANDARD_GRAVITY, check_positive, hertz_limit
from ..laws import lookup, resolve

__all__ = [
    "enskog_g2", "haff_tau0", "haff_temperature", "collision_frequency", "q_exponent",
    "late_exponent", "Bounce", "BounceSequence", "bounce_sequence", "series_scaling",
    "constant_e_rest_time", "gravity_ratio",
]


# ------------------------------------------------------------------------- cooling gas
def enskog_g2(phi: float) -> float:
    """Pair correlation at contact g2 = (1 - phi/2) / (1 - phi)^3, phi in [0, 1)."""
    if not (0.0 <= phi < 1.0):
        raise ValueError(f"volume fraction phi must be in [0, 1), got {phi!r}")
    return (1.0 - 0.5 * phi) / (1.0 - phi) ** 3


def collision_frequency(T: float, *, n: float, sigma: float, m: float, phi: float) -> float:
    """Enskog collision frequency per particle omega = 4 sqrt(pi) g2 n sigma^2 sqrt(T / m) [1/s]."""
    return 4.0 * math.sqrt(math.pi) * enskog_g2(phi) * n * sigma ** 2 * math.sqrt(T / m)


def haff_tau0(e: float, *, n: float, sigma: float, m: float, T0: float, phi: float | None = None
              ) -> float:
    """Haff's time tau0 [s]: 1 / tau0 = (2 sqrt(pi) / 3) (1 - e^2) g2 n sigma^2 sqrt(T0 / m).

    n number density [1/m^3], sigma diameter [m], m mass [kg], T0 = m <v^2> / 3 [J];
    phi defaults to pi n sigma^3 / 6.  e in (0, 1) (e = 1 does not cool: tau0 = inf).
    """
    if not (0.0 < e <= 1.0):
        raise ValueError(f"restitution e must be in (0, 1], got {e!r}")
    for name, v in (("n", n), ("sigma", sigma), ("m", m), ("T0", T0)):
        check_positive(name, v)
    if phi is None:
        phi = math.pi * n * sigma ** 3 / 6.0
    if e == 1.0:
        return math.inf
    rate = (2.0 * math.sqrt(math.pi) / 3.0) * (1.0 - e * e) * enskog_g2(phi) * n * sigma ** 2 \
        * math.sqrt(T0 / m)
    return 1.0 / rate


def haff_temperature(t, T0: float, tau0: float):
    """Haff's law T(t) = T0 / (1 + t / tau0)^2 (array in, array out)."""
    return T0 / (1.0 + np.asarray(t, dtype=float) / tau0) ** 2


def q_exponent(model: str, p: float | None = None) -> float:
    """q = (4 p - 1) / 5: 1 - e grows like v^q for small dissipation (Ts: 0, KK: 1/5).

    Jian's relaxation factor tends to 1 at low speed (t_c grows, tau is fixed), so its late
    behaviour is that of KK (p = 1/2).
    """
    law = lookup(model)
    pp = resolve(model, beta=0.0 if law.needs_beta else None, p=p).p
    return (4.0 * pp - 1.0) / 5.0


def late_exponent(model: str, p: float | None = None) -> float:
    """Late-time cooling exponent -2 / (1 + q): Ts -2, KK and Jian -5/3, LH -5/2."""
    return -2.0 / (1.0 + q_exponent(model, p))


# ------------------------------------------------------------------ ball on a plate
@dataclass(frozen=True)
class Bounce:
    """One collision of the sequence: impact speed v_in, rebound v_out = e v_in [m/s],
    contact time tc [s] (to the zero-force end), peak force fmax [N], residual [m] overlap at
    the end, t_impact [s] the time the contact starts (from release), apex [m] of the flight
    that follows, flight [s] its duration."""

    v_in: float
    e: float
    v_out: float
    tc: float
    fmax: float
    residual: float
    t_impact: float
    apex: float
    flight: float

    @property
    def tc_overlap(self) -> float:
        """Time from first to last overlap [s]: the clamped ball leaves the zero-force end with a
        residual overlap that it recovers in flight at v_out (what a DEM run sees)."""
        return self.tc + self.residual / self.v_out


@dataclass
class BounceSequence:
    """The exact bounce sequence of one law (see :func:`bounce_sequence`).

    ``bounces`` in order; ``stopped`` says why the sequence ends: ``apex`` (the next flight
    would be lower than ``h_min``), ``n_max`` or ``no rebound``.  ``t_rest`` [s] is the time the
    last counted flight lands (release at t = 0).
    """

    model: str
    bounces: list[Bounce] = field(default_factory=list)
    stopped: str = ""
    t_rest: float = 0.0
    h_min: float = 0.0

    @property
    def n(self) -> int:
        """Number of bounces whose flight reached at least h_min."""
        return len(self.bounces)

    def column(self, name: str) -> np.ndarray:
        return np.array([getattr(b, name) for b in self.bounces])


def bounce_sequence(model: str, *, m: float, k_hertz: float, c: float, tau: float | None = None,
                    p: float | None = None, v0: float | None = None, height: float | None = None,
                    g: float = STANDARD_GRAVITY, h_min: float = 1e-5, n_max: int = 2000,
                    end: str = "force") -> BounceSequence:
    """A ball released from ``height`` (or hitting at ``v0``) bouncing on a rigid plate.

    Each bounce is one exact collision, :func:`viscontact.impact` at that bounce's impact speed
    with the fixed physical c (and tau) of the calibrated law (m* = m, rigid plate); the flight
    after it is a parabola: apex h = v_out^2 / (2 g), duration 2 v_out / g.  Gravity during
    contact is neglected.  A bounce counts when its flight reaches h_min [m]; the sequence ends
    at the first one that does not (or after n_max).
    """
    from ..dimensional import impact

    check_positive("gravity", g)
    check_positive("h_min", h_min)
    if (v0 is None) == (height is None):
        raise ValueError("give exactly one of v0 (impact speed) and height (drop height)")
    if height is not None:
        v = math.sqrt(2.0 * g * check_positive("height", height))
        t = v / g
    else:
        v = check_positive("v0", v0)
        t = 0.0
    seq = BounceSequence(model=model, h_min=h_min)
    while True:
        if len(seq.bounces) >= n_max:
            seq.stopped = "n_max"
            break
        r = impact(model, m_eff=m, k_hertz=k_hertz, v=v, c=c, tau=tau, p=p, end=end,
                   history=False)
        v_out = r.e * v
        apex = v_out * v_out / (2.0 * g)
        if not r.separated or v_out <= 0.0:
            seq.stopped = "no rebound"
            break
        if apex < h_min:
            seq.stopped = "apex"
            break
        flight = 2.0 * v_out / g
        seq.bounces.append(Bounce(v_in=v, e=r.e, v_out=v_out, tc=r.tc, fmax=r.fmax,
                                  residual=r.residual, t_impact=t,
                                  apex=apex, flight=flight))
        t += r.tc + r.residual / v_out + flight
        v = v_out
    seq.t_rest = t
    return seq


def constant_e_rest_time(e: float, v0: float, g: float = STANDARD_GRAVITY) -> float:
    """Time of an infinite sequence of instantaneous bounces with constant e, from the first
    impact at v0: sum_k 2 v0 e^k / g = 2 v0 e / (g (1 - e)) (finite: the ball rests after
    infinitely many bounces)."""
    if not (0.0 < e < 1.0):
        raise ValueError(f"e must be in (0, 1), got {e!r}")
    return 2.0 * v0 * e / (g * (1.0 - e))


def series_scaling(q: float, A: float, v0: float, k) -> np.ndarray:
    """Impact speed after k bounces when 1 - e = A v^q (small dissipation, continuum in k).

    dv/dk = -A v^(1+q)  =>  v_k = (v0^(-q) + q A k)^(-1/q)  (q != 0),  v_k = v0 exp(-A k) (q = 0).
    For q > 0 the bounces never stop but v_k ~ k^(-1/q): the total flight time sum 2 v_k / g
    is finite when q < 1 and grows without bound (logarithmically) when q = 1 (Hunt-Crossley).
    For q < 0 (LH) the loss grows as v falls and the series ends sooner than geometric.
    """
    k = np.asarray(k, dtype=float)
    if q == 0.0:
        return v0 * np.exp(-A * k)
    base = v0 ** (-q) + q * A * k
    out = np.full_like(k, np.nan)
    ok = base > 0
    out[ok] = base[ok] ** (-1.0 / q)
    if q < 0:
        out[~ok] = 0.0  # the continuum model stops: v reaches 0 after finitely many bounces
    return out


def gravity_ratio(v, *, m: float, k_hertz: float, g: float = STANDARD_GRAVITY):
    """g t_c / v: the speed gravity adds during an (elastic Hertz) contact relative to the
    impact speed, t_c = 3.218 (m / k_Hertz)^(2/5) v^(-1/5).  Gravity during contact is
    negligible while this is small; it grows like v^(-6/5) as the ball slows."""
    v = np.asarray(v, dtype=float)
    tc = np.array([hertz_limit(m, k_hertz, float(x))[0] for x in np.atleast_1d(v)])
    return (g * tc / np.atleast_1d(v)).reshape(v.shape)
