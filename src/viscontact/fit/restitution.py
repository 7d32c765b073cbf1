"""Every law fitted to restitution measured at several impact speeds, e(v), and ranked.

With m*, k_Hertz and the physical damping prefactor c held fixed, a law of exponent p has the
non-dimensional damping constant (Jian et al., Powder Technol. 356 (2019) 735, eq. of c in
section 2; docs/fit-restitution.md)

    alpha(v) = alpha_ref (v / v_ref)^((4p - 1)/5),    beta(v) = beta_ref (v / v_ref)^(1/5) (Jian)

so an e(v) curve determines one number for LH, Ts, KK, Li and Hunt (alpha_ref at the reference
speed v_ref), two for Jian (alpha_ref, beta_ref) and two for the power law (alpha_ref, p).
e(alpha[, beta]) comes from the calibration tables (|e - exact| <= 1e-10), so a fit costs a
few table look-ups per point and iteration; every fit of one law (the data set, its
leave-one-out subsets, or many synthetic data sets) runs as one vectorised Levenberg-Marquardt
iteration over the whole batch.

Uncertainties: from the given sigma_e (weights 1/sigma^2), from the scatter of replicates (rows
at one speed: one pooled sigma), or from the residuals (sigma^2 = RSS / (n - k)); the
covariance is (J^T W J)^-1 (times sigma^2 in the last case), propagated linearly.  Laws are
ranked by AICc (Hurvich & Tsai, Biometrika 76 (1989) 297; it needs n >= k + 2 points) and
described by their leave-one-out prediction error; AICc differences below 2 cannot tell two
laws apart (Burnham & Anderson, Model Selection and Multimodel Inference, 2002, sec. 2.6).
The physical constants (c, tau; k_Hertz from measured contact times) follow when the mass and
k_Hertz (or the contact times) are known.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..calibration.inverse import restitution
from ..collision.single import check_end
from ..physics.laws import Jian, Power, lookup
from ..physics.pair import damping_unit, time_scale
from .fitting import FIT_LAWS
from ..physics import domain
from ..physics.pair import check_positive
from .recording import RecordingError, check_path, float_array

__all__ = ["RestitutionData", "RestitutionLawFit", "RestitutionFit", "read_restitution",
           "restitution_data", "fit_restitution", "fit_restitution_sets", "law_exponent",
           "model_e", "RES_LAWS"]

#: the laws fitted to e(v), in the order they are listed
RES_LAWS: tuple[str, ...] = FIT_LAWS

#: search ranges of the fitted constants: ln alpha_ref, ln beta_ref, p (the force fit's range)
_LN_ALPHA = (math.log(1e-7), math.log(1000.0))
_LN_BETA = (math.log(1e-4), math.log(1000.0))
_P_RANGE = (0.0, 3.0)
_H = 1e-5         # finite-difference step in the fitted coordinates (tables: 1e-10 in e)
_MAX_ITER = 60
#: more points than this: leave-one-out by the leverage form instead of n refits
_LOO_REFIT_MAX = 40
#: AICc difference below which two laws cannot be told apart
AICC_TIE = 2.0

_SPEED_UNITS = {"m/s": 1.0, "cm/s": 1e-2, "mm/s": 1e-3}
_TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6}


def law_exponent(law: str, p: float | None = None) -> float:
    """The damping exponent p of ``law`` (``p`` for the power law)."""
    spec = lookup(law)
    return float(p) if spec.p is None else float(spec.p)


def _n_params(law: str) -> int:
    spec = lookup(law)
    return 2 if (spec.needs_beta or spec.p is None) else 1


def model_e(law: str, v: Any, vref: float, alpha: Any, *, beta: Any = None, p: Any = None,
            end: str = "force") -> np.ndarray:
    """e at impact speeds ``v`` [m/s] of ``law`` with alpha_ref (and beta_ref, Jian) at
    ``vref``: e(alpha_ref (v/vref)^((4p-1)/5)[, beta_ref (v/vref)^(1/5)]).  Broadcasts ``v``
    against the constants (for the power law ``p`` is one number); alpha and beta above 1000
    act as 1000."""
    spec = lookup(law)
    if spec.p is None:
        p = domain.check("p", p)
    pe = law_exponent(spec.name, p)
    s = float_array("v", v, lo=0.0, lo_open=True) / check_positive("vref", vref)
    a = float_array("alpha", alpha, lo=0.0) * s ** ((4.0 * pe - 1.0) / 5.0)
    a = np.minimum(a, 1000.0)
    if spec.needs_beta:
        b = np.minimum(float_array("beta", beta, lo=0.0) * s ** 0.2, 1000.0)
        return np.asarray(restitution(spec.name, a, beta=b, end=end))
    if spec.p is None:
        return np.asarray(restitution(spec.name, a, p=pe, end=end))
    return np.asarray(restitution(spec.name, a, end=end))


# ------------------------------------------------------------------------------------------
# data
# ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RestitutionData:
    """Measured (v, e) points in recording order.

    Attributes:
        v: impact speeds [m/s].  e: restitution coefficients, in (0, 1].
        sigma: one standard deviation of each e (None: not given).
        tc: contact times [s] (None: not given).  source: where the points came from.
        drop: the drop (file) each point belongs to (bounce input), else None.
    """

    v: np.ndarray
    e: np.ndarray
    sigma: np.ndarray | None = None
    tc: np.ndarray | None = None
    source: str = ""
    drop: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.v.size)


def restitution_data(v: Any, e: Any, *, sigma: Any = None, tc: Any = None, source: str = "",
                     drop: Any = None) -> RestitutionData:
    """Validated :class:`RestitutionData`: v > 0 finite, e in (0, 1], sigma > 0, tc > 0, one
    length; at least two points.  ValueError names the first bad value."""
    if not isinstance(source, str):
        raise ValueError(f"source must be a str (where the points came from), got {source!r:.60}")
    v_a = _column("v", v, positive=True)
    e_a = _column("e", e, positive=True)
    n = v_a.size
    if n < 2:
        raise ValueError(f"{source or 'the data'}: {n} point{'s' if n != 1 else ''}; a fit of "
                         "e(v) needs at least two (v, e) points")
    if e_a.size != n:
        raise ValueError(f"v has {n} values and e {e_a.size}; give one e per speed")
    bad = np.flatnonzero(e_a > 1.0)
    if bad.size:
        raise ValueError(f"{source or 'e'}: e = {e_a[bad[0]]:g} at v = {v_a[bad[0]]:g} m/s; "
                         "e must lie in (0, 1]")
    s_a = None if sigma is None else _column("sigma_e", sigma, positive=True, n=n)
    t_a = None if tc is None else _column("tc", tc, positive=True, n=n)
    d_a = None if drop is None else np.asarray(drop, dtype=int)
    return RestitutionData(v_a, e_a, s_a, t_a, source, d_a)


def _column(name: str, x: Any, *, positive: bool, n: int | None = None) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float).ravel()
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be numbers, got {x!r}") from None
    if n is not None and a.size != n:
        raise ValueError(f"{name} has {a.size} values for {n} points; give one per point")
    bad = np.flatnonzero(~np.isfinite(a) | ((a <= 0) if positive else False))
    if bad.size:
        raise ValueError(f"{name} = {a[bad[0]]!r} in point {bad[0] + 1}: {name} must be a finite "
                         "number > 0")
    return a


_HEAD = re.compile(r"^\s*([A-Za-z_]+)\s*(?:[\[(]\s*([^\])]*)\s*[\])])?\s*$")


def read_restitution(path: str | Path) -> RestitutionData:
    """A table of (v, e[, sigma_e][, tc]) from a CSV or whitespace-separated text file.

    '#' starts a comment; the header names the columns ``v``, ``e``, optional ``sigma_e``
    (one standard deviation of e) and ``tc`` (contact time), with units in brackets:
    ``v [cm/s]`` or ``v [mm/s]`` convert to m/s, ``tc [ms]`` or ``[us]`` to s.  Without a
    header the columns are v [m/s], e[, sigma_e[, tc [s]]].  Rows at one speed are replicates.
    RecordingError (a ValueError) says what is wrong with the file.
    """
    p = check_path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordingError(f"{path}: cannot read the file ({exc})") from None
    rows = []
    header: list[str] | None = None
    for k, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        cells = _cells(line)
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if header is None and not rows:
                header = cells
                continue
            raise RecordingError(f"{path}, line {k}: {raw.strip()!r} is not a row of numbers") \
                from None
    names, scale = _columns(path, header, rows)
    if not rows:
        raise RecordingError(f"{path}: no rows of numbers; give columns v [m/s] and e")
    width = {len(r) for r in rows}
    if len(width) != 1 or width.pop() != len(names):
        raise RecordingError(f"{path}: every row needs {len(names)} numbers ({', '.join(names)})")
    a = np.array(rows, dtype=float)
    cols = {name: a[:, i] * scale[i] for i, name in enumerate(names)}
    try:
        return restitution_data(cols["v"], cols["e"], sigma=cols.get("sigma_e"),
                                tc=cols.get("tc"), source=str(path))
    except ValueError as exc:
        msg = str(exc)
        raise RecordingError(msg if msg.startswith(str(path)) else f"{path}: {msg}") from None


def _cells(line: str) -> list[str]:
    """Cells of a row: split at commas, semicolons or tabs, else at spaces (a unit in brackets
    stays with its column name)."""
    if re.search(r"[,;\t]", line):
        return [c.strip() for c in re.split(r"[,;\t]", line) if c.strip()]
    out: list[str] = []
    for tok in line.split():
        if out and tok[0] in "[(":
            out[-1] += " " + tok
        else:
            out.append(tok)
    return out


def _columns(path: Any, header: list[str] | None,
             rows: list[list[float]]) -> tuple[list[str], list[float]]:
    """Column names (v, e, sigma_e, tc) and their factors to SI from the header."""
    if header is None:
        n = len(rows[0]) if rows else 2
        if not 2 <= n <= 4:
            raise RecordingError(f"{path}: {n} columns without a header; give v, e[, sigma_e"
                                 "[, tc]] or a header naming them")
        return ["v", "e", "sigma_e", "tc"][:n], [1.0] * n
    names, scale = [], []
    alias = {"v": "v", "speed": "v", "v_i": "v", "e": "e", "cor": "e", "sigma_e": "sigma_e",
             "sigma": "sigma_e", "err": "sigma_e", "tc": "tc", "t_c": "tc"}
    for cell in header:
        m = _HEAD.match(cell)
        key = alias.get(m.group(1).lower()) if m else None
        if key is None or key in names:
            raise RecordingError(f"{path}: header column {cell!r}; allowed are v [m/s|cm/s|mm/s], "
                                 "e, sigma_e, tc [s|ms|us], each once")
        unit = (m.group(2) or "").strip()
        table = _SPEED_UNITS if key == "v" else _TIME_UNITS if key == "tc" else {"": 1.0, "1": 1.0}
        if unit and unit not in table:
            raise RecordingError(f"{path}: unit [{unit}] of column {key}; allowed are "
                                 f"{', '.join(u for u in table if u) or 'none'}")
        names.append(key)
        scale.append(table.get(unit, 1.0) if unit else 1.0)
    if "v" not in names or "e" not in names:
        raise RecordingError(f"{path}: the header must name columns v and e")
    return names, scale


# ------------------------------------------------------------------------------------------
# the vectorised fit
# ------------------------------------------------------------------------------------------


@dataclass
class _Batch:
    """P problems of one law over n points each (a zero weight leaves a point out)."""

    law: str
    v: np.ndarray      # (P, n)
    e: np.ndarray      # (P, n)
    w: np.ndarray      # (P, n)
    vref: float
    end: str

    def model(self, theta: np.ndarray) -> np.ndarray:
        spec = lookup(self.law)
        alpha = np.exp(theta[:, :1])
        if spec.needs_beta:
            return model_e(self.law, self.v, self.vref, alpha, beta=np.exp(theta[:, 1:2]),
                           end=self.end)
        if spec.p is None:  # one exponent per problem: one batch solve each
            out = np.empty_like(self.v)
            for i in range(theta.shape[0]):
                out[i] = model_e(self.law, self.v[i], self.vref, alpha[i, 0],
                                 p=float(theta[i, 1]), end=self.end)
            return out
        return model_e(self.law, self.v, self.vref, alpha, end=self.end)


def _clip(law: str, theta: np.ndarray) -> np.ndarray:
    t = theta.copy()
    t[:, 0] = np.clip(t[:, 0], *_LN_ALPHA)
    if t.shape[1] > 1:
        t[:, 1] = np.clip(t[:, 1], *(_LN_BETA if lookup(law).needs_beta else _P_RANGE))
    return t


def _cost(b: _Batch, m: np.ndarray) -> np.ndarray:
    return np.sum(b.w * (m - b.e) ** 2, axis=1)


def _jacobian(b: _Batch, theta: np.ndarray, m0: np.ndarray) -> np.ndarray:
    """Forward differences (P, n, k); the step goes inward at the upper bounds."""
    k = theta.shape[1]
    J = np.empty(m0.shape + (k,))
    hi = np.array([_LN_ALPHA[1]] + ([(_LN_BETA if lookup(b.law).needs_beta else _P_RANGE)[1]]
                                    if k > 1 else []))
    for j in range(k):
        h = np.where(theta[:, j] + _H > hi[j], -_H, _H)
        t = theta.copy()
        t[:, j] += h
        J[:, :, j] = (b.model(t) - m0) / h[:, None]
    return J


def _start(b: _Batch) -> np.ndarray:
    """Grid search: the best of a log grid of alpha_ref (Jian: alpha_ref x beta_ref)."""
    spec = lookup(b.law)
    P = b.v.shape[0]
    ln_a = np.linspace(math.log(1e-4), math.log(300.0), 48)
    if spec.needs_beta:
        ln_b = np.linspace(math.log(1e-2), math.log(30.0), 10)
        grid = np.array([(a, c) for a in ln_a[::2] for c in ln_b])
    elif spec.p is None:  # from the best of the fixed-exponent laws (tables, no solves)
        return _power_start(b, ln_a)
    else:
        grid = ln_a[:, None]
    G = grid.shape[0]
    rep = _Batch(b.law, np.repeat(b.v, G, axis=0), np.repeat(b.e, G, axis=0),
                 np.repeat(b.w, G, axis=0), b.vref, b.end)
    theta = np.tile(grid, (P, 1))
    m = rep.model(theta)
    cost = _cost(rep, m).reshape(P, G)
    return grid[np.argmin(cost, axis=1)]


def _power_start(b: _Batch, ln_a: np.ndarray) -> np.ndarray:
    """(ln alpha_ref, p) of the best fixed-exponent law on a grid of alpha_ref; p is moved
    off the law's exact value by 0.01 (exact rational exponents compile solver variants of
    their own; the fit moves p anyway)."""
    fixed = [n for n in RES_LAWS if lookup(n).p is not None and not lookup(n).needs_beta]
    P, G = b.v.shape[0], ln_a.size
    best = np.full(P, np.inf)
    out = np.zeros((P, 2))
    for name in fixed:
        m = model_e(name, b.v[:, None, :], b.vref, np.exp(ln_a)[None, :, None], end=b.end)
        cost = np.sum(b.w[:, None, :] * (m - b.e[:, None, :]) ** 2, axis=2)
        i = np.argmin(cost, axis=1)
        c = cost[np.arange(P), i]
        better = c < best
        best[better] = c[better]
        out[better] = np.column_stack([ln_a[i], np.full(P, float(lookup(name).p) + 0.01)])[better]
    return out


def _lm(b: _Batch, theta0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Levenberg-Marquardt on every problem at once: (theta, model at theta, J^T W J)."""
    theta = _clip(b.law, _start(b) if theta0 is None else theta0)
    m = b.model(theta)
    cost = _cost(b, m)
    lam = np.full(theta.shape[0], 1e-3)
    live = np.ones(theta.shape[0], dtype=bool)
    k = theta.shape[1]
    eye = np.eye(k)
    for _ in range(_MAX_ITER):
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        sub = _Batch(b.law, b.v[idx], b.e[idx], b.w[idx], b.vref, b.end)
        J = _jacobian(sub, theta[idx], m[idx])
        A = np.einsum("pni,pn,pnj->pij", J, sub.w, J)
        g = np.einsum("pni,pn,pn->pi", J, sub.w, m[idx] - sub.e)
        D = A * eye + 1e-30
        step = -np.linalg.solve(A + lam[idx, None, None] * D, g[..., None])[..., 0]
        trial = _clip(b.law, theta[idx] + step)
        mt = sub.model(trial)
        ct = _cost(sub, mt)
        better = ct <= cost[idx]
        good = idx[better]
        moved = np.max(np.abs(trial - theta[idx]), axis=1)
        gain = cost[idx] - ct
        theta[good], m[good], cost[good] = trial[better], mt[better], ct[better]
        lam[good] = np.maximum(lam[good] / 4.0, 1e-9)
        lam[idx[~better]] *= 8.0
        done = (better & ((moved < 1e-7) | (gain <= 1e-10 * (cost[idx] + 1e-30)))) | \
            (lam[idx] > 1e12)
        live[idx[done]] = False
    J = _jacobian(b, theta, m)
    A = np.einsum("pni,pn,pnj->pij", J, b.w, J)
    return theta, m, A


