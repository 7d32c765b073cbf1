"""Theory the DEM study is checked against.

* Haff's law for a freely cooling gas of smooth spheres with a constant restitution e:
  T(t) = T0 / (1 + t / tau0)^2,
  1 / tau0 = (2 sqrt(pi) / 3) (1 - e^2) g2 n sigma^2 sqrt(T0 / m),
  g2 = (1 - phi / 2) / (1 - phi)^3 (Enskog / Carnahan-Starling), T = m <v^2> / 3.
  P.K. Haff, J. Fluid Mech. 134 (1983) 401; N.V. Brilliantov, T. Poschel, Kinetic Theory of
  Granular Gases (Oxford 2004), chapter 6.
* Speed-dependent restitution 1 - e ~ v^q, q = (4 p - 1) / 5 for damping exponent p (small
  dissipation): T ~ t^(-2 / (1 + q)) at late times, t^(-5/3) for Kuwabara-Kono
  (Brilliantov & Poschel, Phys. Rev. E 61 (2000) 5573).
* Kinetic theory of the cooling with any e(v) (the same Enskog gas, Maxwellian velocities):
  dT/dt = -(4 sqrt(pi) / 3) g2 n sigma^2 sqrt(T / m) T <1 - e^2>_T, the loss averaged over the
  normal impact speeds g_n of a Maxwellian gas weighted by the energy they carry,
  <1 - e^2>_T = int_0^inf (1 - e(v_T sqrt(u))^2) u exp(-u) du, v_T = 2 sqrt(T / m) (the rms
  g_n of colliding pairs).  A constant e gives Haff's law; 1 - e^2 = A v^q gives
  T = T0 (1 + t / tau_q)^(-2 / (1 + q)) (Brilliantov & Poschel, Kinetic Theory of Granular
  Gases, chapter 6, neglecting the small non-Gaussian correction a2).
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

from ..physics.pair import STANDARD_GRAVITY, check_positive, hertz_limit
from ..physics.laws import lookup, resolve

__all__ = [
    "enskog_g2", "haff_tau0", "haff_temperature", "collision_frequency", "damping_exponent",
    "q_exponent",
    "mean_loss", "kinetic_temperature", "log_slope",
    "late_exponent", "Bounce", "BounceSequence", "bounce_sequence", "series_scaling",
    "constant_e_rest_time", "gravity_ratio", "a2_homogeneous_cooling", "sonine_a2",
    "effective_restitution", "shear_instability_length", "LUBE_RUNOUT", "LUBE_HEIGHT",
    "collapse_runout", "collapse_height",
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


def _impact_nodes(order: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Laguerre nodes and weights for int_0^inf f(u) u exp(-u) du (weights sum to 1)."""
    from scipy.special import roots_genlaguerre

    u, w = roots_genlaguerre(order, 1.0)
    return u, w


def mean_loss(e_of_speed, v_T: float, order: int = 48) -> float:
    """<1 - e^2>: the loss 1 - e(g_n)^2 averaged over the normal impact speeds g_n of a
    Maxwellian gas, weighted by collision rate and energy (g_n^3 exp(-g_n^2 / v_T^2)):
    int_0^inf (1 - e(v_T sqrt(u))^2) u exp(-u) du, v_T = 2 sqrt(T / m) [m/s].

    ``e_of_speed`` maps an array of impact speeds [m/s] to e.  A constant e gives 1 - e^2.
    Gauss-Laguerre quadrature of ``order`` nodes: exact for a loss polynomial in v^2, relative
    error below 1e-4 for a loss ~ v^q, q in [-0.2, 1] (measured: 4e-5 at q = -0.2).
    """
    u, w = _impact_nodes(order)
    e = np.asarray(e_of_speed(v_T * np.sqrt(u)), dtype=float)
    return float(np.sum(w * (1.0 - e * e)))


