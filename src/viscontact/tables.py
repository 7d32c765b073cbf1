"""Precomputed interpolation tables of e(alpha) (and e(alpha, beta) for Jian), built from the exact solver.

A table is a set of Chebyshev pieces over alpha in [0, ALPHA_TABLE_MAX].  Each piece lives in
its own variable y, chosen so that e is analytic (or at least very smooth) in y:

- ``POWER`` y = alpha^(1/k) on [0, 1].  Under the zero-force end the contact stops where
  s^k + alpha g v = 0 (x = s^m, k = m (3/2 - p), see :mod:`viscontact.kernels`), so the end
  point and e are power series in alpha^(1/k); under the zero-overlap end (and for Hunt, whose
  force vanishes only with the overlap) the regularised equations are polynomial in alpha and
  k = 1.  For Jian, beta near 0 uses y = beta^(1/2) (the switch-on factor enters through
  t / beta, and t ~ s^2 near the start).
- ``LOG`` y = log(alpha) above 1 (the decay of e at large damping is smooth in log alpha).
- ``CRIT`` y = -(alpha_c - alpha)^(1/2) just below a critical alpha_c beyond which a zero-overlap
  contact never separates (LH, Tsuji): e vanishes there (like (alpha_c - alpha) for LH, faster
  than any power for Tsuji).
- ``ZERO`` e = 0 on [alpha_c, ALPHA_TABLE_MAX], where the exact solver reports no rebound.

Jian's e(alpha, beta) uses tensor-product pieces: rows of beta pieces (POWER with k = 2 on
[0, 1], LOG above), each row with its own alpha pieces (starting from the KK layout), so
that refinement stays local (under the zero-overlap end e has a steep ridge across the
(alpha, beta) plane where a slowly creeping return gives way to a prompt rebound).

Pieces are refined adaptively (halved in y) until the trailing Chebyshev coefficients fall
below ``_TAIL_TOL``; the finished table is checked against the exact solver on held-out
random points, piece boundaries and tiny alpha, and refused if any error exceeds
``VERIFY_TOL`` = 1e-10.  Tables are cached on disk (see :func:`cache_dir`) under a key that
hashes the source of every module that determines the values, so a code change rebuilds them.

Evaluation and inversion are compiled (numba, parallel over the input array).  The inverse
alpha(e) is a safeguarded Newton iteration on the (monotone decreasing) interpolant, started
by inverse quadratic interpolation in a dense sample of each piece (1D), or from the ends of
the piece (2D); it stops when the residual in e is below 1e-13, or when a Taylor bound puts
the residual after the last step below 1e-11 (one evaluation fewer; the contract is 1e-9).
A 1D piece is evaluated only up to its last coefficient that matters: the trailing ones it
skips sum to at most 1e-13.
"""

from __future__ import annotations

import hashlib
import math
import os
import sys
import tempfile
import threading
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numba
import numpy as np
from numpy.polynomial import chebyshev as npcheb
from numpy.typing import ArrayLike

__all__ = [
    "ALPHA_TABLE_MAX", "BETA_TABLE_MAX", "VERIFY_TOL", "TABLE_LAWS", "Table", "build_all",
    "cache_dir", "clear_memory", "code_key", "enabled", "exact_e", "get_table", "table_path",
    "through_tables",
]

#: alpha (and beta, Jian) range the tables cover; outside it the exact solver answers.
ALPHA_TABLE_MAX = 10.0
BETA_TABLE_MAX = 10.0
#: largest |e_table - e_exact| a table may show on its held-out points.
VERIFY_TOL = 1e-10
#: laws with a table (the general power law has a free exponent: no table).
TABLE_LAWS: tuple[str, ...] = ("LH", "Ts", "KK", "Li", "Hunt", "Jian")
#: switch the tables off (every call goes to the exact solver); tests compare both paths.
enabled: bool = True

POWER, LOG, CRIT, ZERO = 0, 1, 2, 3
_NODES_1D = 24  # Chebyshev points per 1D piece
_NODES_2D = (16, 16)  # per 2D piece, (alpha, beta)
_TAIL_TOL = 1e-12  # accept a piece when its last coefficients are below this (|e| <= 1)
_TAIL_TERMS = 3
_MAX_ROUNDS = 12  # refinement rounds (each halves the pieces that fail)
_NODE_RTOL = 1e-14  # batch solver tolerance for the nodes (e to ~1e-14)
_CRIT_WIDTH = 0.1  # width in alpha of the CRIT piece below alpha_c
_INVERSE_SAMPLES = 256  # dense samples per piece that start the Newton inversion
_TRUNC_TOL = 1e-13  # coefficients cut from a piece's end may change e by at most this
_INVERSE_TOL = 1e-13  # |e_table(alpha) - e| at which the inversion stops (contract: 1e-9)
#: bound on |e_table(alpha) - e| after a Newton step at which the inversion stops without
#: evaluating again (a bound, not a residual; still 100 times below the 1e-9 contract)
_STEP_TOL = 1e-11
_FORMAT = 2  # bump when the file layout changes

# "contract" lets a * b + c become one fused multiply-add (one rounding, half the latency of
# the Clenshaw chains); no other fast-math liberties.
_jit = numba.njit(cache=True, fastmath={"contract"}, nogil=True)
# the per-point helpers are inlined into the drivers: a call passing several arrays costs
# more than the arithmetic it runs
_ijit = numba.njit(cache=True, fastmath={"contract"}, nogil=True, inline="always")
_pjit = numba.njit(cache=True, fastmath={"contract"}, nogil=True, parallel=True)