@dataclass(frozen=True)
class SetFits:
    """One law fitted to many data sets at once (:func:`fit_restitution_sets`).

    Arrays over the sets: ``alpha``, ``alpha_err``, ``second`` and ``second_err`` (beta_ref for
    Jian, p for power, None for one-parameter laws), ``aicc`` (None with fewer than k + 2
    speeds), ``rms``."""

    law: str
    alpha: np.ndarray
    alpha_err: np.ndarray
    second: np.ndarray | None
    second_err: np.ndarray | None
    aicc: np.ndarray | None
    rms: np.ndarray


def _sigma_weights(v: np.ndarray, e: np.ndarray, sigma: np.ndarray | None
                   ) -> tuple[np.ndarray, str]:
    """Weights 1/sigma^2 per point and where sigma came from (given, replicates, residuals)."""
    if sigma is not None:
        return 1.0 / sigma ** 2, "given"
    _, inv, counts = np.unique(v, return_inverse=True, return_counts=True)
    dof = int(np.sum(counts - 1))
    if dof >= 2:
        means = np.bincount(inv, weights=e) / counts
        s2 = float(np.sum((e - means[inv]) ** 2)) / dof
        if s2 > 0:
            return np.full(v.size, 1.0 / s2), "replicates"
    return np.ones(v.size), "residuals"


