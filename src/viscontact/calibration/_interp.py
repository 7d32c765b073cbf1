"""The compiled arithmetic of the e(alpha) tables: piece maps, Clenshaw sums, location and the
parallel drivers of evaluation and inversion (numba).

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

import math

import numba
import numpy as np
from numpy.polynomial import chebyshev as npcheb

POWER, LOG, CRIT, ZERO = 0, 1, 2, 3
_NODES_2D = (16, 16)  # per 2D piece, (alpha, beta)
_INVERSE_TOL = 1e-13  # |e_table(alpha) - e| at which the inversion stops (contract: 1e-9)
#: bound on |e_table(alpha) - e| after a Newton step at which the inversion stops without
#: evaluating again (a bound, not a residual; still 100 times below the 1e-9 contract)
_STEP_TOL = 1e-11
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


def _chunks() -> int:
    """Work items of the 2D drivers (:func:`_eval2_many`, :func:`_invert2_many`)."""
    return 8 * numba.get_num_threads()
