"""A table of e(alpha) (or e(alpha, beta) for Jian): Chebyshev pieces over the alpha (and beta)
axis, each in its own variable y (see :mod:`viscontact.calibration.tables`), evaluated and
inverted by the compiled kernels of :mod:`._interp`; saved to and loaded from ``.npz`` files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import chebyshev as npcheb

from .._support.locks import compile_once
from ..physics.laws import LAWS
from ._interp import (
    _E_CELLS, _LOOKUP_CELLS, _NB, _NODES_2D, _chunks, _eval1_many, _eval2_many, _from_unit,
    _invert1_many, _invert2_many,
)

_INVERSE_SAMPLES = 256  # dense samples per piece that start the Newton inversion
_TRUNC_TOL = 1e-13  # coefficients cut from a piece's end may change e by at most this
_FORMAT = 2  # bump when the file layout changes


#: alpha (and beta, Jian) range the tables cover; outside it the exact solver answers.
ALPHA_TABLE_MAX = 10.0
BETA_TABLE_MAX = 10.0
#: largest |e_table - e_exact| a table may show on its held-out points.
VERIFY_TOL = 1e-10
#: laws with a table (the general power law has a free exponent: no table).
TABLE_LAWS: tuple[str, ...] = tuple(name for name, law in LAWS.items() if law.p is not None)

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


def _run(driver, *args) -> None:
    """Call a compiled driver of :mod:`._interp`, compiled first once for the processes that
    start together (:func:`viscontact._support.locks.compile_once`: up to ~10 CPU-s each for
    the parallel 2D ones)."""
    compile_once(driver, args)
    driver(*args)


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
            _run(_eval1_many, *self.alpha_axis, self.coef, self._deg, a, out)
        else:
            b = np.ascontiguousarray(beta, dtype=float).ravel()
            _run(_eval2_many, *self._kernel_e2(), a, b, out, _chunks())
        return out.reshape(np.shape(alpha))

    def alpha(self, e: np.ndarray, beta: np.ndarray | None = None) -> np.ndarray:
        """alpha with e_table(alpha) = e for each e in (0, 1]; NaN where the table does not reach."""
        t = np.ascontiguousarray(e, dtype=float).ravel()
        out = np.empty(t.shape)
        if self.beta_axis is None:
            _run(_invert1_many, *self.alpha_axis, self.coef, self._deg, self._inv,
                 self._curvature, t, out)
        else:
            b = np.ascontiguousarray(beta, dtype=float).ravel()
            _run(_invert2_many, *self._kernel_alpha2(), t, b, out, _chunks())
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