def _aicc(chi2: np.ndarray, n: int, k: int, known: bool) -> np.ndarray:
    """AICc = AIC + 2k(k+1)/(n-k-1); AIC = chi^2 + 2k (sigma known) or n ln(RSS/n) + 2k."""
    if n < k + 2:
        return np.full(np.shape(chi2), np.nan)
    base = chi2 if known else n * np.log(np.maximum(chi2, 1e-300) / n)
    return base + 2 * k + 2.0 * k * (k + 1) / (n - k - 1)


def _errors(A: np.ndarray, chi2: np.ndarray, n: int, k: int, known: bool) -> np.ndarray:
    """Covariance of the fitted coordinates (P, k, k)."""
    try:
        cov = np.linalg.inv(A)
    except np.linalg.LinAlgError:
        cov = np.linalg.pinv(A)
    if not known:
        s2 = chi2 / max(n - k, 1) if n > k else np.full_like(chi2, np.nan)
        cov = cov * s2[:, None, None]
    return cov


def fit_restitution_sets(v: Any, e_sets: Any, *, law: str, sigma: Any = None,
                         vref: float | None = None, end: str = "force") -> SetFits:
    """Fit ``law`` to many data sets at the same speeds at once (synthetic studies).

    ``e_sets`` has shape (S, n) for the n speeds ``v``; ``sigma`` (n,) gives the weights and
    known uncertainties (None: from the residuals).  alpha_ref at ``vref`` (default the
    geometric mean of v).
    """
    check_end(end)
    name = lookup(law).name
    v_a = float_array("v", v, lo=0.0, lo_open=True)
    E = np.atleast_2d(float_array("e_sets", e_sets, lo=0.0, lo_open=True))
    n = v_a.size
    if v_a.ndim != 1 or E.ndim != 2 or E.shape[1] != n or E.size == 0:
        raise ValueError(f"e_sets must have shape (S, n) for the n = {n} speeds v (a 1-D array), "
                         f"got v of shape {v_a.shape} and e_sets of shape {E.shape}")
    if np.any(E > 1.0):
        raise ValueError(f"e_sets must lie in (0, 1], got {float(E.max())!r}")
    if n <= _n_params(name):
        raise ValueError(f"{name} has {_n_params(name)} parameters: give more than that many "
                         f"speeds, got {n}")
    S = E.shape[0]
    vref = _default_vref(v_a) if vref is None else check_positive("vref", vref)
    known = sigma is not None
    w = np.ones(n)
    if sigma is not None:
        sd = float_array("sigma", sigma, lo=0.0, lo_open=True)
        if sd.shape != (n,):
            raise ValueError(f"sigma must hold one number > 0 per speed ({n}), got shape {sd.shape}")
        w = 1.0 / sd ** 2
    b = _Batch(name, np.tile(v_a, (S, 1)), E, np.tile(w, (S, 1)), vref, end)
    theta, m, A = _lm(b)
    k = theta.shape[1]
    chi2 = _cost(b, m)
    cov = _errors(A, chi2, n, k, known)
    sd = np.sqrt(np.maximum(np.diagonal(cov, axis1=1, axis2=2), 0.0))
    alpha = np.exp(theta[:, 0])
    second = second_err = None
    if k > 1:
        if lookup(name).needs_beta:
            second, second_err = np.exp(theta[:, 1]), np.exp(theta[:, 1]) * sd[:, 1]
        else:
            second, second_err = theta[:, 1], sd[:, 1]
    rms = np.sqrt(np.mean((m - E) ** 2, axis=1))
    return SetFits(name, alpha, alpha * sd[:, 0], second, second_err,
                   _aicc(chi2, n, k, known) if n >= k + 2 else None, rms)


