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
by inverse quadratic interpolation in a dense sample of each piece (1D), or in a few samples
of the block's series in alpha at the point's beta (2D); it stops when the residual in e is
below 1e-13, or when a Taylor bound puts the residual after the last step below 1e-11 (one
evaluation fewer; the contract is 1e-9).  A 1D piece is evaluated only up to its last
coefficient that matters: the trailing ones it skips sum to at most 1e-13.

The 2D kernels (about 60 ns a point on one core, the inversion twice that) find the beta
piece and the alpha piece in O(1) (lookup grids; for the inversion, cells in e that leave
one candidate block, mostly), reduce the block to a series in alpha with fixed-size sums the
compiler vectorises, and take points through these stages in small batches, so that the
processor overlaps the latencies of several points.
"""

from __future__ import annotations

import hashlib
import math
import os
import sys
import tempfile
import threading
import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator

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
# The 2D kernels work on blocks of a fixed size: with the trip counts known when compiling,
# their sums run in vector registers.
_NA, _NB = _NODES_2D
assert _NA % 2 == 0 and _NB % 2 == 0 and _NB >= 4  # two partial sums; _basis writes T_0..T_3
_E_CELLS = 256  # cells in e of the 2D block search (:func:`_count_above`)
_SAMPLES_2D = 5  # evenly spaced samples of a reduced 2D block that start the Newton inversion
_LOOKUP_CELLS = 512  # most cells of a lookup index (:func:`_lookup`)
_BATCH = 32  # points the 2D kernels carry through each of their stages together

#: T_k at the samples of :func:`_sample`, [k, m] (a constant of the compiled code)
_T_AT_SAMPLES = np.ascontiguousarray(
    npcheb.chebvander(np.linspace(-1.0, 1.0, _SAMPLES_2D), _NA - 1).T)

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
    """sum_k c_k T_k(xi) by Clenshaw's recurrence (c_k - b_{k+2} is ready a step early:
    one fused multiply-add a step on the dependency chain)."""
    b1 = 0.0
    b2 = 0.0
    x2 = 2.0 * xi
    for k in range(c.shape[0] - 1, 0, -1):
        b1, b2 = x2 * b1 + (c[k] - b2), b1
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
        d1, d2 = x2 * d1 + (k * c[k] - d2), d1  # as in _cheb
        b1, b2 = x2 * b1 + (c[k] - b2), b1
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
def _guess(s, a: int, target: float) -> float:
    """xi where the inverse parabola through samples a, a + 1 and a neighbour of ``s`` (e at
    evenly spaced xi, s[a] >= target >= s[a + 1]) takes e = ``target``."""
    ns = s.shape[0]
    h = 2.0 / (ns - 1)
    x0 = -1.0 + a * h
    n3 = a + 2 if a + 2 < ns else a - 1
    return _inverse_quadratic(x0, s[a], x0 + h, s[a + 1], -1.0 + n3 * h, s[n3], target)


@_ijit
def _newton(c, target: float, xi: float) -> float:
    """One Newton step on sum c_k T_k(xi) = target."""
    f, df = _cheb_d(c, xi)
    return xi - (f - target) / df


@_ijit
def _finish(c, s, a: int, target: float, curvature: float, xi: float) -> float:
    """The second of the two Newton steps :func:`_solve_sampled` usually takes from
    :func:`_guess`, written out (no loop exit to mispredict); the rare point it leaves
    unfinished (residual above _INVERSE_TOL and Taylor bound above _STEP_TOL, or a step out
    of the bracket) goes to :func:`_solve_sampled`."""
    f, df = _cheb_d(c, xi)
    step = (f - target) / df
    new = xi - step
    x0 = -1.0 + a * (2.0 / (s.shape[0] - 1))
    if (x0 <= new <= x0 + 2.0 / (s.shape[0] - 1)
            and (abs(f - target) <= _INVERSE_TOL or 0.5 * curvature * step * step <= _STEP_TOL)):
        return new
    return _solve_sampled(c, s, a, target, curvature)


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
    """t[l] = T_l(xi) for l < _NB: T_0 to T_3 by the recurrence, then by doubling,
    T_{m+i} = 2 T_m T_i - T_{m-i} with T_m = 2 T_{m/2}^2 - 1 (m = 4, 8, ...): a chain of a
    few dependent steps where the recurrence has _NB."""
    t[0] = 1.0
    t[1] = xi
    t[2] = 2.0 * xi * xi - 1.0
    t[3] = 2.0 * xi * t[2] - xi
    m = 4
    while m < _NB:
        tm = 2.0 * t[m // 2] * t[m // 2] - 1.0
        t[m] = tm
        for i in range(1, min(m, _NB - m)):
            t[m + i] = 2.0 * tm * t[i] - t[m - i]
        m *= 2


@_ijit
def _find(breaks, lut, scale: float, x: float) -> int:
    """:func:`_locate` in O(1): ``lut[c]`` is the piece holding the left end of cell
    c = floor(x * scale) of an even grid (:func:`_lookup`), so x lies in that piece or a
    later one (several only where pieces are narrower than a cell)."""
    i = lut[min(int(x * scale), lut.shape[0] - 1)]
    while i > 0 and breaks[i] > x:  # a cell's end rounded past x
        i -= 1
    last = breaks.shape[0] - 2
    while i < last and breaks[i + 1] <= x:
        i += 1
    return i


@_ijit
def _reduce(ct, tb, r):
    """r[k] = sum_l ct[l, k] tb[l]: a 2D block (stored transposed, beta index first) reduced
    to a Chebyshev series in alpha.  Each sum is kept in scalars (two, for two shorter
    dependency chains) and stored once, and the fixed trip counts let the compiler run the
    _NA sums in vector registers (an output updated in memory is reloaded on every term)."""
    for k in range(_NA):
        a0 = 0.0
        a1 = 0.0
        for l in range(0, _NB, 2):
            a0 += ct[l, k] * tb[l]
            a1 += ct[l + 1, k] * tb[l + 1]
        r[k] = a0 + a1


@_ijit
def _row(rows, j: int):
    """(first piece, number of pieces) of beta row j on the concatenated alpha axis."""
    return rows[j], rows[j + 1] - rows[j]


@_ijit
def _place2(ax, rows, bx, blut, bscale, alut, ascale, a: float, b: float, tb):
    """(block g, xi of a in it) of the point (a, b), ``tb`` the beta basis at b; g = -1
    outside the table (one return, as in :func:`_block2`)."""
    inside = 0.0 <= b <= bx[0][-1]
    y = b if inside else 0.0
    j = _find(bx[0], blut, bscale, y)
    g0, n = _row(rows, j)
    brk = ax[0][g0 + j:g0 + j + n + 1]  # this row's alpha breaks
    inside = inside and 0.0 <= a <= brk[n]
    x = a if inside else 0.0
    g = g0 + _find(brk, alut[j], ascale[j], x)
    _basis(_to_unit(y, bx[1][j], bx[2][j], bx[3][j], bx[4][j], bx[5][j]), tb)
    return g if inside else -1, _to_unit(x, ax[1][g], ax[2][g], ax[3][g], ax[4][g], ax[5][g])


@_ijit
def _count_above(left, cells, g0: int, tb, e: float) -> int:
    """How many blocks of a row start (left end, beta series ``left[g0 + i]``) at
    e_table >= e.  ``cells[c]`` = (certain, possible) for the e cell c = floor(e * _E_CELLS):
    the first ``certain`` blocks start above every e of the cell at every beta of the row,
    blocks from ``possible`` on below every one; only those between (one, mostly) are
    summed."""
    c = cells[min(max(int(e * _E_CELLS), 0), _E_CELLS - 1)]  # NaN or e <= 0: the first cell
    above = c[0]
    for i in range(c[0], c[1]):
        a0 = 0.0
        a1 = 0.0
        ci = left[g0 + i]
        for l in range(0, _NB, 2):
            a0 += ci[l] * tb[l]
            a1 += ci[l + 1] * tb[l + 1]
        above += a0 + a1 >= e
    return above


@_ijit
def _sample(r, s, e: float) -> int:
    """s[m] = the series r at the evenly spaced xi of :data:`_T_AT_SAMPLES`; returns a with
    s[a] >= e > s[a + 1] (counted over the interior samples, without a branch)."""
    a = 0
    for m in range(_SAMPLES_2D):
        a0 = 0.0
        a1 = 0.0
        for k in range(0, _NA, 2):
            a0 += _T_AT_SAMPLES[k, m] * r[k]
            a1 += _T_AT_SAMPLES[k + 1, m] * r[k + 1]
        s[m] = a0 + a1
    for m in range(1, _SAMPLES_2D - 1):
        a += s[m] >= e
    return a


@_ijit
def _block2(ax, rows, bx, blut, bscale, left, cells, e: float, b: float, tb):
    """First stage of the inversion alpha(e, b): (block g, row j, answer); g = -1 when the
    answer is final (NaN outside the table, 0 above its e range), else ``tb`` holds the
    beta basis at b.  ``left`` and ``cells`` (:func:`_count_above`) find the block without
    reducing every block of the row.  One return at the end: early ones made the compiled
    stage twice as slow."""
    inside = 0.0 <= b <= bx[0][-1]
    x = b if inside else 0.0
    j = _find(bx[0], blut, bscale, x)
    g0 = rows[j]
    _basis(_to_unit(x, bx[1][j], bx[2][j], bx[3][j], bx[4][j], bx[5][j]), tb)
    above = _count_above(left, cells[j], g0, tb, e)
    g = g0 + above - 1
    answer = math.nan
    if not inside:
        g = -1
    elif e >= 1.0 or above == 0:  # e = 1 only without damping
        g = -1
        answer = 0.0
    return g, j, answer


@_ijit
def _curvature_bound(r) -> float:
    """sum_k |r_k| max |T_k''| >= max |e''| on [-1, 1] (|T_k''| <= k^2 (k^2 - 1) / 3)."""
    bound = 0.0
    for k in range(2, r.shape[0]):
        bound += abs(r[k]) * (k * k * (k * k - 1.0) / 3.0)
    return bound


@_pjit
def _invert2_many(ax, rows, bx, blut, bscale, ct, left, cells, e, b, out, chunks):
    """out = alpha(e, b), alpha with e_table(alpha, b) = e (NaN outside the table), over the
    arrays in parallel chunks.

    A chunk takes its points through the stages in batches of _BATCH: find the block
    (:func:`_block2`), reduce it to a series in alpha and sample it along the block
    (:func:`_sample`), the inverse-parabola guess and a Newton step, the second step
    (:func:`_finish`).  Each stage is a short dependency chain, independent from point to
    point, so the processor overlaps several points; carried through every stage one at a
    time, a point is a single long chain and the processor mostly waits.
    """
    n = e.shape[0]
    size = (n + chunks - 1) // chunks
    for ch in numba.prange(chunks):
        tb = np.empty((_BATCH, _NB))
        r = np.empty((_BATCH, _NA))
        s = np.empty((_BATCH, _SAMPLES_2D))
        blk = np.empty(_BATCH, dtype=np.int64)
        row = np.empty(_BATCH, dtype=np.int64)
        bracket = np.empty(_BATCH, dtype=np.int64)
        xi = np.empty(_BATCH)
        stop = min(n, (ch + 1) * size)
        for first in range(ch * size, stop, _BATCH):
            m = min(_BATCH, stop - first)
            for p in range(m):
                blk[p], row[p], out[first + p] = _block2(ax, rows, bx, blut, bscale, left, cells,
                                                         e[first + p], b[first + p], tb[p])
            for p in range(m):  # short: the blocks of several points load at once
                if blk[p] >= 0:
                    _reduce(ct[blk[p]], tb[p], r[p])
            for p in range(m):
                g = blk[p]
                if g >= 0:
                    target = e[first + p]
                    bracket[p] = _sample(r[p], s[p], target)
                    if target < s[p, _SAMPLES_2D - 1]:  # between two pieces (they agree to
                        j = row[p]  # ~1e-12) or below the table
                        out[first + p] = ax[0][g + j + 1] if g + 1 < rows[j + 1] else math.nan
                        blk[p] = -1
                    else:
                        xi[p] = _guess(s[p], bracket[p], target)
            for p in range(m):
                if blk[p] >= 0:
                    xi[p] = _newton(r[p], e[first + p], xi[p])
            for p in range(m):
                g = blk[p]
                if g >= 0:
                    x = _finish(r[p], s[p], bracket[p], e[first + p], _curvature_bound(r[p]),
                                xi[p])
                    out[first + p] = _from_unit(x, ax[1][g], ax[2][g], ax[3][g], ax[4][g],
                                                ax[5][g])


@_pjit
def _eval2_many(ax, rows, bx, blut, bscale, alut, ascale, ct, a, b, out, chunks):
    """out = e_table(a, b) over the arrays (NaN outside the table), in parallel chunks, in
    batches taken through the stages together as in :func:`_invert2_many`: place the point
    (:func:`_place2`), reduce its block (:func:`_reduce`), sum the series."""
    n = a.shape[0]
    size = (n + chunks - 1) // chunks
    for ch in numba.prange(chunks):
        tb = np.empty((_BATCH, _NB))
        r = np.empty((_BATCH, _NA))
        blk = np.empty(_BATCH, dtype=np.int64)
        xi = np.empty(_BATCH)
        stop = min(n, (ch + 1) * size)
        for first in range(ch * size, stop, _BATCH):
            m = min(_BATCH, stop - first)
            for p in range(m):
                blk[p], xi[p] = _place2(ax, rows, bx, blut, bscale, alut, ascale, a[first + p],
                                        b[first + p], tb[p])
            for p in range(m):
                if blk[p] >= 0:
                    _reduce(ct[blk[p]], tb[p], r[p])
            for p in range(m):
                out[first + p] = _cheb(r[p], xi[p]) if blk[p] >= 0 else math.nan


# --------------------------------------------------------------------------------------------
# Tables: data, evaluation, inversion.
# --------------------------------------------------------------------------------------------

def _chunks() -> int:
    """Work items of the 2D drivers (:func:`_eval2_many`, :func:`_invert2_many`)."""
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


def _lookup(breaks: np.ndarray, cells: int, fixed: bool = False) -> tuple[np.ndarray, float]:
    """(lut, scale) of :func:`_find` over [0, breaks[-1]]: ``lut[c]`` is the piece holding
    x = c / scale.  ``cells`` of them (``fixed``), else as many as the narrowest piece asks
    for, up to ``cells``."""
    span = float(breaks[-1])
    if not fixed:
        cells = int(min(cells, max(1, math.ceil(span / np.min(np.diff(breaks))))))
    scale = cells / span
    lut = np.searchsorted(breaks[1:-1], np.arange(cells) / scale, side="right")
    return lut.astype(np.int32), scale


def _block_cells(left: np.ndarray) -> np.ndarray:
    """(certain, possible) of :func:`_count_above` for every e cell of one row, whose blocks'
    left ends have the beta series ``left`` (blocks, _NB): the e range of each left end over
    the row, from 1025 samples widened by the most the series can change between two."""
    xb = np.linspace(-1.0, 1.0, 1025)
    values = npcheb.chebval(xb, left.T)  # (blocks, samples)
    slack = np.abs(left) @ np.arange(_NB) ** 2 * (xb[1] - xb[0]) + 1e-12  # |T_l'| <= l^2
    low = np.minimum.accumulate(values.min(axis=1) - slack)  # decreasing along the row, as e
    high = np.maximum.accumulate((values.max(axis=1) + slack)[::-1])[::-1]
    edges = np.arange(_E_CELLS + 1) / _E_CELLS
    certain = np.count_nonzero(low[:, None] >= edges[None, 1:], axis=0)
    possible = np.count_nonzero(high[:, None] >= edges[None, :-1], axis=0)
    return np.stack([certain, np.maximum(possible, certain)], axis=1).astype(np.int64)


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
        else:
            # beta series of e at the left end of every alpha piece
            left = np.einsum("k,gkl->gl", (-1.0) ** np.arange(self.coef.shape[1]), self.coef)
            self._ct = np.ascontiguousarray(self.coef.transpose(0, 2, 1))  # for _reduce
            counts = np.diff(self.rows)
            self._left = np.ascontiguousarray(left)
            self._cells = np.array([_block_cells(left[g0:g0 + n]) for g0, n in zip(self.rows, counts)])
            self._beta_lookup = _lookup(self.beta_axis[0], _LOOKUP_CELLS)
            rows = [_lookup(self.alpha_axis[0][g0 + j:g0 + j + n + 1], _LOOKUP_CELLS, fixed=True)
                    for j, (g0, n) in enumerate(zip(self.rows, counts))]
            self._alpha_lookup = (np.array([lut for lut, _ in rows]),
                                  np.array([scale for _, scale in rows]))

    def _kernel_e2(self) -> tuple:
        return (self.alpha_axis, self.rows, self.beta_axis, *self._beta_lookup,
                *self._alpha_lookup, self._ct)

    def _kernel_alpha2(self) -> tuple:
        return (self.alpha_axis, self.rows, self.beta_axis, *self._beta_lookup, self._ct,
                self._left, self._cells)

    def e(self, alpha: np.ndarray, beta: np.ndarray | None = None) -> np.ndarray:
        """e at each alpha (and beta); NaN where the point lies outside the table."""
        a = np.ascontiguousarray(alpha, dtype=float).ravel()
        out = np.empty(a.shape)
        if self.beta_axis is None:
            _eval1_many(*self.alpha_axis, self.coef, self._deg, a, out)
        else:
            b = np.ascontiguousarray(beta, dtype=float).ravel()
            _eval2_many(*self._kernel_e2(), a, b, out, _chunks())
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
            _invert2_many(*self._kernel_alpha2(), t, b, out, _chunks())
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
              and (coef.ndim == 2 if rows is None else coef.shape[1:] == _NODES_2D))
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


@contextmanager
def _build_lock(law: str, end: str) -> Iterator[None]:
    """Hold an exclusive lock on this table's cache entry across processes (POSIX flock), so
    that processes sharing a cache directory (parallel test workers, a tool and its
    subprocesses) build a missing table once; without a writable cache (or flock) no lock."""
    try:
        import fcntl

        cache_dir().mkdir(parents=True, exist_ok=True)
        fh = open(cache_dir() / f".table-{law}-{end}.lock", "w")
    except (ImportError, OSError):
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def get_table(law: str, end: str) -> Table | None:
    """The table of ``law`` (registered name) for ``end``, loaded or built on first use.

    None for a law without a table, or when a build failed its verification (a warning
    says so; the exact solver then answers).
    """
    if law not in TABLE_LAWS:
        return None
    with _LOCK:
        if (law, end) not in _MEMORY:
            missing = not table_path(law, end).exists()
            table = _load(law, end)
            if table is None:
                with _build_lock(law, end):
                    if missing:  # built by another process while this one waited?
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