# --------------------------------------------------------------------------------------------
# Compiled evaluation: piece maps, Clenshaw sums, location, the parallel drivers.
# --------------------------------------------------------------------------------------------


@_ijit
def _root(x: float, order: float) -> float:
    """x^(1/order): the orders met in practice (1, 2) without the slow general pow."""
    if order == 1.0:
        return x
    if order == 2.0:
        return math.sqrt(x)
    return x ** (1.0 / order)


@_ijit
def _power(y: float, order: float) -> float:
    """y^order, the inverse of :func:`_root`."""
    if order == 1.0:
        return y
    if order == 2.0:
        return y * y
    return y ** order


@_ijit
def _to_unit(x: float, kind: int, order: float, anchor: float, ylo: float, yhi: float) -> float:
    """Map x (alpha or beta) in a piece to xi in [-1, 1] through the piece's variable y."""
    if kind == POWER:
        y = _root(x, order)
    elif kind == LOG:
        y = math.log(x)
    elif kind == CRIT:  # y grows with x, as in every piece
        y = -math.sqrt(max(anchor - x, 0.0))
    else:
        return 0.0
    xi = (2.0 * y - (ylo + yhi)) / (yhi - ylo)
    return min(1.0, max(-1.0, xi))


@_ijit
def _from_unit(xi: float, kind: int, order: float, anchor: float, ylo: float, yhi: float) -> float:
    """Inverse of :func:`_to_unit` (x from xi)."""
    y = 0.5 * (ylo + yhi) + 0.5 * (yhi - ylo) * xi
    if kind == POWER:
        return _power(max(y, 0.0), order)
    if kind == LOG:
        return math.exp(y)
    if kind == CRIT:
        return anchor - y * y
    return y  # ZERO: y = x


@_ijit
def _cheb(c, xi: float) -> float:
    """sum_k c_k T_k(xi) by Clenshaw's recurrence."""
    b1 = 0.0
    b2 = 0.0
    x2 = 2.0 * xi
    for k in range(c.shape[0] - 1, 0, -1):
        b1, b2 = x2 * b1 - b2 + c[k], b1
    return xi * b1 - b2 + c[0]


@_ijit
def _cheb_d(c, xi: float):
    """(sum_k c_k T_k(xi), its derivative in xi): Clenshaw for T and for U (T_k' = k U_{k-1})."""
    n = c.shape[0]
    b1 = 0.0
    b2 = 0.0
    d1 = 0.0
    d2 = 0.0
    x2 = 2.0 * xi
    for k in range(n - 1, 0, -1):
        d1, d2 = x2 * d1 - d2 + k * c[k], d1
        b1, b2 = x2 * b1 - b2 + c[k], b1
    return xi * b1 - b2 + c[0], d1


@_ijit
def _locate(breaks, x: float) -> int:
    """Index i with breaks[i] <= x <= breaks[i+1] (x inside [breaks[0], breaks[-1]])."""
    lo = 0
    hi = breaks.shape[0] - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if breaks[mid] <= x:
            lo = mid
        else:
            hi = mid - 1
    return lo


@_ijit
def _eval1(breaks, kind, order, anchor, ylo, yhi, coef, deg, x: float) -> float:
    if not (0.0 <= x <= breaks[-1]):
        return math.nan
    i = _locate(breaks, x)
    return _cheb(coef[i, :deg[i]], _to_unit(x, kind[i], order[i], anchor[i], ylo[i], yhi[i]))


@_pjit
def _eval1_many(breaks, kind, order, anchor, ylo, yhi, coef, deg, x, out):
    """out = e(x) for every element (NaN outside the table)."""
    for j in numba.prange(x.shape[0]):
        out[j] = _eval1(breaks, kind, order, anchor, ylo, yhi, coef, deg, x[j])


@_ijit
def _solve_piece(c, target: float, xa: float, xb: float, ea: float, eb: float,
                 xi: float, curvature: float) -> float:
    """xi in [xa, xb] with sum c_k T_k(xi) = target, the sum decreasing from ea to eb there.

    Newton's method from the guess ``xi`` (NaN: the linear interpolant), kept inside a
    shrinking bracket (bisection when a step leaves it); stops when the residual in e is
    below _INVERSE_TOL, or after a step d whose residual is bounded by curvature d^2 / 2
    below _STEP_TOL (``curvature`` >= max |second derivative| on the piece; Taylor).
    """
    if ea <= eb:
        return xa
    if not (xa <= xi <= xb):
        xi = xa + (xb - xa) * (ea - target) / (ea - eb)
    for _ in range(60):
        f, df = _cheb_d(c, xi)
        f -= target
        if abs(f) <= _INVERSE_TOL:
            break
        if f > 0.0:
            xa = xi
        else:
            xb = xi
        new = xi - f / df if df < 0.0 else math.nan
        if not (xa < new < xb):
            new = 0.5 * (xa + xb)
        elif 0.5 * curvature * (new - xi) ** 2 <= _STEP_TOL:
            return new
        if new == xi or xb - xa <= 4e-16:
            break
        xi = new
    return xi