def _default_vref(v: np.ndarray) -> float:
    """The geometric mean of the speeds, to three significant digits."""
    g = float(np.exp(np.mean(np.log(v))))
    return float(f"{g:.3g}")


# ------------------------------------------------------------------------------------------
# results
# ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RestitutionLawFit:
    """One law fitted to e(v).

    Attributes:
        law, end: the law and the end criterion.  vref: reference speed [m/s].
        alpha, alpha_err: alpha_ref at vref and its 1-sigma uncertainty.
        beta, beta_err: beta_ref at vref (Jian; else None).  p, p_err: exponent (power: fitted).
        e_fit: the fitted e at the data's speeds.  rms: root mean square of e_fit - e.
        aicc: AICc (None with too few points).  loo: root mean square leave-one-out prediction
        error of e (None with fewer than k + 2 points).
        c, c_err, c_unit: physical prefactor of delta^p delta' (needs mass and k_Hertz).
        tau, tau_err: Jian's relaxation time [s].  k_hertz, k_hertz_err: used or measured.
    """

    law: str
    end: str
    vref: float
    alpha: float
    alpha_err: float | None
    beta: float | None
    beta_err: float | None
    p: float
    p_err: float | None
    e_fit: np.ndarray
    rms: float
    aicc: float | None
    loo: float | None
    n_params: int
    c: float | None = None
    c_err: float | None = None
    c_unit: str | None = None
    tau: float | None = None
    tau_err: float | None = None
    k_hertz: float | None = None
    k_hertz_err: float | None = None

    def e_at(self, v: Any) -> np.ndarray:
        """The fitted e at impact speeds ``v`` [m/s]."""
        return model_e(self.law, v, self.vref, self.alpha, beta=self.beta,
                       p=self.p if lookup(self.law).p is None else None, end=self.end)

    def contact_time(self, v: Any, mass: float, k_hertz: float) -> np.ndarray:
        """This law's own contact time [s] at impact speeds ``v`` for a ball of ``mass`` [kg]
        and ``k_hertz`` [N/m^1.5]: t_c(alpha(v)[, beta(v)]) / T times T(v) (the undamped
        3.218 T only at alpha -> 0)."""
        v_a = np.atleast_1d(np.asarray(v, dtype=float))
        tc_hat = _tc_over_T(self.law, self.alpha, self.beta, self.p, self.vref, v_a, self.end)
        return tc_hat * (mass / k_hertz) ** 0.4 / v_a ** 0.2

    def to_dict(self) -> dict[str, Any]:
        return {"law": self.law, "end": self.end, "vref": self.vref, "alpha": self.alpha,
                "alpha_err": self.alpha_err, "beta": self.beta, "beta_err": self.beta_err,
                "p": self.p, "p_err": self.p_err, "rms": self.rms,
                "e_fit": [float(x) for x in self.e_fit], "aicc": self.aicc, "loo": self.loo,
                "c": self.c, "c_err": self.c_err, "c_unit": self.c_unit, "tau": self.tau,
                "tau_err": self.tau_err, "k_hertz": self.k_hertz,
                "k_hertz_err": self.k_hertz_err}


