"""Least-squares fits of the contact laws to force-plate recordings.

One recording (:func:`fit_law`, :func:`fit_laws`): for each law the non-dimensional constants
(alpha; Jian also beta, power also p; optionally k_Hertz) and a small shift of the contact
start minimise

    sum_i [ w_F (F_i - F(t_i))/F_max ]^2 + [ w_d (delta_i - delta(t_i))/delta_max ]^2
          + [ w_v (delta'_i - delta'(t_i))/v_i ]^2

over the samples of the fit window (the contact and a margin either side), where F(t) is the
law's simulated trace (:mod:`.model`) and delta_i, delta'_i are integrated from the recording.
Uncertainties are one standard deviation from the Jacobian at the optimum,
cov = s^2 (J^T J)^-1 with s^2 = RSS / (N - n); c and tau carry them by linear propagation.
Laws are ranked by the Bayesian information criterion of the force residuals,
BIC = N ln(RSS_F / N) + n ln N, so a law with a free extra parameter (Jian, power) ranks above
a fixed one only when it fits clearly better than noise allows.

Several recordings of one ball (:func:`fit_global`): one set of physical constants
(c, tau, k_Hertz; p for power) for all of them; alpha and beta follow at each impact speed
from the physical damping (Jian et al. 2019), which is how the study predicts e(v), t_c(v), F_max(v).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

# scipy is imported in the functions that use it: the command line loads this module for
# its --help, which should not pay for scipy.
from ..physics import domain
from ..calibration.inverse import alpha_from_e
from ..physics.domain import ALPHA_MAX
from ..physics.pair import damping_coefficient, damping_constants, damping_unit, time_scale
from ..physics.laws import STUDY_MODELS, lookup
from ..collision.sweep import SweepResult, velocity_sweep
from .model import Trace, simulate
from .recording import Measured
from ..physics.laws import Jian, Power

__all__ = ["LawFit", "GlobalFit", "fit_law", "fit_laws", "fit_global", "FIT_LAWS", "Weights"]

#: the laws ``--laws all`` fits: the study's six and the general power law
FIT_LAWS: tuple[str, ...] = (*STUDY_MODELS, Power.name)
#: relative finite-difference steps of the Jacobian, coarse then fine (well above the
#: solver's 1e-9 tolerance); see :func:`_least_squares`
_DIFF_STEPS = (1e-2, 1e-5)
#: least-squares iterations per fit (each costs one solve per parameter that needs one)
_MAX_NFEV = 40


@dataclass(frozen=True)
class Weights:
    """Weights of the force, overlap and overlap-rate residuals (each scaled to order one)."""

    force: float = 1.0
    overlap: float = 0.0
    rate: float = 0.0

    def __post_init__(self) -> None:
        for name in ("force", "overlap", "rate"):
            domain.check("weight", getattr(self, name), label=f"weight of {name}")
        if self.force == self.overlap == self.rate == 0:
            raise ValueError("at least one weight (force, overlap, rate) must be > 0")


@dataclass(frozen=True)
class _Param:
    """One fitted parameter: name, start, bounds, and the factor to its physical value."""

    name: str
    x0: float
    lo: float
    hi: float
    unit: float = 1.0


def _residuals(meas: Measured, trace: Trace, t0: float, w: Weights, offset: float) -> np.ndarray:
    """Scaled residuals of one recording against one trace started at t0.

    ``offset`` [N] is what is left of the baseline after :func:`measure` removed its
    estimate; the integrated velocity and overlap are corrected for it from the start on.
    """
    force, delta, rate = trace.sample(meas.t, t0)
    parts = [w.force * (meas.force - offset - force) / meas.fmax] if w.force else []
    if w.overlap or w.rate:
        since = np.maximum(meas.t - meas.t_start, 0.0)
        if w.overlap:
            measured = meas.overlap_from(t0) + offset * since ** 2 / (2.0 * meas.mass)
            parts.append(w.overlap * (measured - delta) / meas.dmax)
        if w.rate:
            measured = meas.velocity + offset * since / meas.mass
            parts.append(w.rate * (measured - rate) / meas.v)
    return np.concatenate(parts)


def _force_rss(meas: Measured, trace: Trace, t0: float, offset: float) -> tuple[float, float]:
    """(RMS force error [N], RSS of force residuals scaled by F_max)."""
    r = meas.force - offset - trace.sample(meas.t, t0)[0]
    return float(np.sqrt(np.mean(r * r))), float(np.sum((r / meas.fmax) ** 2))


def _shift_bound(meas: Measured) -> float:
    """How far [samples] a fit may move the contact start read from the force: the start of a
    weak, Hertz-like rise is uncertain by a few samples (more at high rates)."""
    return max(8.0, 0.08 * meas.tc * meas.rate)


def _least_squares(fun: Callable[[np.ndarray], np.ndarray], params: Sequence[_Param]):
    """Run the fit; (optimum x, covariance of x, scipy result).

    Two passes: coarse finite-difference steps first (the cost is rugged on the scale of a
    sample as samples enter and leave the simulated contact, which stops a fine-step search
    early), then fine steps from there for the optimum and the Jacobian of the covariance.
    """
    from scipy.optimize import least_squares

    lo, hi = [p.lo for p in params], [p.hi for p in params]
    x = np.array([min(max(p.x0, p.lo), p.hi) for p in params])
    for step in _DIFF_STEPS:
        res = least_squares(fun, x, bounds=(lo, hi), x_scale="jac", diff_step=step,
                            max_nfev=_MAX_NFEV, xtol=1e-8, ftol=1e-10, gtol=1e-10)
        x = res.x
    dof = max(res.fun.size - len(params), 1)
    s2 = 2.0 * res.cost / dof
    cov = s2 * np.linalg.pinv(res.jac.T @ res.jac)
    return res.x, cov, res


def _propagate(g: Callable[[np.ndarray], float], x: np.ndarray, cov: np.ndarray) -> float:
    """Standard deviation of g(x) by linear propagation (central differences)."""
    grad = np.zeros(x.size)
    for i in range(x.size):
        h = 1e-6 * max(1.0, abs(x[i]))
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        grad[i] = (g(xp) - g(xm)) / (2 * h)
    return float(math.sqrt(max(grad @ cov @ grad, 0.0)))


def _nan_to_none(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


@dataclass
class LawFit:
    """One law fitted to one recording (SI units; ``*_err``: one standard deviation).

    Attributes:
        law; alpha, beta (Jian), p (power; the law's fixed p otherwise, p_err None);
        k_hertz [N/m^1.5] (fitted when ``k_fitted``, else the measured value, error None);
        t0 [s] the fitted contact start; offset [N] the baseline left after :func:`measure`;
        T [s] the time scale; c in ``c_unit``; tau [s] (Jian).
        rms [N] force error over the fit window and rms / F_max as ``rms_rel``; bic the
        information criterion of the ranking (lower is better); n_samples, n_params.
        e, tc [s], fmax [N], dmax [m], residual [m]: the law's simulated impact at the fit.
        solves: collisions solved; converged, message: scipy's verdict.
    """

    law: str
    alpha: float
    alpha_err: float
    beta: float | None
    beta_err: float | None
    p: float
    p_err: float | None
    k_hertz: float
    k_hertz_err: float | None
    k_fitted: bool
    t0: float
    t0_err: float
    offset: float
    offset_err: float
    T: float
    c: float
    c_err: float
    c_unit: str
    tau: float | None
    tau_err: float | None
    rms: float
    rms_rel: float
    bic: float
    n_samples: int
    n_params: int
    solves: int
    converged: bool
    message: str
    trace: Trace = field(repr=False)

    e = property(lambda self: self.trace.impact.e, doc="e of the simulated impact at the fit")
    tc = property(lambda self: self.trace.impact.tc, doc="t_c [s] of the simulated impact")
    fmax = property(lambda self: self.trace.impact.fmax, doc="F_max [N] of the simulated impact")
    dmax = property(lambda self: self.trace.impact.dmax, doc="delta_max [m], simulated impact")
    residual = property(lambda self: self.trace.impact.residual, doc="residual overlap [m]")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: law, alpha, beta, p, c, tau, rms first; None where a field does not apply."""
        d: dict[str, Any] = {"law": self.law}
        for k in ("alpha", "beta", "p", "c", "tau", "rms", "alpha_err", "beta_err", "p_err",
                  "c_err", "tau_err", "c_unit", "k_hertz", "k_hertz_err", "k_fitted", "t0",
                  "t0_err", "offset", "offset_err", "T", "rms_rel", "bic", "n_samples", "n_params", "e", "tc", "fmax",
                  "dmax", "residual", "solves", "converged"):
            v = getattr(self, k)
            d[k] = _nan_to_none(v) if isinstance(v, float) else v
        if self.law != Power.name:
            d["p"] = None  # the law's exponent is fixed, not a fitted parameter
        return d


class _Counter:
    """Counts the collisions a fit solves (cached repeats excluded)."""

    def __init__(self) -> None:
        self.keys: set[tuple] = set()

    def __call__(self, *key: Any) -> None:
        self.keys.add(key)

    @property
    def n(self) -> int:
        return len(self.keys)


def _start_guess(law: str, e: float, beta: float | None, p: float | None) -> float:
    """alpha reproducing the measured e (clipped into the law's reach), a good start."""
    try:
        return float(alpha_from_e(law, min(max(e, 0.02), 0.995), beta=beta, p=p))
    except ValueError:
        return 1.0


def _check_fit_args(meas: Any, fit_k: Any, weights: Any) -> None:
    """ValueError unless ``meas`` is a :class:`Measured`, ``fit_k`` a bool, ``weights`` Weights."""
    if not isinstance(meas, Measured):
        raise ValueError(f"fits need a Measured recording (measure(...)), got {meas!r}")
    domain.check_bool("fit_k", fit_k)
    if not isinstance(weights, Weights):
        raise ValueError(f"weights must be a Weights(force, overlap, rate), got {weights!r}")


def fit_law(
    meas: Measured, law: str, *, fit_k: bool = True, weights: Weights = Weights(),
    k_hertz: float | None = None, start: dict[str, float] | None = None,
) -> LawFit:
    """Fit one law to one recording (see module docstring).

    Besides the law's constants the fit always has the contact start and a remaining
    baseline offset.  ``fit_k``: fit k_Hertz too (default; otherwise it is held at
    ``k_hertz``, default the measured value).  ``start`` overrides starting values (alpha,
    beta, p).
    """
    name = lookup(law).name
    needs_beta = lookup(name).needs_beta
    free_p = lookup(name).p is None
    _check_fit_args(meas, fit_k, weights)
    if k_hertz is not None:
        k_hertz = domain.check("k_hertz", k_hertz)
    if start is not None and not isinstance(start, dict):
        raise ValueError(f"start must be a dict of starting values, got {start!r}")
    start = {k: domain.check(k, v_, label=f"start {k}") for k, v_ in (start or {}).items()
             if k in ("alpha", "beta", "p")} | {k: v_ for k, v_ in (start or {}).items()
                                                if k not in ("alpha", "beta", "p")}
    k_ref = float(k_hertz) if k_hertz is not None else meas.k_hertz
    beta0 = start.get("beta", 0.5) if needs_beta else None
    p0 = start.get("p", 0.5) if free_p else None
    alpha0 = start.get("alpha") or _start_guess(name, meas.e, beta0, p0)
    sample = 1.0 / meas.rate
    shift_max = _shift_bound(meas)
    alpha0 = min(alpha0, ALPHA_MAX)
    params = [_Param("alpha", alpha0, 0.0, min(ALPHA_MAX, max(20.0, 10.0 * alpha0)))]
    if needs_beta:
        params.append(_Param("beta", beta0, 0.0, 50.0))
    if free_p:
        params.append(_Param("p", p0, 0.0, 3.0))
    if fit_k:
        params.append(_Param("k", 1.0, 0.5, 2.0, k_ref))
    params.append(_Param("shift", 0.0, -shift_max, shift_max, sample))
    params.append(_Param("offset", 0.0, -0.05, 0.05, meas.fmax))
    names = [p.name for p in params]
    solves = _Counter()

    def unpack(x: np.ndarray) -> dict[str, float]:
        q = {p.name: float(v) * p.unit for p, v in zip(params, x)}
        q.setdefault("k", k_ref)
        return q

    def trace_of(q: dict[str, float]) -> Trace:
        solves(q["alpha"], q.get("beta"), q.get("p"))
        return simulate(name, q["alpha"], m_eff=meas.mass, k_hertz=q["k"], v=meas.v,
                        beta=q.get("beta"), p=q.get("p"))

    def fun(x: np.ndarray) -> np.ndarray:
        q = unpack(x)
        return _residuals(meas, trace_of(q), meas.t_start + q["shift"], weights, q["offset"])

    x, cov, res = _least_squares(fun, params)
    q = unpack(x)
    trace = trace_of(q)
    t0 = meas.t_start + q["shift"]
    err = {n: math.sqrt(max(cov[i, i], 0.0)) * params[i].unit for i, n in enumerate(names)}

    def c_of(xx: np.ndarray) -> float:
        qq = unpack(xx)
        p_of = qq.get("p")  # a difference step may leave the bound p >= 0
        return damping_coefficient(name, max(qq["alpha"], 0.0), m_eff=meas.mass,
                                   k_hertz=qq["k"], v=meas.v,
                                   p=None if p_of is None else max(p_of, 0.0))

    def tau_of(xx: np.ndarray) -> float:
        qq = unpack(xx)
        return qq["beta"] * time_scale(meas.mass, qq["k"], meas.v)

    rms, rss = _force_rss(meas, trace, t0, q["offset"])
    n = meas.t.size
    T = time_scale(meas.mass, q["k"], meas.v)
    return LawFit(
        law=name, alpha=q["alpha"], alpha_err=err["alpha"],
        beta=q.get("beta"), beta_err=err.get("beta"),
        p=trace.impact.p, p_err=err.get("p"),
        k_hertz=q["k"], k_hertz_err=err.get("k"), k_fitted=fit_k,
        t0=t0, t0_err=err["shift"], offset=q["offset"], offset_err=err["offset"], T=T,
        c=c_of(x), c_err=_propagate(c_of, x, cov), c_unit=damping_unit(trace.impact.p),
        tau=tau_of(x) if needs_beta else None,
        tau_err=_propagate(tau_of, x, cov) if needs_beta else None,
        rms=rms, rms_rel=rms / meas.fmax, bic=n * math.log(max(rss, 1e-300) / n) + len(x) * math.log(n),
        n_samples=n, n_params=len(x), solves=solves.n, converged=bool(res.success),
        message=str(res.message), trace=trace,
    )


def fit_laws(
    meas: Measured, laws: Sequence[str] = FIT_LAWS, *, fit_k: bool = True,
    weights: Weights = Weights(), progress: Callable[[str], None] | None = None,
) -> list[LawFit]:
    """Fit each law to one recording; the list is sorted best first (lowest BIC).

    The power law starts from the best fixed-exponent law found before it, so it does not
    settle in a poorer local minimum.  ``progress(law)`` is called after each law.
    """
    if isinstance(laws, str) or not isinstance(laws, Sequence):
        raise ValueError(f"laws must be a sequence of law names, got {laws!r}")
    names = [lookup(law).name for law in laws]
    if not names:
        raise ValueError("give at least one law to fit")
    _check_fit_args(meas, fit_k, weights)
    if progress is not None and not callable(progress):
        raise ValueError(f"progress must be callable, got {progress!r}")
    fits: list[LawFit] = []
    for name in sorted(dict.fromkeys(names), key=lambda n: n == Power.name):
        start = None
        fixed = [f for f in fits if f.law not in (Jian.name, Power.name)]
        if name == Power.name and fixed:
            best = min(fixed, key=lambda f: f.bic)
            start = {"alpha": best.alpha, "p": best.p}
        fits.append(fit_law(meas, name, fit_k=fit_k, weights=weights, start=start))
        if progress is not None:
            progress(name)
    return sorted(fits, key=lambda f: f.bic)


@dataclass
class GlobalFit:
    """One law with one set of physical constants fitted to several recordings (SI units).

    Attributes:
        law; c (``c_unit``), tau [s] (Jian), p (power), k_hertz [N/m^1.5], each with ``*_err``.
        t0 [s]: the fitted contact start of each recording.  rms [N] over all recordings and
        rms_each [N] per recording; bic as in :class:`LawFit`; solves; converged, message.
        traces: the law's simulated impact for each recording; sweep: e, t_c, F_max over a
        range of impact speeds with these constants (for plots); measured: the recordings.
    """

    law: str
    c: float
    c_err: float
    c_unit: str
    tau: float | None
    tau_err: float | None
    p: float
    p_err: float | None
    k_hertz: float
    k_hertz_err: float | None
    t0: list[float]
    rms: float
    rms_each: list[float]
    bic: float
    solves: int
    converged: bool
    message: str
    traces: list[Trace] = field(repr=False)
    measured: list[Measured] = field(repr=False)
    sweep: SweepResult | None = field(repr=False, default=None)

    def points(self) -> list[dict[str, float]]:
        """Per recording: v, and measured against predicted e, t_c [s], F_max [N]."""
        return [{"v": m.v, "e": m.e, "e_fit": tr.impact.e, "tc": m.tc, "tc_fit": tr.impact.tc,
                 "fmax": m.fmax, "fmax_fit": tr.impact.fmax}
                for m, tr in zip(self.measured, self.traces)]

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"law": self.law}
        for k in ("c", "tau", "k_hertz", "p", "c_err", "tau_err", "k_hertz_err", "p_err",
                  "c_unit", "rms", "rms_each", "bic", "t0", "solves", "converged"):
            d[k] = getattr(self, k)
        if self.law != Power.name:
            d["p"] = None
        d["points"] = self.points()
        return d