@_ijit
def _inverse_quadratic(x0: float, e0: float, x1: float, e1: float, x2: float, e2: float,
                       target: float) -> float:
    """x where the parabola x(e) through three points takes e = ``target`` (NaN if two e agree)."""
    if e0 == e1 or e1 == e2 or e0 == e2:
        return math.nan
    return (x0 * (target - e1) * (target - e2) / ((e0 - e1) * (e0 - e2))
            + x1 * (target - e0) * (target - e2) / ((e1 - e0) * (e1 - e2))
            + x2 * (target - e0) * (target - e1) / ((e2 - e0) * (e2 - e1)))


@_ijit
def _bracket(s, target: float) -> int:
    """a with s[a] >= target > s[a + 1] (s decreasing, s[0] >= target >= s[-1])."""
    a = 0
    b = s.shape[0] - 1
    while b - a > 1:
        mid = (a + b) // 2
        if s[mid] >= target:
            a = mid
        else:
            b = mid
    return a


@_ijit
def _solve_sampled(c, s, a: int, target: float, curvature: float) -> float:
    """xi in [-1, 1] with sum c_k T_k(xi) = target, given the e samples ``s`` at evenly
    spaced xi with s[a] >= target >= s[a + 1]: Newton from the inverse parabola through
    samples a, a + 1 and a neighbour (close enough that one step usually suffices)."""
    ns = s.shape[0]
    h = 2.0 / (ns - 1)
    n3 = a + 2 if a + 2 < ns else a - 1
    x0 = -1.0 + a * h
    guess = _inverse_quadratic(x0, s[a], x0 + h, s[a + 1], -1.0 + n3 * h, s[n3], target)
    return _solve_piece(c, target, x0, x0 + h, s[a], s[a + 1], guess, curvature)


@_ijit
def _invert1(breaks, kind, order, anchor, ylo, yhi, coef, deg, samples, curvature,
             target: float) -> float:
    """alpha with e_table(alpha) = target; NaN when the target is below the table's e range.

    ``samples[i]`` holds e at evenly spaced xi in piece i; e decreases along every piece
    (the piece variables all grow with alpha) and from piece to piece.
    """
    npc = coef.shape[0]
    ns = samples.shape[1]
    if target >= 1.0 or target >= samples[0, 0]:  # e = 1 only without damping
        return 0.0
    lo = 0
    hi = npc - 1
    while lo < hi:  # the last piece whose first sample is >= target
        mid = (lo + hi + 1) // 2
        if samples[mid, 0] >= target:
            lo = mid
        else:
            hi = mid - 1
    i = lo
    if target < samples[i, ns - 1]:  # between pieces (they agree to ~1e-12) or below the table
        if i + 1 < npc and kind[i + 1] != ZERO:
            return breaks[i + 1]
        return math.nan
    s = samples[i]
    xi = _solve_sampled(coef[i, :deg[i]], s, _bracket(s, target), target, curvature[i])
    return _from_unit(xi, kind[i], order[i], anchor[i], ylo[i], yhi[i])


@_pjit
def _invert1_many(breaks, kind, order, anchor, ylo, yhi, coef, deg, samples, curvature, e, out):
    for j in numba.prange(e.shape[0]):
        out[j] = _invert1(breaks, kind, order, anchor, ylo, yhi, coef, deg, samples, curvature,
                          e[j])


@_ijit
def _basis(xi: float, t):
    """t[l] = T_l(xi) for every l."""
    t[0] = 1.0
    if t.shape[0] > 1:
        t[1] = xi
    for k in range(2, t.shape[0]):
        t[k] = 2.0 * xi * t[k - 1] - t[k - 2]


@_ijit
def _rows(ct, tb, r):
    """r[k] = sum_l ct[l, k] tb[l]: a 2D piece (stored transposed, beta index first) reduced
    to a Chebyshev series in alpha; the inner loop runs over k, so it vectorises."""
    r[:] = 0.0
    for l in range(ct.shape[0]):
        w = tb[l]
        for k in range(ct.shape[1]):
            r[k] += ct[l, k] * w


@_ijit
def _unit2(ax, x: float):
    """(piece index, xi) of x on an axis (breaks, kind, order, anchor, ylo, yhi)."""
    i = _locate(ax[0], x)
    return i, _to_unit(x, ax[1][i], ax[2][i], ax[3][i], ax[4][i], ax[5][i])


@_ijit
def _row(rows, j: int):
    """(first piece, number of pieces) of beta row j on the concatenated alpha axis."""
    return rows[j], rows[j + 1] - rows[j]


@_ijit
def _eval2(ax, rows, bx, ct, a: float, b: float, tb, r) -> float:
    if not (0.0 <= b <= bx[0][-1]):
        return math.nan
    j, xb = _unit2(bx, b)
    g0, n = _row(rows, j)
    brk = ax[0][g0 + j:g0 + j + n + 1]  # this row's alpha breaks
    if not (0.0 <= a <= brk[n]):
        return math.nan
    g = g0 + _locate(brk, a)
    xa = _to_unit(a, ax[1][g], ax[2][g], ax[3][g], ax[4][g], ax[5][g])
    _basis(xb, tb)
    _rows(ct[g], tb, r)
    return _cheb(r, xa)


@_ijit
def _dot(c, t) -> float:
    """sum_l c[l] t[l] in four interleaved partial sums (four independent chains)."""
    n = t.shape[0]
    a0 = a1 = a2 = a3 = 0.0
    for l in range(0, n - 3, 4):
        a0 += c[l] * t[l]
        a1 += c[l + 1] * t[l + 1]
        a2 += c[l + 2] * t[l + 2]
        a3 += c[l + 3] * t[l + 3]
    for l in range(n - n % 4, n):
        a0 += c[l] * t[l]
    return (a0 + a1) + (a2 + a3)