@dataclass(frozen=True)
class RestitutionFit:
    """Every law fitted to one e(v) data set, and what the data can tell.

    ``laws`` maps law name -> :class:`RestitutionLawFit`; ``ranking`` lists the laws best
    first by AICc (empty when there are too few points to rank); ``verdict`` is the plain
    sentence; ``sigma_source``: ``given``, ``replicates`` or ``residuals``; ``rejected`` and
    ``impacts`` come from bounce or audio input (see :mod:`.bounces`)."""

    data: RestitutionData
    laws: dict[str, RestitutionLawFit]
    ranking: list[str]
    verdict: str
    sigma_source: str
    end: str
    vref: float
    notes: list[str] = field(default_factory=list)
    rejected: list[dict[str, Any]] = field(default_factory=list)
    impacts: list[list[float]] = field(default_factory=list)

    @property
    def best(self) -> RestitutionLawFit:
        """The first of the ranking; without one, the smallest rms among the laws with fewer
        constants than points (a law with as many constants as points fits any data)."""
        if self.ranking:
            return self.laws[self.ranking[0]]
        pool = [k for k, f in self.laws.items() if f.n_params < self.data.n] or list(self.laws)
        return self.laws[min(pool, key=lambda k: self.laws[k].rms)]

    def to_dict(self) -> dict[str, Any]:
        """The ``restitution`` object of ``viscontact fit --json``."""
        d = self.data
        return {
            "data": {"v": [float(x) for x in d.v], "e": [float(x) for x in d.e],
                     "sigma_e": None if d.sigma is None else [float(x) for x in d.sigma],
                     "source": d.source},
            "rejected": self.rejected, "impacts": self.impacts,
            "end": self.end, "vref": self.vref, "sigma_source": self.sigma_source,
            "laws": {k: f.to_dict() for k, f in self.laws.items()},
            "ranking": self.ranking, "verdict": self.verdict, "notes": self.notes,
        }


