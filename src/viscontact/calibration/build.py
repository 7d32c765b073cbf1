"""Building a table from the exact solver, and verifying it.

Pieces are refined adaptively (halved in y) until the trailing Chebyshev coefficients fall
below ``_TAIL_TOL``; the finished table is checked against the exact solver on held-out random
points, piece boundaries and tiny alpha, and refused if any error exceeds ``VERIFY_TOL`` =
1e-10.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.polynomial import chebyshev as npcheb
from numpy.typing import ArrayLike

from .._support.progress import Progress
from ..physics.laws import lookup, resolve
from ._interp import _NODES_2D, CRIT, LOG, POWER, ZERO
from .table import ALPHA_TABLE_MAX, BETA_TABLE_MAX, VERIFY_TOL, Piece, Table, _axis, _axis_pieces

_NODES_1D = 24  # Chebyshev points per 1D piece
_TAIL_TOL = 1e-12  # accept a piece when its last coefficients are below this (|e| <= 1)
_TAIL_TERMS = 3
_MAX_ROUNDS = 12  # refinement rounds (each halves the pieces that fail)
_NODE_RTOL = 1e-14  # batch solver tolerance for the nodes (e to ~1e-14)
_CRIT_WIDTH = 0.1  # width in alpha of the CRIT piece below alpha_c


# --------------------------------------------------------------------------------------------
# Building from the exact solver.
# --------------------------------------------------------------------------------------------

Exact = Callable[[np.ndarray, np.ndarray | None], np.ndarray]


def exact_e(law: str, end: str, alpha: ArrayLike, beta: ArrayLike | None = None) -> np.ndarray:
    """e by the exact (batch) solver at the tables' node tolerance (|error| ~ 1e-14)."""
    from ..solvers.batch import solve_batch

    lp = resolve(law, beta=0.0 if lookup(law).needs_beta else None)
    return solve_batch(lp, alpha, end, beta=beta, rtol=_NODE_RTOL).e


class _Solver:
    """:func:`exact_e` for batches of points, counting them on a progress bar."""

    chunk = 4096  # solves per progress-bar update

    def __init__(self, law: str, end: str, bar: Progress) -> None:
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

    lp = resolve(law, beta=0.0 if lookup(law).needs_beta else None)
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
    """(table, largest held-out error) of e(alpha, beta); alpha pieces start from the table of
    the law it is at beta = 0 (KK for Jian)."""
    from .tables import get_table  # the cache builds through this module

    base = lookup(law).beta_zero
    kk = get_table(base, end) if base is not None else None
    if kk is None:
        raise RuntimeError(f"the {base} table is needed to lay out the {law} table")
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

    t0 = time.perf_counter()
    rng = np.random.default_rng(20190735)  # deterministic held-out points
    bar = Progress(None, unit="solve", delay=1.0, leave=False)  # no bar off a terminal
    bar.describe(f"viscontact: {law} table ({end} end)")
    try:
        exact = _Solver(law, end, bar)
        table, error = (_build_2d if lookup(law).needs_beta else _build_1d)(law, end, exact, rng)
    finally:
        bar.close()
    table.max_error, table.nodes = error, exact.count
    table.build_seconds = time.perf_counter() - t0
    if not table.max_error <= VERIFY_TOL:
        raise RuntimeError(f"{law} table ({end} end) misses the exact solver by "
                           f"{table.max_error:.2e} > {VERIFY_TOL:g}")
    return table