def fit_global(
    measured: Sequence[Measured], law: str, *, start: Sequence[LawFit] | None = None,
    fit_k: bool = True, weights: Weights = Weights(), sweep_points: int = 25,
) -> GlobalFit:
    """One set of physical constants of ``law`` fitted to all recordings at once.

    Each recording keeps its own contact start and baseline offset; its force residuals are
    scaled by its own F_max, so a low drop counts as much as a high one.

    ``start``: per-recording fits of the same law (their medians start the fit; without
    them each recording is first fitted alone).  ``fit_k``: fit one k_Hertz (else the median
    measured value).  ``sweep_points`` > 0 adds the law's e, t_c, F_max over the speeds of
    the recordings (+-20 %) with the fitted constants.
    """
    if isinstance(measured, (str, Measured)) or not isinstance(measured, Sequence):
        raise ValueError(f"measured must be a sequence of Measured recordings, got {measured!r}")
    if len(measured) < 1:
        raise ValueError("give at least one recording")
    for m in measured:
        _check_fit_args(m, fit_k, weights)
    sweep_points = domain.check_int("sweep_points", sweep_points, 0, 10_000)
    name = lookup(law).name
    needs_beta = lookup(name).needs_beta
    free_p = lookup(name).p is None
    if start is None:
        start = [fit_law(m, name) for m in measured]
    if (isinstance(start, str) or not isinstance(start, Sequence)
            or not all(isinstance(f, LawFit) for f in start)):
        raise ValueError(f"start must be a sequence of LawFit (one per recording), got {start!r}")
    if len(start) != len(measured) or any(f.law != name for f in start):
        raise ValueError(f"give one {name} fit per recording as start")
    c_ref = float(np.median([f.c for f in start])) or 1.0
    k_ref = float(np.median([f.k_hertz for f in start]))
    T_ref = float(np.median([f.T for f in start]))
    params = [_Param("c", 1.0, 0.0, 20.0, c_ref)]
    if needs_beta:
        params.append(_Param("tau", float(np.median([f.tau for f in start])) / T_ref, 0.0, 50.0,
                             T_ref))
    if free_p:
        params.append(_Param("p", float(np.median([f.p for f in start])), 0.0, 3.0))
    if fit_k:
        params.append(_Param("k", 1.0, 0.5, 2.0, k_ref))
    for i, (m, f) in enumerate(zip(measured, start)):
        shift_max = _shift_bound(m)
        params.append(_Param(f"shift{i}", (f.t0 - m.t_start) * m.rate, -shift_max, shift_max,
                             1.0 / m.rate))
        params.append(_Param(f"offset{i}", f.offset / m.fmax, -0.05, 0.05, m.fmax))
    solves = _Counter()

    def unpack(x: np.ndarray) -> dict[str, float]:
        q = {p.name: float(v) * p.unit for p, v in zip(params, x)}
        q.setdefault("k", k_ref)
        return q

    def traces_of(q: dict[str, float]) -> list[Trace]:
        out = []
        for m in measured:
            alpha, beta = damping_constants(name, q["c"], m_eff=m.mass, k_hertz=q["k"], v=m.v,
                                            tau=q.get("tau"), p=q.get("p"))
            solves(alpha, beta, q.get("p"))
            out.append(simulate(name, alpha, m_eff=m.mass, k_hertz=q["k"], v=m.v, beta=beta,
                                p=q.get("p")))
        return out

    def fun(x: np.ndarray) -> np.ndarray:
        q = unpack(x)
        return np.concatenate([
            _residuals(m, tr, m.t_start + q[f"shift{i}"], weights, q[f"offset{i}"])
            for i, (m, tr) in enumerate(zip(measured, traces_of(q)))])

    x, cov, res = _least_squares(fun, params)
    q = unpack(x)
    traces = traces_of(q)
    err = {p.name: math.sqrt(max(cov[i, i], 0.0)) * p.unit for i, p in enumerate(params)}
    t0 = [m.t_start + q[f"shift{i}"] for i, m in enumerate(measured)]
    stats = [_force_rss(m, tr, s, q[f"offset{i}"])
             for i, (m, tr, s) in enumerate(zip(measured, traces, t0))]
    n = sum(m.t.size for m in measured)
    rss = sum(s[1] for s in stats)
    sq = sum(s[0] ** 2 * m.t.size for s, m in zip(stats, measured))
    p_val = traces[0].impact.p
    sweep = None
    if sweep_points > 0:
        vs = [m.v for m in measured]
        speeds = np.linspace(0.8 * min(vs), 1.2 * max(vs), sweep_points)
        sweep = velocity_sweep(name, speeds, m_eff=float(np.median([m.mass for m in measured])),
                               k_hertz=q["k"], c=q["c"], tau=q.get("tau"), p=q.get("p"))
    return GlobalFit(
        law=name, c=q["c"], c_err=err["c"], c_unit=damping_unit(p_val), tau=q.get("tau"),
        tau_err=err.get("tau"), p=p_val, p_err=err.get("p"), k_hertz=q["k"],
        k_hertz_err=err.get("k"), t0=t0, rms=math.sqrt(sq / n), rms_each=[s[0] for s in stats],
        bic=n * math.log(max(rss, 1e-300) / n) + len(x) * math.log(n), solves=solves.n,
        converged=bool(res.success), message=str(res.message), traces=traces,
        measured=list(measured), sweep=sweep,
    )