def fit_restitution(
    data: RestitutionData, laws: Sequence[str] = RES_LAWS, *, end: str = "force",
    vref: float | None = None, mass: float | None = None, k_hertz: float | None = None,
    rejected: Sequence[dict[str, Any]] = (), impacts: Sequence[Sequence[float]] = (),
) -> RestitutionFit:
    """Fit every law in ``laws`` to ``data`` by weighted least squares in e, rank them.

    ``vref`` [m/s]: where alpha_ref (beta_ref) is stated (default: the geometric mean of the
    speeds, three digits).  ``mass`` [kg] (m*; a ball on a plate: its mass) with ``k_hertz``
    [N/m^1.5] gives c and tau; with ``mass`` and contact times in ``data.tc`` and no
    ``k_hertz``, k_Hertz is measured from them per law (each law's own t_c(alpha)/T).
    """
    check_end(end)
    if not isinstance(data, RestitutionData):
        raise ValueError("data must be RestitutionData (read_restitution or restitution_data)")
    if isinstance(laws, str):
        laws = (laws,)
    if not isinstance(laws, (list, tuple)) or not all(isinstance(x, str) for x in laws):
        raise ValueError(f"laws must be law names ({', '.join(RES_LAWS)}), got {laws!r:.60}")
    vref = None if vref is None else check_positive("vref", vref)
    mass = None if mass is None else domain.check("mass", mass)
    k_hertz = None if k_hertz is None else domain.check("k_hertz", k_hertz)
    names = list(dict.fromkeys(lookup(x).name for x in laws))
    if not names:
        raise ValueError(f"give at least one law ({', '.join(RES_LAWS)})")
    n = data.n
    vref = _default_vref(data.v) if vref is None else float(vref)
    w, source = _sigma_weights(data.v, data.e, data.sigma)
    known = source != "residuals"
    fits: dict[str, RestitutionLawFit] = {}
    for name in names:
        fits[name] = _fit_one(name, data, w, known, vref, end, mass, k_hertz)
    ranked = all(f.aicc is not None for f in fits.values())
    ranking = sorted(fits, key=lambda k: fits[k].aicc) if ranked else []
    verdict = _verdict(fits, ranking, n)
    notes = [f"uncertainties from {_SOURCE_TEXT[source]}"]
    for f in fits.values():
        if f.beta is not None and not math.exp(_LN_BETA[0]) * 1.01 < f.beta < math.exp(_LN_BETA[1]) / 1.01:
            notes.append(f"{f.law}: beta_ref = {f.beta:.3g} is at the end of its search range "
                         f"({math.exp(_LN_BETA[0]):g} to {math.exp(_LN_BETA[1]):g}): the data do "
                         "not determine it (beta -> 0 is KK; a large beta damps only late in "
                         "the contact), so its constants are not to be trusted")
    return RestitutionFit(data, fits, ranking, verdict, source, end, vref, notes,
                          list(rejected), [list(map(float, t)) for t in impacts])