def kinetic_temperature(e_of_speed, t, *, T0: float, n: float, sigma: float, m: float,
                        phi: float | None = None, rtol: float = 1e-10) -> np.ndarray:
    """T(t) [J] of a homogeneous gas of smooth spheres whose restitution depends on the impact
    speed, from the kinetic equation dT/dt = -(4 sqrt(pi)/3) g2 n sigma^2 sqrt(T/m) T
    <1 - e^2>_T (:func:`mean_loss`, module docstring).  t [s] >= 0 (array), T0 [J] at t = 0;
    n [1/m^3], sigma [m], m [kg] as in :func:`haff_tau0`.  Integrated in ln T against
    ln(1 + t / tau) (smooth over decades) to ``rtol``.
    """
    from scipy.integrate import solve_ivp

    for name, v in (("n", n), ("sigma", sigma), ("m", m), ("T0", T0)):
        check_positive(name, v)
    if phi is None:
        phi = math.pi * n * sigma ** 3 / 6.0
    t = np.asarray(t, dtype=float)
    if t.size and (not np.all(np.isfinite(t)) or t.min() < 0.0):
        raise ValueError("times t must be finite and >= 0")
    rate = (4.0 * math.sqrt(math.pi) / 3.0) * enskog_g2(phi) * n * sigma ** 2
    loss0 = mean_loss(e_of_speed, 2.0 * math.sqrt(T0 / m))
    if loss0 <= 0.0:
        return np.full_like(t, T0)
    tau = 1.0 / (0.5 * rate * math.sqrt(T0 / m) * loss0)  # Haff's tau0 at the initial loss

    def rhs(x: float, y: np.ndarray) -> list[float]:
        T = T0 * math.exp(y[0])
        loss = mean_loss(e_of_speed, 2.0 * math.sqrt(T / m))
        return [-rate * math.sqrt(T / m) * loss * tau * math.exp(x)]

    x = np.log1p(t / tau)
    x_end = float(x.max()) if x.size else 0.0
    if x_end == 0.0:
        return np.full_like(t, T0)
    sol = solve_ivp(rhs, (0.0, x_end), [0.0], method="DOP853", dense_output=True, rtol=rtol,
                    atol=rtol)
    return T0 * np.exp(sol.sol(x.ravel())[0].reshape(t.shape))


def log_slope(t, T, t_from: float, t_to: float | None = None) -> tuple[float, float]:
    """Slope of ln T against ln t over t_from <= t <= t_to (least squares): the local cooling
    exponent there; returns (slope, its standard error; nan with fewer than 4 samples)."""
    t = np.asarray(t, dtype=float)
    T = np.asarray(T, dtype=float)
    sel = (t >= t_from) & (T > 0) & (t > 0)
    if t_to is not None:
        sel &= t <= t_to
    if sel.sum() < 4:
        return math.nan, math.nan
    (slope, _), cov = np.polyfit(np.log(t[sel]), np.log(T[sel]), 1, cov=True)
    return float(slope), float(math.sqrt(cov[0, 0]))


def damping_exponent(model: str, p: float | None = None) -> float:
    """The law's damping exponent p (F_d ~ delta^p delta'); ``p`` only for ``power``.  Jian
    has KK's p = 1/2 (its relaxation factor tends to 1 at low speed)."""
    law = lookup(model)
    return resolve(model, beta=0.0 if law.needs_beta else None, p=p).p


def q_exponent(model: str, p: float | None = None) -> float:
    """q = (4 p - 1) / 5: 1 - e grows like v^q for small dissipation (Ts: 0, KK: 1/5).

    Jian's relaxation factor tends to 1 at low speed (t_c grows, tau is fixed), so its late
    behaviour is that of KK (p = 1/2).
    """
    return (4.0 * damping_exponent(model, p) - 1.0) / 5.0


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
    from ..collision.impact import impact

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


# ------------------------------------------------- the gas beyond the cooling rate
def a2_homogeneous_cooling(e: float, d: int = 3) -> float:
    """Second Sonine coefficient a2 of the homogeneous cooling state with a constant e:
    a2 = <v^4> / <v^4>_Maxwell - 1 (3D: (3/5) <v^4> / <v^2>^2 - 1),

    a2 = 16 (1 - e) (1 - 2 e^2) / (9 + 24 d - e (41 - 8 d) + 30 e^2 (1 - e))

    (T.P.C. van Noije, M.H. Ernst, Granular Matter 1 (1998) 57; in 3D the denominator is
    81 - 17 e + 30 e^2 (1 - e), Brilliantov & Poschel 2004, chapter 7).  Zero at e = 1 and at
    e = 1/sqrt(2); -0.0126 at e = 0.8.
    """
    if not (0.0 <= e <= 1.0):
        raise ValueError(f"restitution e must be in [0, 1], got {e!r}")
    return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) / (
        9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * e * e * (1.0 - e))