@_ijit
def _invert2(ax, rows, bx, ct, edges, e: float, b: float, tb, r) -> float:
    """alpha with e_table(alpha, b) = e; NaN outside the table.

    ``edges[g, 0]`` and ``edges[g, 1]`` are the beta series of e at the left and right end
    of block g, so the alpha piece is found without reducing every block of the row.
    """
    if not (0.0 <= b <= bx[0][-1]):
        return math.nan
    j, xb = _unit2(bx, b)
    g0, n = _row(rows, j)
    _basis(xb, tb)
    top = _dot(edges[g0, 0], tb)
    if e >= 1.0 or e >= top:  # e = 1 only without damping
        return 0.0
    lo = 0
    hi = n - 1
    e_lo = top
    while lo < hi:  # the last piece whose left end has e >= target
        mid = (lo + hi + 1) // 2
        v = _dot(edges[g0 + mid, 0], tb)
        if v >= e:
            lo = mid
            e_lo = v
        else:
            hi = mid - 1
    g = g0 + lo
    e_hi = _dot(edges[g, 1], tb)
    if e < e_hi:  # between two pieces that agree to ~1e-12, or below the table
        return ax[0][g + j + 1] if lo + 1 < n else math.nan
    _rows(ct[g], tb, r)
    bound = 0.0  # |T_k''| <= k^2 (k^2 - 1) / 3 on [-1, 1]: a bound on the series' curvature
    for k in range(2, r.shape[0]):
        bound += abs(r[k]) * (k * k * (k * k - 1.0) / 3.0)
    xi = _solve_piece(r, e, -1.0, 1.0, e_lo, e_hi, math.nan, bound)
    return _from_unit(xi, ax[1][g], ax[2][g], ax[3][g], ax[4][g], ax[5][g])


@_pjit
def _many2(ax, rows, bx, ct, edges, x, b, out, chunks, invert: bool):
    """out = e(x, b) (or alpha(x, b) when ``invert``) over the arrays, in parallel chunks
    that allocate their scratch rows once."""
    n = x.shape[0]
    size = (n + chunks - 1) // chunks
    for ch in numba.prange(chunks):
        tb = np.empty(ct.shape[1])
        r = np.empty(ct.shape[2])
        for j in range(ch * size, min(n, (ch + 1) * size)):
            if invert:
                out[j] = _invert2(ax, rows, bx, ct, edges, x[j], b[j], tb, r)
            else:
                out[j] = _eval2(ax, rows, bx, ct, x[j], b[j], tb, r)


# --------------------------------------------------------------------------------------------
# Tables: data, evaluation, inversion.
# --------------------------------------------------------------------------------------------

def _chunks() -> int:
    """Work items of the 2D driver :func:`_many2`."""
    return 8 * numba.get_num_threads()


_AXIS_FIELDS = ("breaks", "kind", "order", "anchor", "ylo", "yhi")


@dataclass(frozen=True)
class Piece:
    """One interval of an axis, in its own variable y (see the module docstring)."""

    kind: int
    order: float  # k of y = x^(1/k) (POWER)
    anchor: float  # alpha_c (CRIT)
    ylo: float
    yhi: float

    def x_at(self, xi: np.ndarray | float) -> np.ndarray:
        """Points x (alpha or beta) at unit coordinates xi."""
        return np.vectorize(_from_unit, otypes=[float])(
            xi, self.kind, self.order, self.anchor, self.ylo, self.yhi)

    def halves(self) -> tuple[Piece, Piece]:
        mid = 0.5 * (self.ylo + self.yhi)
        return (Piece(self.kind, self.order, self.anchor, self.ylo, mid),
                Piece(self.kind, self.order, self.anchor, mid, self.yhi))


def _axis(pieces: list[Piece]) -> tuple[np.ndarray, ...]:
    """The compiled kernels' axis tuple (breaks, kind, order, anchor, ylo, yhi)."""
    pieces = sorted(pieces, key=lambda pc: float(pc.x_at(-1.0)))
    breaks = np.array([float(pc.x_at(-1.0)) for pc in pieces] + [float(pieces[-1].x_at(1.0))])
    breaks[0] = 0.0
    return (breaks, np.array([pc.kind for pc in pieces], dtype=np.int64),
            *(np.array([getattr(pc, f) for pc in pieces], dtype=float)
              for f in ("order", "anchor", "ylo", "yhi")))


def _axis_pieces(axis: tuple[np.ndarray, ...]) -> list[Piece]:
    return [Piece(int(k), float(o), float(a), float(lo), float(hi))
            for k, o, a, lo, hi in zip(*axis[1:])]


def _degree(weights: np.ndarray) -> int:
    """Terms to keep of a Chebyshev series whose k-th term is at most weights[k] in size:
    the trailing ones sum to at most _TRUNC_TOL (|T_k| <= 1), so Clenshaw skips them."""
    tail = np.cumsum(weights[::-1])[::-1]  # tail[k] = sum of weights[k:]
    return max(1, int(np.count_nonzero(tail > _TRUNC_TOL)))