_SOURCE_TEXT = {"given": "the given sigma_e",
                "replicates": "the scatter of replicates (rows at one speed, one pooled sigma)",
                "residuals": "the residuals (sigma^2 = RSS / (n - k))"}


def _fit_one(name: str, data: RestitutionData, w: np.ndarray, known: bool, vref: float,
             end: str, mass: float | None, k_hertz: float | None) -> RestitutionLawFit:
    n = data.n
    k = _n_params(name)
    loo_ok = n >= k + 2
    refit = loo_ok and n <= _LOO_REFIT_MAX
    P = 1 + (n if refit else 0)
    W = np.tile(w, (P, 1))
    if refit:
        W[np.arange(1, P), np.arange(n)] = 0.0  # problem i + 1 leaves point i out
    b = _Batch(name, np.tile(data.v, (P, 1)), np.tile(data.e, (P, 1)), W, vref, end)
    theta, m, A = _lm(b)
    chi2 = float(_cost(b, m)[0])
    cov = _errors(A[:1], np.array([chi2]), n, k, known)[0]
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    e_fit = m[0]
    loo = None
    if refit:
        loo = float(np.sqrt(np.mean((m[np.arange(1, P), np.arange(n)] - data.e) ** 2)))
    elif loo_ok:  # many points: the leverage form, r_i / (1 - h_ii) (exact for linear models)
        J = _jacobian(_Batch(name, b.v[:1], b.e[:1], b.w[:1], vref, end), theta[:1], m[:1])[0]
        h = w * np.einsum("ni,ij,nj->n", J, np.linalg.pinv(A[0]), J)
        loo = float(np.sqrt(np.mean(((data.e - e_fit) / np.maximum(1.0 - h, 1e-12)) ** 2)))
    aicc = _aicc(np.array([chi2]), n, k, known)[0]
    spec = lookup(name)
    alpha = float(np.exp(theta[0, 0]))
    beta = beta_err = p_err = None
    p = law_exponent(name, 0.0)
    if spec.needs_beta:
        beta, beta_err = float(np.exp(theta[0, 1])), float(np.exp(theta[0, 1]) * sd[1])
    elif spec.p is None:
        p, p_err = float(theta[0, 1]), float(sd[1])
    phys = _physical(name, alpha, beta, p, cov, vref, mass, k_hertz, data, end)
    return RestitutionLawFit(
        law=name, end=end, vref=vref, alpha=alpha, alpha_err=float(alpha * sd[0]), beta=beta,
        beta_err=beta_err, p=p, p_err=p_err, e_fit=e_fit,
        rms=float(np.sqrt(np.mean((e_fit - data.e) ** 2))),
        aicc=None if not np.isfinite(aicc) else float(aicc), loo=loo, n_params=k, **phys)