def sonine_a2(v: np.ndarray) -> float:
    """Measured a2 = (3/5) <|v|^4> / <|v|^2>^2 - 1 of (N, 3) velocities (0 for a Maxwellian)."""
    v2 = np.sum(np.asarray(v, dtype=float) ** 2, axis=1)
    return float(0.6 * np.mean(v2 ** 2) / np.mean(v2) ** 2 - 1.0)


def effective_restitution(e_of_speed, v_T: float) -> float:
    """The constant e with the same cooling rate as e(g_n) at rms impact speed v_T:
    e_eff = sqrt(1 - <1 - e^2>_T) (:func:`mean_loss`)."""
    return math.sqrt(max(0.0, 1.0 - mean_loss(e_of_speed, v_T)))


def shear_instability_length(e: float, *, n: float, sigma: float, phi: float | None = None
                             ) -> float:
    """Shortest box [m] in which the homogeneous cooling state is linearly unstable to shear
    (vortex) modes, the first step to clustering: a shear wave of wavenumber k decays as
    nu k^2 while the thermal speed decays at zeta / 2, so it grows relative to the thermal
    motion when nu k^2 < zeta / 2, L_c = 2 pi sqrt(2 nu / zeta).  With the dilute Chapman-Enskog
    viscosity eta = (5 / (16 sigma^2)) sqrt(m T / pi), nu = eta / (n m), and Haff's cooling rate
    zeta = (4 sqrt(pi) / 3) (1 - e^2) g2 n sigma^2 sqrt(T / m), T cancels:

    L_c = 2 pi sqrt(30 / (64 pi)) / (n sigma^2 sqrt(g2 (1 - e^2)))

    (Goldhirsch & Zanetti, Phys. Rev. Lett. 70 (1993) 1619; Brilliantov & Poschel 2004,
    chapter 20).  An estimate: the inelastic corrections to eta and the Enskog factor of
    eta change it by several percent at e = 0.8.  Density clusters need a larger box still.
    """
    if not (0.0 <= e < 1.0):
        raise ValueError(f"restitution e must be in [0, 1), got {e!r}")
    check_positive("n", n)
    check_positive("sigma", sigma)
    if phi is None:
        phi = math.pi * n * sigma ** 3 / 6.0
    return 2.0 * math.pi * math.sqrt(30.0 / (64.0 * math.pi)) / (
        n * sigma ** 2 * math.sqrt(enskog_g2(phi) * (1.0 - e * e)))


# ------------------------------------------------------------- collapse of a column
#: Published scaling of quasi-two-dimensional column collapses (run-out and final height over
#: the initial length L0, aspect ratio a = H0 / L0): Lube, Huppert, Sparks & Freundt,
#: Phys. Rev. E 72 (2005) 041301 (rectangular channel, several granular materials):
#: (L_f - L0) / L0 = 1.2 a for a below about 2.3, 1.9 a^(2/3) above; H_f / L0 = a for a below
#: 1.15 (the top of the column does not move), a^(2/5) above.  Lajeunesse, Monnier & Homsy,
#: Phys. Fluids 17 (2005) 103302 (channel): the same linear law 1.2 a for a below about 3 and
#: a^(2/3) above.
LUBE_RUNOUT = ((2.3, 1.2, 1.0), (math.inf, 1.9, 2.0 / 3.0))  # (a up to, coefficient, exponent)
LUBE_HEIGHT = ((1.15, 1.0, 1.0), (math.inf, 1.0, 0.4))


def _piecewise_power(a, branches) -> np.ndarray:
    a = np.asarray(a, dtype=float)
    out = np.empty_like(a)
    lo = -math.inf
    for hi, c, p in branches:
        sel = (a > lo) & (a <= hi)
        out[sel] = c * a[sel] ** p
        lo = hi
    return out


def collapse_runout(a):
    """Published run-out (L_f - L0) / L0 of a quasi-2D column of aspect ratio a
    (:data:`LUBE_RUNOUT`)."""
    return _piecewise_power(a, LUBE_RUNOUT)


def collapse_height(a):
    """Published final height H_f / L0 of a quasi-2D column of aspect ratio a
    (:data:`LUBE_HEIGHT`)."""
    return _piecewise_power(a, LUBE_HEIGHT)