@dataclass
class Table:
    """Piecewise Chebyshev interpolant of e(alpha) (``beta_axis`` None) or e(alpha, beta).

    1D: ``coef`` has shape (pieces, n).  2D: every beta piece j (a row) has its own alpha
    pieces, so refinement stays local to where e varies fast; ``rows[j]:rows[j+1]`` are the
    row's blocks in ``coef`` (blocks, n_alpha, n_beta) and in the concatenated alpha axis,
    whose breaks of row j sit at ``rows[j] + j`` to ``rows[j+1] + j``.
    ``max_error`` is the largest |e_table - e_exact| seen on the held-out points at build
    time; ``nodes`` the number of exact solves the build took.
    """

    law: str
    end: str
    alpha_axis: tuple[np.ndarray, ...]
    coef: np.ndarray
    beta_axis: tuple[np.ndarray, ...] | None = None
    rows: np.ndarray | None = None
    max_error: float = math.nan
    nodes: int = 0
    build_seconds: float = math.nan

    def __post_init__(self) -> None:
        """Derive what the compiled kernels use: (1D) each piece's degree, the coefficients
        Clenshaw needs (the 2D blocks keep all theirs: cutting them to per-block degrees
        cost more in lost vectorisation than it saved), and the samples that start the
        inversion."""
        if self.beta_axis is None:  # dense samples that start the inversion
            self._deg = np.array([_degree(np.abs(c)) for c in self.coef], dtype=np.int64)
            cut = [c[:n] for c, n in zip(self.coef, self._deg)]
            xi = np.linspace(-1.0, 1.0, _INVERSE_SAMPLES)
            self._inv = np.array([npcheb.chebval(xi, c) for c in cut])
            # sum |c''_k| >= max |e''| on a piece (|T_k| <= 1): bounds a Newton step's residual
            self._curvature = np.array([np.sum(np.abs(npcheb.chebder(c, 2))) for c in cut])
        else:  # beta series of e at both ends of every alpha piece
            left = np.einsum("k,gkl->gl", (-1.0) ** np.arange(self.coef.shape[1]), self.coef)
            self._inv = np.ascontiguousarray(np.stack([left, self.coef.sum(axis=1)], axis=1))
            self._ct = np.ascontiguousarray(self.coef.transpose(0, 2, 1))  # for _rows

    def _kernel_2d(self) -> tuple:
        return self.alpha_axis, self.rows, self.beta_axis, self._ct, self._inv

    def e(self, alpha: np.ndarray, beta: np.ndarray | None = None) -> np.ndarray:
        """e at each alpha (and beta); NaN where the point lies outside the table."""
        a = np.ascontiguousarray(alpha, dtype=float).ravel()
        out = np.empty(a.shape)
        if self.beta_axis is None:
            _eval1_many(*self.alpha_axis, self.coef, self._deg, a, out)
        else:
            b = np.ascontiguousarray(beta, dtype=float).ravel()
            _many2(*self._kernel_2d(), a, b, out, _chunks(), False)
        return out.reshape(np.shape(alpha))

    def alpha(self, e: np.ndarray, beta: np.ndarray | None = None) -> np.ndarray:
        """alpha with e_table(alpha) = e for each e in (0, 1]; NaN where the table does not reach."""
        t = np.ascontiguousarray(e, dtype=float).ravel()
        out = np.empty(t.shape)
        if self.beta_axis is None:
            _invert1_many(*self.alpha_axis, self.coef, self._deg, self._inv, self._curvature, t,
                          out)
        else:
            b = np.ascontiguousarray(beta, dtype=float).ravel()
            _many2(*self._kernel_2d(), t, b, out, _chunks(), True)
        return out.reshape(np.shape(e))

    def to_arrays(self) -> dict[str, np.ndarray]:
        arrays = {f"alpha_{f}": v for f, v in zip(_AXIS_FIELDS, self.alpha_axis)}
        if self.beta_axis is not None:
            arrays |= {f"beta_{f}": v for f, v in zip(_AXIS_FIELDS, self.beta_axis)}
            arrays["rows"] = self.rows
        return arrays | {
            "coef": self.coef, "max_error": np.float64(self.max_error),
            "nodes": np.int64(self.nodes), "build_seconds": np.float64(self.build_seconds),
            "format": np.int64(_FORMAT),
        }

    @classmethod
    def from_arrays(cls, law: str, end: str, d) -> Table:
        if int(d["format"]) != _FORMAT:
            raise ValueError("old table format")
        alpha_axis = tuple(d[f"alpha_{f}"] for f in _AXIS_FIELDS)
        beta_axis = tuple(d[f"beta_{f}"] for f in _AXIS_FIELDS) if "beta_breaks" in d else None
        rows = None if beta_axis is None else np.asarray(d["rows"], dtype=np.int64)
        coef = np.ascontiguousarray(d["coef"], dtype=float)
        npc = coef.shape[0]
        n_rows = 1 if rows is None else rows.size - 1
        ok = (alpha_axis[0].size == npc + n_rows and all(v.shape == (npc,) for v in alpha_axis[1:])
              and coef.ndim == (2 if rows is None else 3))
        if rows is not None:
            ok = ok and beta_axis[0].size == rows.size and rows[0] == 0 and rows[-1] == npc and \
                bool(np.all(np.diff(rows) > 0))
        if not ok or not np.all(np.isfinite(coef)):
            raise ValueError("inconsistent table arrays")
        return cls(law, end, alpha_axis, coef, beta_axis, rows, float(d["max_error"]),
                   int(d["nodes"]), float(d["build_seconds"]))


# --------------------------------------------------------------------------------------------
# Building from the exact solver.
# --------------------------------------------------------------------------------------------