def _physical(name: str, alpha: float, beta: float | None, p: float, cov: np.ndarray,
              vref: float, mass: float | None, k_hertz: float | None, data: RestitutionData,
              end: str) -> dict[str, Any]:
    """c, tau (and k_Hertz from contact times) with their uncertainties, when the pair is known.

    c = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5), tau = beta T(vref) (Jian et al. 2019);
    errors by linear propagation in (ln alpha, ln beta or p) and, for a measured k, its
    standard error."""
    if mass is None:
        return {}
    k_err = None
    if k_hertz is None:
        if data.tc is None:
            return {}
        k_hertz, k_err = _k_from_contact_times(name, alpha, beta, p, vref, mass, data, end)
    ln_pref = ((3 - 2 * p) * math.log(mass) + (1 - 4 * p) * math.log(vref)
               + (2 + 2 * p) * math.log(k_hertz)) / 5.0
    c = alpha * math.exp(ln_pref)
    grad = np.zeros(cov.shape[0])
    grad[0] = 1.0
    if lookup(name).p is None:  # d ln c / dp
        grad[1] = (-2 * math.log(mass) - 4 * math.log(vref) + 2 * math.log(k_hertz)) / 5.0
    var_ln_c = float(grad @ cov @ grad)
    if k_err is not None:
        var_ln_c += ((2 + 2 * p) / 5.0 * k_err / k_hertz) ** 2
    out: dict[str, Any] = {"c": c, "c_err": c * math.sqrt(var_ln_c), "c_unit": damping_unit(p),
                           "k_hertz": k_hertz, "k_hertz_err": k_err}
    if beta is not None:
        T = time_scale(mass, k_hertz, vref)
        var_ln_t = float(cov[1, 1]) + (0.0 if k_err is None else (0.4 * k_err / k_hertz) ** 2)
        out["tau"], out["tau_err"] = beta * T, beta * T * math.sqrt(var_ln_t)
    return out


def _tc_over_T(law: str, alpha: float, beta: float | None, p: float, vref: float,
               v: np.ndarray, end: str) -> np.ndarray:
    """The law's own contact time t_c / T at impact speeds v, at alpha(v) (and beta(v)) of
    the fit (the undamped 3.218 only at alpha -> 0)."""
    from ..physics.laws import resolve
    from ..solvers.batch import solve_batch

    spec = lookup(law)
    s = v / vref
    a = np.minimum(alpha * s ** ((4 * p - 1) / 5.0), 1000.0)
    lp = resolve(law, beta=0.0 if spec.needs_beta else None, p=p if spec.p is None else None)
    b = None if beta is None else np.minimum(beta * s ** 0.2, 1000.0)
    return solve_batch(lp, a, end, beta=b, dissipated=False).tc


def _k_from_contact_times(name: str, alpha: float, beta: float | None, p: float, vref: float,
                          mass: float, data: RestitutionData, end: str) -> tuple[float, float]:
    """k_Hertz from each measured t_c with the law's own t_c / T (:func:`_tc_over_T`):
    T = t_c / that, k = m* / (T^(5/2) v^(1/2)); the mean and its standard error."""
    T = data.tc / _tc_over_T(name, alpha, beta, p, vref, data.v, end)
    k = mass / (T ** 2.5 * np.sqrt(data.v))
    err = float(np.std(k, ddof=1) / math.sqrt(k.size)) if k.size > 1 else float("nan")
    return float(np.mean(k)), err


def _verdict(fits: dict[str, RestitutionLawFit], ranking: list[str], n: int) -> str:
    """The plain sentence: who wins, by how much, and whether the data can tell."""
    if not ranking:
        need = max(f.n_params for f in fits.values()) + 2
        return (f"too few points to rank the laws: {n} points, AICc needs at least k + 2 "
                f"({need} for the two-constant laws); the fits are given without a ranking")
    best = fits[ranking[0]]
    ties = [k for k in ranking[1:] if fits[k].aicc - best.aicc < AICC_TIE]
    if not ties:
        if len(ranking) == 1:
            return f"{best.law} fits with rms {best.rms:.3g} (only one law fitted)"
        second = fits[ranking[1]]
        return (f"{best.law} fits best (AICc {second.aicc - best.aicc:.1f} below "
                f"{second.law}, the next; rms {best.rms:.3g} against {second.rms:.3g})")
    names = [best.law, *ties]
    listed = ", ".join(names[:-1]) + " and " + names[-1]
    return (f"the data cannot tell {listed} apart (AICc within {AICC_TIE:g} of the best, "
            f"{best.law}); more points or a wider range of speeds would")
