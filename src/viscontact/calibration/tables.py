"""Precomputed interpolation tables of e(alpha) (and e(alpha, beta) for Jian), built from the exact solver.

A table is a set of Chebyshev pieces over alpha in [0, ALPHA_TABLE_MAX].  Each piece lives in
its own variable y, chosen so that e is analytic (or at least very smooth) in y:

- ``POWER`` y = alpha^(1/k) on [0, 1].  Under the zero-force end the contact stops where
  s^k + alpha g v = 0 (x = s^m, k = m (3/2 - p), see :mod:`viscontact.physics.kernels`), so the end
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

Pieces are refined and verified by :mod:`.build` (refused if any held-out error exceeds
``VERIFY_TOL`` = 1e-10); their compiled evaluation and inversion are in :mod:`._interp`, the
table itself in :mod:`.table`.  This module keeps them: in memory per process and on disk (see
:func:`cache_dir`) under a key that hashes the source of every module that determines the
values, so a code change rebuilds them; and it is the one entry point of the calibration
(:func:`through_tables`).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import threading
import warnings
from collections.abc import Callable
from contextlib import AbstractContextManager
from pathlib import Path

import numpy as np

from .._support.locks import file_lock
from ..physics.laws import lookup
from .build import _build, exact_e
from .table import (
    _FORMAT, ALPHA_TABLE_MAX, BETA_TABLE_MAX, TABLE_LAWS, VERIFY_TOL, Table,
)


__all__ = [
    "ALPHA_TABLE_MAX", "BETA_TABLE_MAX", "VERIFY_TOL", "TABLE_LAWS", "Table", "build_all",
    "cache_dir", "clear_memory", "code_key", "enabled", "exact_e", "get_table", "table_path",
    "through_tables",
]

#: switch the tables off (every call goes to the exact solver); tests compare both paths.
enabled: bool = True

# --------------------------------------------------------------------------------------------
# Cache: in memory per process, on disk per code version.
# --------------------------------------------------------------------------------------------

#: modules whose source determines the tabulated values (relative to the package root)
_VALUE_SOURCES = ("physics/kernels.py", "physics/laws.py", "collision/single.py", "solvers",
                  "calibration/_interp.py", "calibration/table.py", "calibration/build.py")
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
        from .._version import __version__

        root = Path(__file__).resolve().parent.parent
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


def _build_lock(law: str, end: str) -> AbstractContextManager[None]:
    """Hold an exclusive lock on this table's cache entry across processes (POSIX flock), so
    that processes sharing a cache directory (parallel test workers, a tool and its
    subprocesses) build a missing table once; without a writable cache (or flock) no lock."""
    return file_lock(cache_dir() / f".table-{law}-{end}.lock")


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
    from ..solvers import END_CRITERIA

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
        if kk.any() and (kk_table := get_table(lookup(lp.name).beta_zero, end)) is not None:
            out[kk] = getattr(kk_table, what)(flat[kk])
    missing = np.isnan(out)
    if missing.any():
        out[missing] = exact(lp, flat[missing], None if b is None else b[missing], end)
    return out.reshape(x.shape)