Exact = Callable[[np.ndarray, np.ndarray | None], np.ndarray]


def exact_e(law: str, end: str, alpha: ArrayLike, beta: ArrayLike | None = None) -> np.ndarray:
    """e by the exact (batch) solver at the tables' node tolerance (|error| ~ 1e-14)."""
    from .laws import resolve
    from .solvers import solve_batch

    lp = resolve(law, beta=0.0 if law == "Jian" else None)
    return solve_batch(lp, alpha, end, beta=beta, rtol=_NODE_RTOL).e


class _Solver:
    """:func:`exact_e` for batches of points, counting them on a progress bar."""

    chunk = 4096  # solves per progress-bar update

    def __init__(self, law: str, end: str, bar) -> None:
        self.law, self.end, self.bar, self.count = law, end, bar, 0

    def __call__(self, alpha: np.ndarray, beta: np.ndarray | None = None) -> np.ndarray:
        alpha = np.asarray(alpha, dtype=float).ravel()
        self.bar.total = (self.bar.total or 0) + alpha.size
        out = np.empty(alpha.size)
        for i in range(0, alpha.size, self.chunk):
            part = slice(i, i + self.chunk)
            out[part] = exact_e(self.law, self.end, alpha[part],
                                None if beta is None else np.asarray(beta, dtype=float).ravel()[part])
            self.bar.update(out[part].size)
        self.count += alpha.size
        return out


def _coef_matrix(n: int) -> np.ndarray:
    """M with c = M f: Chebyshev coefficients from values at the n first-kind Chebyshev points."""
    m = (2.0 / n) * npcheb.chebvander(npcheb.chebpts1(n), n - 1).T
    m[0] /= 2.0
    return m


def _tail(c: np.ndarray, axis: int = -1) -> float:
    return float(np.max(np.abs(np.take(c, range(c.shape[axis] - _TAIL_TERMS, c.shape[axis]),
                                       axis=axis))))


def _start_order(law: str, end: str) -> float:
    """k of the first piece's variable alpha^(1/k) (module docstring)."""
    from .laws import resolve

    lp = resolve(law, beta=0.0 if law == "Jian" else None)
    return lp.m * (1.5 - lp.p) if end == "force" and lp.p < 1.5 else 1.0


def _critical_alpha(exact: Exact) -> float | None:
    """alpha_c beyond which the exact solver reports no rebound (None if e(ALPHA_TABLE_MAX) > 0).

    Sections of [lo, hi] by 31 points a round (one batch solve each), to a few ulp.
    """
    if exact(np.array([ALPHA_TABLE_MAX]))[0] > 0:
        return None
    lo, hi = 0.0, ALPHA_TABLE_MAX
    points = 31
    while hi - lo > 4e-16 * hi:
        pts = np.linspace(lo, hi, points + 2)[1:-1]
        separated = exact(pts) > 0
        n_sep = int(np.argmin(separated)) if not separated.all() else points
        lo = pts[n_sep - 1] if n_sep > 0 else lo
        hi = pts[n_sep] if n_sep < points else hi
    return lo


def _initial_pieces(law: str, end: str, alpha_c: float | None) -> list[Piece]:
    """The layout of the module docstring, before refinement (ZERO piece excluded)."""
    top = ALPHA_TABLE_MAX if alpha_c is None else alpha_c - min(_CRIT_WIDTH, alpha_c / 2)
    k = _start_order(law, end)
    pieces = [Piece(POWER, k, 0.0, 0.0, min(1.0, top) ** (1.0 / k))]
    if top > 1.0:
        pieces.append(Piece(LOG, 1.0, 0.0, 0.0, math.log(top)))
    if alpha_c is not None:
        pieces.append(Piece(CRIT, 1.0, alpha_c, -math.sqrt(alpha_c - top), 0.0))
    return pieces


def _refine_1d(pieces: list[Piece], exact: Exact, n: int) -> list[tuple[Piece, np.ndarray]]:
    """Halve pieces until their trailing coefficients fall below _TAIL_TOL."""
    xi, m = npcheb.chebpts1(n), _coef_matrix(n)
    done: list[tuple[Piece, np.ndarray]] = []
    for rnd in range(_MAX_ROUNDS):
        if not pieces:
            break
        values = exact(np.concatenate([pc.x_at(xi) for pc in pieces])).reshape(len(pieces), n)
        later = []
        for pc, f in zip(pieces, values):
            c = m @ f
            if _tail(c) <= _TAIL_TOL or rnd == _MAX_ROUNDS - 1:
                done.append((pc, c))
            else:
                later.extend(pc.halves())
        pieces = later
    return done


def _refine_2d(a_init: list[Piece], b_init: list[Piece], exact: Exact, n: tuple[int, int]
               ) -> tuple[list[Piece], list[list[Piece]], list[list[np.ndarray]]]:
    """Rows (beta pieces), each with its own alpha pieces, refined in rounds: a block with alpha
    coefficients above _TAIL_TOL has its alpha piece halved (in its row only), and a row with
    a block whose beta coefficients exceed _TAIL_TOL is halved (both halves keep the row's
    alpha pieces)."""
    xa, xb = npcheb.chebpts1(n[0]), npcheb.chebpts1(n[1])
    ma, mb = _coef_matrix(n[0]), _coef_matrix(n[1])
    blocks: dict[tuple[Piece, Piece], np.ndarray] = {}

    def evaluate(rows: dict[Piece, list[Piece]]) -> None:
        todo = [(pa, pb) for pb, row in rows.items() for pa in row if (pa, pb) not in blocks]
        if todo:
            grids = [np.meshgrid(pa.x_at(xa), pb.x_at(xb), indexing="ij") for pa, pb in todo]
            values = exact(np.concatenate([g[0].ravel() for g in grids]),
                           np.concatenate([g[1].ravel() for g in grids]))
            for key, f in zip(todo, values.reshape(len(todo), *n)):
                blocks[key] = ma @ f @ mb.T

    rows = {pb: list(a_init) for pb in b_init}
    for _ in range(2 * _MAX_ROUNDS):
        evaluate(rows)
        new_rows: dict[Piece, list[Piece]] = {}
        for pb, row in rows.items():
            split = [pa.halves() if _tail(blocks[pa, pb], 0) > _TAIL_TOL else (pa,) for pa in row]
            row_split = [h for parts in split for h in parts]
            if any(_tail(blocks[pa, pb], 1) > _TAIL_TOL for pa in row):
                new_rows |= {half: row_split for half in pb.halves()}
            else:
                new_rows[pb] = row_split
        if new_rows == rows:
            break
        rows = new_rows
    evaluate(rows)  # the last round's halves, should the rounds run out
    key = lambda pc: float(pc.x_at(-1.0))  # noqa: E731
    b_pieces = sorted(rows, key=key)
    a_rows = [sorted(rows[pb], key=key) for pb in b_pieces]
    return b_pieces, a_rows, [[blocks[pa, pb] for pa in row] for pb, row in zip(b_pieces, a_rows)]


def _held_out(pieces: list[Piece], rng: np.random.Generator, per_piece: int = 2) -> np.ndarray:
    """Random points in every piece, the piece ends, and tiny values near 0."""
    pts = [pc.x_at(rng.uniform(-1.0, 1.0, per_piece)) for pc in pieces]
    ends = [pc.x_at(np.array([-1.0, 1.0])) for pc in pieces]
    return np.unique(np.concatenate(pts + ends + [np.array([1e-9, 1e-6, 1e-3])]))


def _build_1d(law: str, end: str, exact: Exact, rng: np.random.Generator) -> tuple[Table, float]:
    """(table, largest held-out error) of e(alpha)."""
    alpha_c = _critical_alpha(exact)
    done = _refine_1d(_initial_pieces(law, end, alpha_c), exact, _NODES_1D)
    if alpha_c is not None:
        done.append((Piece(ZERO, 1.0, 0.0, alpha_c, ALPHA_TABLE_MAX), np.zeros(_NODES_1D)))
    done.sort(key=lambda item: float(item[0].x_at(-1.0)))
    pieces = [pc for pc, _ in done]
    table = Table(law, end, _axis(pieces), np.array([c for _, c in done]))
    pts = _held_out(pieces, rng)
    return table, float(np.max(np.abs(table.e(pts) - exact(pts))))


def _build_2d(law: str, end: str, exact: Exact, rng: np.random.Generator) -> tuple[Table, float]:
    """(table, largest held-out error) of e(alpha, beta); alpha pieces start from the KK table's."""
    kk = get_table("KK", end)
    if kk is None:
        raise RuntimeError("the KK table is needed to lay out the Jian table")
    a_init = [pc for pc in _axis_pieces(kk.alpha_axis) if pc.kind != ZERO]
    b_init = [Piece(POWER, 2.0, 0.0, 0.0, 1.0), Piece(LOG, 1.0, 0.0, 0.0, math.log(BETA_TABLE_MAX))]
    b_pieces, a_rows, coefs = _refine_2d(a_init, b_init, exact, _NODES_2D)
    row_axes = [_axis(row) for row in a_rows]
    alpha_axis = tuple(np.concatenate(parts) for parts in zip(*row_axes))
    rows = np.cumsum([0] + [len(row) for row in a_rows]).astype(np.int64)
    table = Table(law, end, alpha_axis, np.array([c for row in coefs for c in row]),
                  _axis(b_pieces), rows)
    a_pts = _held_out(list({pa for row in a_rows for pa in row}), rng, 1)
    b_pts = _held_out(b_pieces, rng)
    n_rand = 4 * (a_pts.size + b_pts.size)
    pa = np.concatenate([rng.choice(a_pts, b_pts.size), a_pts, rng.uniform(0, ALPHA_TABLE_MAX, n_rand)])
    pb = np.concatenate([b_pts, rng.choice(b_pts, a_pts.size), rng.uniform(0, BETA_TABLE_MAX, n_rand)])
    return table, float(np.max(np.abs(table.e(pa, pb) - exact(pa, pb))))


def _build(law: str, end: str) -> Table:
    """Build and verify one table from the exact solver (refuses one that misses VERIFY_TOL)."""
    import time

    from tqdm import tqdm

    t0 = time.perf_counter()
    rng = np.random.default_rng(20190735)  # deterministic held-out points
    with tqdm(desc=f"viscontact: {law} table ({end} end)", unit="solve", file=sys.stderr,
              delay=1.0, leave=False, disable=None) as bar:  # None: no bar off a terminal
        exact = _Solver(law, end, bar)
        table, error = (_build_2d if law == "Jian" else _build_1d)(law, end, exact, rng)
    table.max_error, table.nodes = error, exact.count
    table.build_seconds = time.perf_counter() - t0
    if not table.max_error <= VERIFY_TOL:
        raise RuntimeError(f"{law} table ({end} end) misses the exact solver by "
                           f"{table.max_error:.2e} > {VERIFY_TOL:g}")
    return table
# --------------------------------------------------------------------------------------------
# Cache: in memory per process, on disk per code version.
# --------------------------------------------------------------------------------------------

#: modules whose source determines the tabulated values (relative to the package)
_VALUE_SOURCES = ("kernels.py", "laws.py", "collision.py", "solvers", "tables.py")
_LOCK = threading.RLock()
_MEMORY: dict[tuple[str, str], Table | None] = {}
_KEY: str | None = None


def cache_dir() -> Path:
    """Where tables are cached: $VISCONTACT_CACHE_DIR, else the user's cache directory."""
    env = os.environ.get("VISCONTACT_CACHE_DIR")
    if env:
        return Path(env)
    import platformdirs

    return Path(platformdirs.user_cache_dir("viscontact"))


def code_key() -> str:
    """Hash of the package version and the source of every module that determines e."""
    global _KEY
    if _KEY is None:
        from . import __version__

        root = Path(__file__).resolve().parent
        h = hashlib.sha256(f"{__version__}/{_FORMAT}".encode())
        for name in _VALUE_SOURCES:
            path = root / name
            for f in sorted(path.glob("*.py")) if path.is_dir() else [path]:
                h.update(f.relative_to(root).as_posix().encode())
                h.update(f.read_bytes())
        _KEY = h.hexdigest()
    return _KEY


def table_path(law: str, end: str) -> Path:
    return cache_dir() / f"table-{law}-{end}-{code_key()[:20]}.npz"


def _load(law: str, end: str) -> Table | None:
    path = table_path(law, end)
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as d:
            return Table.from_arrays(law, end, d)
    except Exception as exc:  # a corrupt or foreign file is rebuilt, never trusted
        warnings.warn(f"viscontact: rebuilding unreadable table cache {path.name} ({exc})",
                      RuntimeWarning, stacklevel=3)
        return None


def _save(table: Table) -> None:
    """Write atomically (temporary file, then rename) and drop stale versions of this table."""
    path = table_path(table.law, table.end)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".tmp", delete=False) as fh:
            np.savez(fh, **table.to_arrays())
        os.replace(fh.name, path)
        for old in path.parent.glob(f"table-{table.law}-{table.end}-*.npz"):
            if old != path:
                old.unlink(missing_ok=True)
    except OSError as exc:  # a read-only cache still leaves the table usable in memory
        warnings.warn(f"viscontact: could not cache table in {path.parent} ({exc})",
                      RuntimeWarning, stacklevel=3)


def get_table(law: str, end: str) -> Table | None:
    """The table of ``law`` (registered name) for ``end``, loaded or built on first use.

    None for a law without a table, or when a build failed its verification (a warning
    says so; the exact solver then answers).
    """
    if law not in TABLE_LAWS:
        return None
    with _LOCK:
        if (law, end) not in _MEMORY:
            table = _load(law, end)
            if table is None:
                try:
                    table = _build(law, end)
                except RuntimeError as exc:
                    warnings.warn(f"viscontact: {exc}; the exact solver answers instead",
                                  RuntimeWarning, stacklevel=2)
                else:
                    _save(table)
            _MEMORY[law, end] = table
        return _MEMORY[law, end]


def clear_memory() -> None:
    """Forget the tables loaded in this process (the next use reads the disk cache again)."""
    global _KEY
    with _LOCK:
        _MEMORY.clear()
        _KEY = None


def build_all(rebuild: bool = False) -> dict[tuple[str, str], Table | None]:
    """Load or build every table (each law with a table, both ends); ``rebuild`` ignores the cache."""
    from .solvers import END_CRITERIA

    with _LOCK:
        if rebuild:
            for law in TABLE_LAWS:
                for end in END_CRITERIA:
                    table_path(law, end).unlink(missing_ok=True)
            clear_memory()
        return {(law, end): get_table(law, end) for law in TABLE_LAWS for end in END_CRITERIA}


# --------------------------------------------------------------------------------------------
# The one entry point of the public API (viscontact.calibration).
# --------------------------------------------------------------------------------------------


def through_tables(what: str, lp, x: np.ndarray, beta: np.ndarray | None, end: str,
                   exact: Callable[..., np.ndarray]) -> np.ndarray:
    """e(alpha) (``what="e"``) or alpha(e) (``what="alpha"``) through the law's table.

    ``x`` and ``beta`` are validated arrays of one shape; ``exact(lp, x, beta, end)`` (flat
    arrays) answers every element the table does not cover (no table for the law, table disabled
    or refused, alpha or beta beyond the table, e below its range).  Jian with beta = 0 is
    exactly KK and goes through the KK table.
    """
    flat = np.ascontiguousarray(x, dtype=float).ravel()
    b = None if beta is None else np.ascontiguousarray(np.broadcast_to(beta, x.shape)).ravel()
    table = get_table(lp.name, end) if enabled else None
    if table is None:
        return exact(lp, flat, b, end).reshape(x.shape)
    out = getattr(table, what)(flat, b)
    if b is not None:
        kk = b == 0.0
        if kk.any() and (kk_table := get_table("KK", end)) is not None:
            out[kk] = getattr(kk_table, what)(flat[kk])
    missing = np.isnan(out)
    if missing.any():
        out[missing] = exact(lp, flat[missing], None if b is None else b[missing], end)
    return out.reshape(x.shape)
